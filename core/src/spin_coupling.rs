//! Spin coupling: an air force bilinear in the angular velocity Ω and the
//! air velocity V, a model extension outside eqs. (5)-(6).
//!
//! Eq. (5) makes the force a function of V alone (`½ρ|V|²L² C_F(E)`) and
//! eq. (6)'s damping makes the torque depend on Ω; neither lets a spinning
//! body feel a force across its flight path. Two well-known effects do
//! exactly that, both bilinear in Ω and V: the Magnus force (`∝ Ω × V`) and
//! the gyroscopic part of added mass (`(M_a V) × Ω`, Kirchhoff's equations).
//! This extension covers both, and any other bilinear term, with a
//! non-dimensional 3x3x3 tensor K:
//!
//! `F_i = ½ρ L³ Σ_jk K_ijk Ω_j V_k` (body frame, N; Ω in rad/s, V in m/s,
//! L the reference length in m).
//!
//! With the spin ratio `s = |Ω|L/|V|` this is `½ρ|V|²L² · s · K(Ω̂, E)`, the
//! form of eq. (5) scaled by the spin ratio. A pure Magnus term of scale
//! `c` is `K_ijk = c ε_ijk` ([`SpinCoupling::magnus`]).
//!
//! Stored as extension [`SPIN_COUPLING`](crate::extension::extension_kind::SPIN_COUPLING),
//! payload version 1: the 27 numbers `K_ijk` in the order i, j, k
//! (k fastest), each an `f32`, little-endian (108 bytes).

use crate::error::ModelError;
use crate::extension::{extension_kind, Extension};
use crate::math::Real;
use nalgebra::Vector3;

/// Payload version written and understood by this build.
pub const PAYLOAD_VERSION: u8 = 1;
/// Number of tensor entries.
pub const TERMS: usize = 27;
/// Payload size, bytes.
pub const PAYLOAD_BYTES: usize = 4 * TERMS;

/// The tensor `K_ijk` of the spin-coupling force (non-dimensional):
/// `k[i][3 * j + k]` multiplies `Ω_j V_k` in force component i.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpinCoupling<T: Real> {
    /// `K_ijk` as `k[i][3 * j + k]`.
    pub k: [[T; 9]; 3],
}

impl<T: Real> SpinCoupling<T> {
    /// A Magnus force `½ρ L³ c (Ω × V)`: `K_ijk = c ε_ijk`.
    pub fn magnus(c: T) -> Self {
        let mut k = [[T::zero(); 9]; 3];
        // (Ω × V)_i = ε_ijk Ω_j V_k.
        for (i, j, kk, sign) in [
            (0, 1, 2, 1.0),
            (0, 2, 1, -1.0),
            (1, 2, 0, 1.0),
            (1, 0, 2, -1.0),
            (2, 0, 1, 1.0),
            (2, 1, 0, -1.0),
        ] {
            if let Some(x) = k.get_mut(i).and_then(|row| row.get_mut(3 * j + kk)) {
                *x = c * T::of_f64(sign);
            }
        }
        Self { k }
    }

    /// The force, body frame, N: `½ρ L³ Σ_jk K_ijk Ω_j V_k`.
    ///
    /// * `velocity`: V, body frame, m/s; `angular_velocity`: Ω, body frame,
    ///   rad/s; `air_density`: ρ, kg/m³; `reference_length`: L, m.
    pub fn force(
        &self,
        velocity: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        air_density: T,
        reference_length: T,
    ) -> Vector3<T> {
        let l = reference_length;
        let scale = T::of_f64(0.5) * air_density * l * l * l;
        // Outer product Ω ⊗ V in the layout of one row of `k`.
        let (w, v) = (angular_velocity, velocity);
        let outer = [
            w.x * v.x,
            w.x * v.y,
            w.x * v.z,
            w.y * v.x,
            w.y * v.y,
            w.y * v.z,
            w.z * v.x,
            w.z * v.y,
            w.z * v.z,
        ];
        let row = |r: &[T; 9]| {
            r.iter()
                .zip(outer.iter())
                .fold(T::zero(), |acc, (a, b)| acc + *a * *b)
                * scale
        };
        let [r0, r1, r2] = &self.k;
        Vector3::new(row(r0), row(r1), row(r2))
    }

    /// The Magnus part of K: the `c` of the pure Magnus tensor `c ε_ijk`
    /// ([`Self::magnus`]) closest to K, i.e. K's projection on the
    /// Levi-Civita tensor, `Σ K_ijk ε_ijk / 6` (non-dimensional, as K;
    /// the Magnus force is then `½ρ L³ c (Ω × V)`).
    pub fn magnus_scale(&self) -> f64 {
        let e = SpinCoupling::<f64>::magnus(1.0);
        self.k
            .iter()
            .flatten()
            .zip(e.k.iter().flatten())
            .map(|(a, b)| a.as_f64() * b)
            .sum::<f64>()
            / 6.0
    }

    /// The Frobenius norm `|K|` (non-dimensional): how strong the coupling
    /// is overall, Magnus part or not.
    pub fn norm(&self) -> f64 {
        let squares = self.k.iter().flatten().map(|x| x.as_f64() * x.as_f64());
        libm::sqrt(squares.sum::<f64>())
    }

    /// The model extension holding this tensor (payload version 1).
    pub fn to_extension(&self) -> Result<Extension, ModelError> {
        crate::payload::encode(
            extension_kind::SPIN_COUPLING,
            PAYLOAD_VERSION,
            self.k.iter().flatten().copied(),
            "spin_coupling",
        )
    }

    /// The tensor of an extension: `Ok(None)` when the extension is of
    /// another kind or of a payload version this build does not know (it
    /// is then kept but not evaluated); an error when the payload is of
    /// the wrong size or holds a non-finite number.
    pub fn from_extension(e: &Extension) -> Result<Option<Self>, ModelError> {
        let values: Option<[T; TERMS]> = crate::payload::decode(
            e,
            extension_kind::SPIN_COUPLING,
            PAYLOAD_VERSION,
            "spin_coupling",
            "spin_coupling payload",
        )?;
        Ok(values.map(|v| Self {
            k: core::array::from_fn(|i| {
                core::array::from_fn(|jk| v.get(9 * i + jk).copied().unwrap_or_else(T::zero))
            }),
        }))
    }
}
