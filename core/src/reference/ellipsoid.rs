//! Potential-flow added mass of a solid ellipsoid in translation (Lamb,
//! *Hydrodynamics*, 6th ed., §114-115): for semi-axes `a, b, c` along body
//! x, y, z, the added mass along x is
//! `m_x = ρ (4/3)π abc · α₀ / (2 - α₀)`, with
//! `α₀ = abc ∫₀^∞ dλ / ((a² + λ) Δ(λ))`, `Δ = √((a²+λ)(b²+λ)(c²+λ))`,
//! and cyclically for y (β₀) and z (γ₀); `α₀ + β₀ + γ₀ = 2`. The integral
//! is Carlson's symmetric form, `α₀ = (2/3) abc R_D(b², c², a²)`
//! (DLMF 19.16.5, 19.20.18), computed by the duplication theorem (Carlson
//! 1995, Numer. Algorithms 10; DLMF 19.36.1). Rotational added inertia is
//! not computed (the equations of motion carry translation only, see
//! [`crate::rigid_body::state_rate_with_added_mass`]).

/// Carlson's `R_D(x, y, z) = (3/2) ∫₀^∞ dt / ((t+x)^½ (t+y)^½ (t+z)^{3/2})`
/// for `x, y >= 0` (at most one zero), `z > 0`; NaN otherwise.
pub fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    if !(x >= 0.0 && y >= 0.0 && z > 0.0) || x + y <= 0.0 {
        return f64::NAN;
    }
    let (mut x, mut y, mut z) = (x, y, z);
    let (mut sum, mut fac) = (0.0, 1.0);
    // Each duplication step shrinks the spread by 4; 40 steps reach any
    // double's precision.
    let mut ave = 0.0;
    let mut d = [0.0; 3];
    for _ in 0..40 {
        let (sx, sy, sz) = (libm::sqrt(x), libm::sqrt(y), libm::sqrt(z));
        let lam = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lam));
        fac *= 0.25;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        ave = 0.2 * (x + y + 3.0 * z);
        d = [(ave - x) / ave, (ave - y) / ave, (ave - z) / ave];
        if d.iter().all(|v| v.abs() < 1e-4) {
            break;
        }
    }
    let [dx, dy, dz] = d;
    let (ea, eb) = (dx * dy, dz * dz);
    let (ec, ed) = (ea - eb, ea - 6.0 * eb);
    let ee = ed + ec + ec;
    let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0);
    let (c5, c6) = (0.25 * c3, 1.5 * c4);
    3.0 * sum
        + fac
            * (1.0
                + ed * (-c1 + c5 * ed - c6 * dz * ee)
                + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea)))
            / (ave * libm::sqrt(ave))
}

/// Lamb's `α₀, β₀, γ₀` of an ellipsoid with semi-axes `a, b, c` (m, > 0).
pub fn lamb_coefficients(a: f64, b: f64, c: f64) -> [f64; 3] {
    let abc = a * b * c;
    let (a2, b2, c2) = (a * a, b * b, c * c);
    [
        2.0 / 3.0 * abc * carlson_rd(b2, c2, a2),
        2.0 / 3.0 * abc * carlson_rd(c2, a2, b2),
        2.0 / 3.0 * abc * carlson_rd(a2, b2, c2),
    ]
}

/// Added mass (kg) of translation along body x, y, z of the ellipsoid
/// with semi-axes `semi` (m) in a fluid of density `rho` (kg/m³).
pub fn added_mass(semi: [f64; 3], rho: f64) -> [f64; 3] {
    let [a, b, c] = semi;
    let volume = 4.0 / 3.0 * core::f64::consts::PI * a * b * c;
    lamb_coefficients(a, b, c).map(|k| rho * volume * k / (2.0 - k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_has_half_its_displaced_mass() {
        // Lamb §92: a sphere's added mass is half the displaced fluid's.
        let m = added_mass([0.1, 0.1, 0.1], 1.2);
        let half = 0.5 * 1.2 * 4.0 / 3.0 * core::f64::consts::PI * 1e-3;
        assert!(
            m.iter().all(|x| (x - half).abs() < 1e-12 * half.max(1.0)),
            "{m:?}"
        );
    }

    #[test]
    fn coefficients_sum_to_two_and_thin_disc_tends_to_eight_thirds_rho_r_cubed() {
        let k = lamb_coefficients(0.15, 0.25, 0.01);
        assert!((k.iter().sum::<f64>() - 2.0).abs() < 1e-12, "{k:?}");
        // Circular disc of radius R moving normal to itself: (8/3) ρ R³
        // (Lamb §108).
        let r = 0.2;
        let m = added_mass([r, r, r * 1e-5], 1.0);
        let disc = 8.0 / 3.0 * r * r * r;
        assert!((m[2] - disc).abs() < 1e-4 * disc, "{} vs {disc}", m[2]);
        // Elliptic disc 0.15 x 0.25 m (semi-axes), normal: (4/3)π ρ b a² / E(e)
        // with a < b, e² = 1 - a²/b² = 0.64, E(0.8) = 1.276349943.
        let m = added_mass([0.15, 0.25, 1e-6], 1.0);
        let ell = 4.0 / 3.0 * core::f64::consts::PI * 0.25 * 0.15 * 0.15 / 1.276_349_943;
        assert!((m[2] - ell).abs() < 1e-4 * ell, "{} vs {ell}", m[2]);
    }
}
