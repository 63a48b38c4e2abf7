//! The potential-flow added-mass tensor of the synthetic objects (the
//! `added_mass` effect's SCALE 1): the body is approximated by the
//! ellipsoid inscribed in its bounding box (semi-axes `a_i` = half the
//! extents). For translation along axis i, Lamb, *Hydrodynamics* §114-115:
//!
//! `m_i = ρ V_e α_i / (2 - α_i)`, `α_i = a b c ∫₀^∞ dλ / ((a_i² + λ) Δ(λ))`,
//! `Δ(λ) = sqrt((a² + λ)(b² + λ)(c² + λ))`, `V_e = 4/3 π a b c`,
//!
//! body frame, kg. For a thin plate (`c -> 0`) this tends to the elliptic
//! disk's normal added mass (a circular disk of radius r: `8/3 ρ r³`); the
//! open box is only roughly an ellipsoid (its walls carry fluid with them,
//! its open ends do not), which is why the set's truth records the tensor
//! used, not a claim about the real object.

use nalgebra::{Matrix3, Vector3};

/// Lamb's `α_i` of the ellipsoid with semi-axes `s`: the integral over
/// `λ ∈ [0, ∞)` mapped to `u ∈ [0, 1)` by `λ = c² (u / (1 - u))²` with `c`
/// the smallest semi-axis (so the peak of width c² near 0 of a thin body
/// is resolved), midpoint rule, 20 000 points.
fn lamb_alpha(s: &Vector3<f64>, i: usize) -> f64 {
    let (a, b, c) = (s.x, s.y, s.z);
    let n = 20_000;
    let mut sum = 0.0;
    for k in 0..n {
        let u = (k as f64 + 0.5) / n as f64;
        let c2 = s.min() * s.min();
        let r = u / (1.0 - u);
        let lambda = c2 * r * r;
        let dl = c2 * 2.0 * u / (1.0 - u).powi(3);
        let delta = ((a * a + lambda) * (b * b + lambda) * (c * c + lambda)).sqrt();
        sum += dl / ((s[i] * s[i] + lambda) * delta);
    }
    a * b * c * sum / n as f64
}

/// The added-mass tensor (kg, body frame, diagonal) of the ellipsoid
/// inscribed in a box of `extents` (m) in air of density `rho` (kg/m³).
pub fn ellipsoid_added_mass(extents: &Vector3<f64>, rho: f64) -> Matrix3<f64> {
    let s = extents * 0.5;
    let volume = 4.0 / 3.0 * std::f64::consts::PI * s.x * s.y * s.z;
    let m = Vector3::from_fn(|i, _| {
        let alpha = lamb_alpha(&s, i);
        rho * volume * alpha / (2.0 - alpha).max(1e-12)
    });
    Matrix3::from_diagonal(&m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_has_half_its_displaced_mass() {
        // Sphere: α = 2/3, m = ρ V / 2.
        let m = ellipsoid_added_mass(&Vector3::new(0.2, 0.2, 0.2), 1.2);
        let v = 4.0 / 3.0 * std::f64::consts::PI * 0.1f64.powi(3);
        for i in 0..3 {
            assert!(
                (m[(i, i)] - 0.6 * v).abs() < 1e-4 * 0.6 * v,
                "{}",
                m[(i, i)]
            );
        }
    }

    #[test]
    fn thin_disk_tends_to_eight_thirds_rho_r_cubed() {
        let r: f64 = 0.2;
        let m = ellipsoid_added_mass(&Vector3::new(2.0 * r, 2.0 * r, 2e-3), 1.0);
        let disk = 8.0 / 3.0 * r.powi(3);
        assert!(
            (m[(2, 2)] - disk).abs() < 0.01 * disk,
            "{} vs {disk}",
            m[(2, 2)]
        );
        assert!(m[(0, 0)] < 0.01 * disk);
    }
}
