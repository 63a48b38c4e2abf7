//! Projection of a direction function onto OmniAD coefficients, eqs. (11)
//! and (13): `alpha^i_lm = ∫ (C_F(E)·E^i) Y_lm(E) dS` by Gauss-Legendre
//! (in z about the pole) x uniform (in longitude) quadrature, exact for
//! band-limited integrands up to degree `2 * QUAD_DEGREE`.

use nalgebra::{Rotation3, Vector3};
use omniad_core::basis::vector_basis;
use omniad_core::sh::{self, MAX_COEFFS};
use omniad_core::{Coefficients, ModelError};

/// Gauss-Legendre nodes in z.
const LATITUDES: usize = 48;
/// Longitude divisions.
const LONGITUDES: usize = 96;

/// Gauss-Legendre nodes and weights on [-1, 1].
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut nodes = vec![(0.0, 0.0); n];
    omniad_core::quadrature::gauss_legendre(&mut nodes);
    nodes
}

/// Quadrature points `(E, weight)` on the unit sphere, symmetric about
/// `pole`; the weights sum to 4π.
pub fn sphere_quadrature(pole: &Vector3<f64>) -> Vec<(Vector3<f64>, f64)> {
    let to_pole = Rotation3::rotation_between(&Vector3::z(), pole)
        .unwrap_or_else(|| Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    let dphi = 2.0 * std::f64::consts::PI / LONGITUDES as f64;
    let mut out = Vec::with_capacity(LATITUDES * LONGITUDES);
    for (z, w) in gauss_legendre(LATITUDES) {
        let r = (1.0 - z * z).max(0.0).sqrt();
        for j in 0..LONGITUDES {
            let phi = (j as f64 + 0.5) * dphi;
            out.push((
                to_pole * Vector3::new(r * phi.cos(), r * phi.sin(), z),
                w * dphi,
            ));
        }
    }
    out
}

/// Projects `f(E) = (C_F(E), C_T(E))` (body frame, non-dimensional) onto
/// coefficients of `degree` with the given pole and reference length (m).
pub fn project(
    degree: u8,
    pole: Vector3<f64>,
    reference_length: f64,
    f: impl Fn(&Vector3<f64>) -> (Vector3<f64>, Vector3<f64>),
) -> Result<Coefficients<f64>, ModelError> {
    let mut model = Coefficients::zeros(degree, pole, reference_length)?;
    let pole = model.pole();
    let n = model.coeff_count();
    let mut sums = vec![[0.0f64; 6]; n];
    let mut y = [0.0; MAX_COEFFS];
    for (e, w) in sphere_quadrature(&pole) {
        let (cf, ct) = f(&e);
        let basis = vector_basis(&e, &pole);
        let proj = [
            cf.dot(&basis[0]),
            cf.dot(&basis[1]),
            cf.dot(&basis[2]),
            ct.dot(&basis[0]),
            ct.dot(&basis[1]),
            ct.dot(&basis[2]),
        ];
        let count = sh::evaluate(degree as usize, &e, &mut y);
        for (row, yk) in sums.iter_mut().zip(&y[..count]) {
            for (s, p) in row.iter_mut().zip(&proj) {
                *s += w * yk * p;
            }
        }
    }
    for (k, row) in sums.iter().enumerate() {
        for i in 0..3 {
            model.set_alpha(i, k, row[i])?;
            model.set_beta(i, k, row[i + 3])?;
        }
    }
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_weights_sum_to_sphere_area() {
        let total: f64 = sphere_quadrature(&Vector3::new(0.3, 0.1, 0.9).normalize())
            .iter()
            .map(|p| p.1)
            .sum();
        assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-10);
    }

    #[test]
    fn band_limited_function_is_reproduced() {
        // C_F = -E (pure isotropic drag of 1) is exactly alpha^1_00 = -sqrt(4π).
        let m = project(4, Vector3::z(), 1.0, |e| (-e, Vector3::zeros())).unwrap();
        assert!((m.alpha(0, 0).unwrap() + (4.0 * std::f64::consts::PI).sqrt()).abs() < 1e-10);
        let c = m.at_direction(&Vector3::new(0.2, -0.5, 0.7)).unwrap();
        let e = Vector3::new(0.2, -0.5, 0.7).normalize();
        assert!((c.force + e).norm() < 1e-9, "{:?}", c.force);
    }
}
