//! Model extensions: terms outside eqs. (5)-(6), stored as tagged,
//! versioned byte payloads so that a reader that does not know a kind still
//! loads the file and keeps the term. The kinds this build evaluates decode
//! their payloads themselves ([`crate::spin_coupling`],
//! [`crate::gravity_coupling`]).

/// Most model extensions in one model.
pub const MAX_EXTENSIONS: usize = 9;
/// Largest extension payload, in bytes.
pub const EXTENSION_CAPACITY: usize = 112;

/// Kinds of model extension known to this version. Unknown kinds found in
/// a file are kept (and written back) but not evaluated.
pub mod extension_kind {
    /// Added mass ([`crate::effect::EffectKind::AddedMass`]).
    pub const ADDED_MASS: u16 = 1;
    /// Buoyancy of displaced air ([`crate::effect::EffectKind::Buoyancy`]).
    pub const BUOYANCY: u16 = 2;
    /// A force bilinear in Ω and V ([`crate::spin_coupling`]).
    pub const SPIN_COUPLING: u16 = 3;
    /// A force linear in gravity seen from the body: buoyancy and added
    /// mass ([`crate::gravity_coupling`]).
    pub const GRAVITY_COUPLING: u16 = 4;
    /// Rotational lift ([`crate::effect::EffectKind::RotationalLift`]).
    pub const ROTATIONAL_LIFT: u16 = 5;
    /// Propeller thrust ([`crate::effect::EffectKind::PropellerThrust`]).
    pub const PROPELLER_THRUST: u16 = 6;
    /// Linear (viscous) drag ([`crate::effect::EffectKind::LinearDrag`]).
    pub const LINEAR_DRAG: u16 = 7;
    /// Added mass's velocity terms without its acceleration reaction
    /// ([`crate::effect::EffectKind::AddedMassCoupling`]).
    pub const ADDED_MASS_COUPLING: u16 = 8;
}

/// A model extension: a term outside eqs. (5)-(6), stored as a tagged,
/// versioned byte payload so that readers that do not know a kind can still
/// load the file and keep the term.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Extension {
    /// See [`extension_kind`].
    pub kind: u16,
    /// Version of this kind's payload layout.
    pub version: u8,
    /// The payload (postcard of the kind's parameters).
    pub data: heapless::Vec<u8, EXTENSION_CAPACITY>,
}
