//! KiteShop statics and stability (paper §7), allocation-free.
//!
//! A kite is a set of primitives `p` (a box, a plate, or any fitted object),
//! each with its own OmniAD [`Coefficients`], rotated by `Q_p` (primitive
//! frame -> kite body frame) and translated by `Y_p` (m, from the kite's
//! centre of mass, body frame). The kite's orientation is `R` (body ->
//! world).
//!
//! * [`statics`]: force and torque on the kite, eqs. (14)-(15); string
//!   tension from linear equilibrium; the unbalanced torque; the condition
//!   `f_string · g > 0`; the optimal attachment line, eq. (16).
//! * [`stability`]: the Jacobian `∂T_kite/∂Θ` (`R' = R exp[Θ]ₓ`), its
//!   symmetric part and eigen-decomposition, a verdict per axis.
//! * [`trim`]: beyond the paper, the orientation at which the unbalanced
//!   torque vanishes for a fixed attachment point.
//!
//! World frame: z up; the wind and gravity are given by [`Conditions`].

pub mod stability;
pub mod statics;
pub mod trim;

use crate::coefficients::Coefficients;
use crate::lanes::LaneScalar;
use crate::math::Real;
use nalgebra::{Matrix3, Vector3};

/// One primitive of a kite (Fig. 10-right).
#[derive(Clone, Copy, Debug)]
pub struct Primitive<'a, T: LaneScalar> {
    /// The primitive's OmniAD coefficients (its own reference length L).
    pub coefficients: &'a Coefficients<T>,
    /// `Q_p`: primitive frame -> kite body frame (a rotation matrix).
    pub rotation: Matrix3<T>,
    /// `Y_p`: the primitive's origin relative to the kite's centre of mass,
    /// kite body frame, m.
    pub offset: Vector3<T>,
}

/// A kite: its primitives and its total mass.
#[derive(Clone, Copy, Debug)]
pub struct Kite<'a, T: LaneScalar> {
    /// The primitives `P`.
    pub primitives: &'a [Primitive<'a, T>],
    /// Total mass M (frame, covering, sockets, objects), kg.
    pub mass: T,
}

/// The air and gravity the kite is analysed in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions<T: Real> {
    /// Wind velocity `v_wind`, world frame, m/s.
    pub wind: Vector3<T>,
    /// Gravity `g`, world frame, m/s².
    pub gravity: Vector3<T>,
    /// Air density ρ, kg/m³.
    pub air_density: T,
}

impl<T: Real> Conditions<T> {
    /// Wind of `speed` m/s along world +x, g = 9.81 m/s² along -z,
    /// ρ = 1.2 kg/m³ (the paper's values).
    pub fn standard(speed: T) -> Self {
        Self {
            wind: Vector3::new(speed, T::zero(), T::zero()),
            gravity: Vector3::new(T::zero(), T::zero(), T::of_f64(-9.81)),
            air_density: T::of_f64(1.2),
        }
    }
}

/// Why a kite cannot be analysed. Small and `Copy`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KiteError {
    /// A number is NaN or infinite; names the quantity.
    NonFinite(&'static str),
    /// The string tension is zero, so the attachment line (eq. 16) and
    /// the string direction are undefined.
    NoTension,
    /// The kite has no primitives.
    NoPrimitives,
    /// The symmetric eigen-decomposition did not converge.
    EigenFailed,
}

impl core::fmt::Display for KiteError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFinite(what) => write!(f, "non-finite number in {what}"),
            Self::NoTension => write!(f, "string tension is zero: no string direction"),
            Self::NoPrimitives => write!(f, "the kite has no primitives"),
            Self::EigenFailed => write!(f, "symmetric eigen-decomposition did not converge"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for KiteError {}

/// `[a]ₓ`: the skew matrix with `[a]ₓ b = a × b`.
pub fn skew<T: Real>(a: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -a.z, a.y, a.z, z, -a.x, -a.y, a.x, z)
}
