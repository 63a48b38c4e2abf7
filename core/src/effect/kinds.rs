//! The effect kinds: names, parameter counts, file tags, and the formula
//! and source of each (the one place they are written down).

use crate::extension::extension_kind;

/// Most parameters of one effect (the propeller tensor's 9).
pub const MAX_PARAMS: usize = 9;

/// A named effect. Frames: body; `V` the velocity relative to the air,
/// `Ω` the angular velocity, `g_b = Rᵀg` gravity seen from the body, ρ air
/// density, L the reference length (eq. 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    /// `added_mass`: Kirchhoff's added mass of potential flow (Lamb,
    /// *Hydrodynamics* §124-126; Weißmann & Pinkall 2012). Parameters: the
    /// symmetric positive semi-definite M_a, kg, `[xx, yy, zz, xy, xz, yz]`.
    /// Force `-M_a dV/dt - Ω × (M_a V)`, Munk moment `-V × (M_a V)`.
    AddedMass,
    /// `added_mass_coupling`: the velocity terms of Kirchhoff's added mass
    /// alone — force `-Ω × (M_a V)`, Munk moment `-V × (M_a V)` — without
    /// the acceleration reaction `-M_a dV/dt` (Lamb §126 with `dV/dt`
    /// dropped). No real air lacks the acceleration reaction; a stateless
    /// fluid model does: MuJoCo's ellipsoid model evaluates its added mass
    /// without accelerations (`mj_addedMassForces` called with none, "disabled
    /// due to dependency on qacc"; mujoco.readthedocs.io, Fluid forces),
    /// so its air pulls and turns a body as an added mass would while never
    /// resisting its acceleration. Parameters as [`Self::AddedMass`]'s. Its
    /// isotropic part `m I` is the force `m (V × Ω)`, a rotational lift of
    /// `c = -m / (ρL³)`: no force or torque tells the two apart.
    AddedMassCoupling,
    /// `rotational_lift`: lift from circulation bound by rotation (Magnus;
    /// Kutta-Joukowski with Γ ∝ Ω L², Batchelor 2000 §6.6), force
    /// `ρ L³ c (Ω × V)`. Parameter c (dimensionless).
    RotationalLift,
    /// `propeller_thrust`: the angular-velocity force F_Ω of eq. (4) that
    /// §4.1 drops, with D_F linear in the spin direction:
    /// `½ρ L⁴ |Ω| K Ω`. Parameters: K (dimensionless 3x3, row-major).
    PropellerThrust,
    /// `buoyancy`: Archimedes' force of the displaced air, `-ρ V_b g_b`.
    /// Parameter V_b, m³ (0 <= V_b <= the bounding box's volume).
    Buoyancy,
    /// `linear_drag`: viscous (Stokes-like) drag at low Reynolds number,
    /// `-k μ L V` with μ = [`super::AIR_VISCOSITY`] (Stokes' sphere:
    /// k = 3π with L the diameter). Parameter k (dimensionless).
    LinearDrag,
}

impl EffectKind {
    /// Every kind, in a fixed order.
    pub const ALL: [EffectKind; 6] = [
        Self::AddedMass,
        Self::AddedMassCoupling,
        Self::RotationalLift,
        Self::PropellerThrust,
        Self::Buoyancy,
        Self::LinearDrag,
    ];

    /// Number of parameters.
    pub const fn param_count(self) -> usize {
        match self {
            Self::AddedMass | Self::AddedMassCoupling => 6,
            Self::PropellerThrust => 9,
            Self::RotationalLift | Self::Buoyancy | Self::LinearDrag => 1,
        }
    }

    /// The name used on the command line, in reports and JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Self::AddedMass => "added_mass",
            Self::AddedMassCoupling => "added_mass_coupling",
            Self::RotationalLift => "rotational_lift",
            Self::PropellerThrust => "propeller_thrust",
            Self::Buoyancy => "buoyancy",
            Self::LinearDrag => "linear_drag",
        }
    }

    /// The kind named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The tag of its extension payload in `.omni` files.
    pub const fn extension_kind(self) -> u16 {
        match self {
            Self::AddedMass => extension_kind::ADDED_MASS,
            Self::AddedMassCoupling => extension_kind::ADDED_MASS_COUPLING,
            Self::Buoyancy => extension_kind::BUOYANCY,
            Self::RotationalLift => extension_kind::ROTATIONAL_LIFT,
            Self::PropellerThrust => extension_kind::PROPELLER_THRUST,
            Self::LinearDrag => extension_kind::LINEAR_DRAG,
        }
    }

    /// The kind of an extension tag, if it is a named effect.
    pub fn from_extension_kind(tag: u16) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.extension_kind() == tag)
    }

    /// Whether it changes the equations of motion (not only the force):
    /// the reconstruction must carry it in its process model.
    pub const fn changes_motion(self) -> bool {
        matches!(self, Self::AddedMass)
    }
}
