//! Test helpers: quadrature and direction sets.
#![allow(dead_code)]

use nalgebra::Vector3;

/// Gauss-Legendre nodes and weights on [-1, 1].
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut nodes = vec![(0.0, 0.0); n];
    omniad_core::quadrature::gauss_legendre(&mut nodes);
    nodes
}

/// Product quadrature on the sphere exact for polynomials of degree
/// `< 2 * n_lat` in z and `< n_lon` in longitude.
pub fn sphere_quadrature(n_lat: usize, n_lon: usize) -> Vec<(Vector3<f64>, f64)> {
    let dphi = 2.0 * std::f64::consts::PI / n_lon as f64;
    let mut out = Vec::new();
    for (z, w) in gauss_legendre(n_lat) {
        let r = (1.0 - z * z).sqrt();
        for j in 0..n_lon {
            let phi = j as f64 * dphi;
            out.push((Vector3::new(r * phi.cos(), r * phi.sin(), z), w * dphi));
        }
    }
    out
}

/// Deterministic pseudo-random unit vectors (xorshift), plus the six axes
/// and directions within 1e-9 of ±z and of every axis.
pub fn test_directions(n: usize) -> Vec<Vector3<f64>> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut out = Vec::new();
    while out.len() < n {
        let v = Vector3::new(next(), next(), next());
        let len = v.norm();
        if len > 0.1 && len <= 1.0 {
            out.push(v / len);
        }
    }
    for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
        for sign in [1.0, -1.0] {
            out.push(axis * sign);
            for eps in [1e-9, 1e-12, 1e-6] {
                out.push((axis * sign + Vector3::new(eps, -eps, eps * 0.5)).normalize());
            }
        }
    }
    out
}
