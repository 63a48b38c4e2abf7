//! Integration and sampling rules on the unit sphere: Gauss-Legendre on
//! [-1, 1] (the latitude rule), the product rule for integrals over the
//! sphere such as eqs. (11) and (13) ([`sphere_quadrature`]), and a nearly
//! uniform point set ([`fibonacci_sphere`]).
//!
//! Cosines and sines of longitudes go through nalgebra's scalar traits:
//! the platform's maths library when nalgebra has `std` (every host build,
//! through this crate's `std` feature; what the bundled coefficient files
//! were made with), the `libm` crate without it (the firmware's build).

use nalgebra::{ComplexField, Rotation3, Vector3};

/// Gauss-Legendre nodes in z of [`sphere_quadrature`].
pub const SPHERE_LATITUDES: usize = 48;
/// Longitude divisions of [`sphere_quadrature`].
pub const SPHERE_LONGITUDES: usize = 96;

/// Fills `nodes` with the `n = nodes.len()` Gauss-Legendre nodes and
/// weights `(x_i, w_i)` on [-1, 1] (Newton's method on `P_n`), exact for
/// polynomials of degree `< 2n`. No allocation.
pub fn gauss_legendre(nodes: &mut [(f64, f64)]) {
    let n = nodes.len();
    let nf = n as f64;
    for (i, slot) in nodes.iter_mut().enumerate() {
        let mut x = libm::cos(core::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5));
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        *slot = (x, 2.0 / ((1.0 - x * x) * dp * dp));
    }
}

/// `(cos x, sin x)`, see the module documentation.
fn cos_sin(x: f64) -> (f64, f64) {
    (ComplexField::cos(x), ComplexField::sin(x))
}

/// Quadrature points `(E, weight)` on the unit sphere, symmetric about
/// `pole` (unit length): Gauss-Legendre in `z` about the pole
/// ([`SPHERE_LATITUDES`] nodes) times the midpoint rule in longitude
/// ([`SPHERE_LONGITUDES`]); exact for band-limited integrands up to degree
/// 95 in longitude and 95 in z. The weights (sr) sum to 4π.
pub fn sphere_quadrature(pole: &Vector3<f64>) -> impl Iterator<Item = (Vector3<f64>, f64)> {
    let to_pole = Rotation3::rotation_between(&Vector3::z(), pole)
        .unwrap_or_else(|| Rotation3::from_axis_angle(&Vector3::x_axis(), core::f64::consts::PI));
    let dphi = 2.0 * core::f64::consts::PI / SPHERE_LONGITUDES as f64;
    let mut nodes = [(0.0, 0.0); SPHERE_LATITUDES];
    gauss_legendre(&mut nodes);
    nodes.into_iter().flat_map(move |(z, w)| {
        let r = libm::sqrt((1.0 - z * z).max(0.0));
        (0..SPHERE_LONGITUDES).map(move |j| {
            let (c, s) = cos_sin((j as f64 + 0.5) * dphi);
            (to_pole * Vector3::new(r * c, r * s, z), w * dphi)
        })
    })
}

/// `n` nearly uniform unit vectors (the Fibonacci lattice: equal steps in
/// z, longitudes by the golden angle).
pub fn fibonacci_sphere(n: usize) -> impl Iterator<Item = Vector3<f64>> + Clone {
    let golden = core::f64::consts::PI * (3.0 - libm::sqrt(5.0));
    (0..n).map(move |i| {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = libm::sqrt(1.0 - z * z);
        let (c, s) = cos_sin(golden * i as f64);
        Vector3::new(r * c, r * s, z)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_weights_sum_to_the_sphere_area() {
        let total: f64 = sphere_quadrature(&Vector3::new(0.3, 0.1, 0.9).normalize())
            .map(|p| p.1)
            .sum();
        assert!((total - 4.0 * core::f64::consts::PI).abs() < 1e-10);
    }

    #[test]
    fn fibonacci_points_are_unit_and_balanced() {
        let mut mean = Vector3::zeros();
        for e in fibonacci_sphere(500) {
            assert!((e.norm() - 1.0).abs() < 1e-12);
            mean += e / 500.0;
        }
        assert!(mean.norm() < 1e-2, "{mean:?}");
    }

    #[test]
    fn weights_sum_to_two_and_integrate_x_squared() {
        let mut nodes = [(0.0, 0.0); 7];
        super::gauss_legendre(&mut nodes);
        let sum: f64 = nodes.iter().map(|p| p.1).sum();
        let x2: f64 = nodes.iter().map(|p| p.1 * p.0 * p.0).sum();
        assert!((sum - 2.0).abs() < 1e-14 && (x2 - 2.0 / 3.0).abs() < 1e-14);
    }
}
