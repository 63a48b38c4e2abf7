//! Gravity coupling: an air force linear in gravity as seen from the body,
//! a model extension outside eqs. (5)-(6).
//!
//! Two effects of the air on a light body depend on the body's attitude to
//! gravity rather than on its motion through the air:
//! * buoyancy, `-ρ V g` for a displaced volume V;
//! * added mass. With an added-mass matrix `M_a` (body frame) the body
//!   obeys `(M + M_a) a = M g + F_air`, so the force that eq. (9) recovers,
//!   `M a - M g = M(M + M_a)⁻¹ F_air - M(M + M_a)⁻¹ M_a g`, is the air force
//!   seen through a constant matrix (which C_F and the spin coupling absorb:
//!   they are fitted per direction) plus a term linear in `Rᵀg`.
//!
//! Both are covered, with a non-dimensional 3x3 matrix G, by
//!
//! `F = ρ L³ G Rᵀg` (body frame, N; `Rᵀg` the gravity vector in the body
//! frame, m/s²; L the reference length, m).
//!
//! Pure buoyancy of volume V is `G = -(V/L³) I` ([`GravityCoupling::buoyancy`]).
//!
//! Stored as extension [`GRAVITY_COUPLING`](crate::extension::extension_kind::GRAVITY_COUPLING),
//! payload version 1: `G_ij` row-major, each an `f32`, little-endian (36
//! bytes). It needs the body's attitude, so
//! [`crate::Coefficients::wrench_in_gravity`] adds it, not
//! [`crate::Coefficients::wrench`] (which sees only V and Ω).

use crate::error::ModelError;
use crate::extension::{extension_kind, Extension};
use crate::math::Real;
use nalgebra::{Matrix3, Vector3};

/// Payload version written and understood by this build.
pub const PAYLOAD_VERSION: u8 = 1;
/// Number of matrix entries.
pub const TERMS: usize = 9;

/// The matrix G of the gravity-coupling force (non-dimensional).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GravityCoupling<T: Real> {
    /// `G`, body frame.
    pub g: Matrix3<T>,
}

impl<T: Real> GravityCoupling<T> {
    /// Buoyancy of a displaced volume `volume` (m³) for reference length
    /// `reference_length` (m): `G = -(V/L³) I`.
    pub fn buoyancy(volume: T, reference_length: T) -> Self {
        let l3 = reference_length * reference_length * reference_length;
        Self {
            g: Matrix3::identity() * (-volume / l3),
        }
    }

    /// The displaced volume, m³, whose buoyancy is the isotropic part of
    /// G, for reference length `reference_length` L (m): `V = -L³ tr(G)/3`,
    /// the inverse of [`Self::buoyancy`] (`G = -(V/L³) I`). Added mass
    /// shows in the anisotropic part and is not counted.
    pub fn buoyancy_volume(&self, reference_length: T) -> T {
        let l = reference_length;
        -self.g.trace() / T::of_f64(3.0) * (l * l * l)
    }

    /// The force, body frame, N: `ρ L³ G g_body`, with `gravity_body` the
    /// gravity vector in the body frame (`Rᵀg`, m/s²), `air_density` ρ
    /// (kg/m³) and `reference_length` L (m).
    pub fn force(
        &self,
        gravity_body: &Vector3<T>,
        air_density: T,
        reference_length: T,
    ) -> Vector3<T> {
        let l = reference_length;
        self.g * gravity_body * (air_density * l * l * l)
    }

    /// The model extension holding this matrix (payload version 1).
    pub fn to_extension(&self) -> Result<Extension, ModelError> {
        crate::payload::encode(
            extension_kind::GRAVITY_COUPLING,
            PAYLOAD_VERSION,
            self.g.transpose().iter().copied(),
            "gravity_coupling",
        )
    }

    /// The matrix of an extension: `Ok(None)` for another kind or an
    /// unknown payload version (kept, not evaluated); an error for a
    /// payload of the wrong size or with a non-finite number.
    pub fn from_extension(e: &Extension) -> Result<Option<Self>, ModelError> {
        let values: Option<[T; TERMS]> = crate::payload::decode(
            e,
            extension_kind::GRAVITY_COUPLING,
            PAYLOAD_VERSION,
            "gravity_coupling",
            "gravity_coupling payload",
        )?;
        Ok(values.map(|v| Self {
            g: Matrix3::from_row_slice(&v),
        }))
    }
}
