//! Real orthonormal spherical harmonics: orthonormality, closed forms,
//! addition theorem, f32 agreement.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

mod common;

use nalgebra::Vector3;
use omniad_core::sh::{coeff_count, evaluate, index, MAX_COEFFS, MAX_DEGREE};
use std::f64::consts::PI;

fn all(e: &Vector3<f64>) -> [f64; MAX_COEFFS] {
    let mut y = [0.0; MAX_COEFFS];
    evaluate(MAX_DEGREE, e, &mut y);
    y
}

#[test]
fn orthonormal_by_quadrature_up_to_degree_12() {
    // Products have degree <= 24: 13 Gauss nodes in z, 26 in longitude suffice.
    let quad = common::sphere_quadrature(14, 28);
    let n = coeff_count(MAX_DEGREE);
    let mut gram = vec![0.0; n * n];
    for (e, w) in &quad {
        let y = all(e);
        for i in 0..n {
            for j in 0..n {
                gram[i * n + j] += w * y[i] * y[j];
            }
        }
    }
    let mut worst = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let expected = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((gram[i * n + j] - expected).abs());
        }
    }
    assert!(worst <= 1e-10, "max orthonormality error {worst:e}");
}

#[test]
fn closed_forms_up_to_degree_3() {
    for e in common::test_directions(200) {
        let (x, y, z) = (e.x, e.y, e.z);
        let v = all(&e);
        let k = |c: f64| c / PI.sqrt();
        let expected = [
            (0, 0, k(0.5)),
            (1, -1, k(3f64.sqrt() / 2.0) * y),
            (1, 0, k(3f64.sqrt() / 2.0) * z),
            (1, 1, k(3f64.sqrt() / 2.0) * x),
            (2, -2, k(15f64.sqrt() / 2.0) * x * y),
            (2, -1, k(15f64.sqrt() / 2.0) * y * z),
            (2, 0, k(5f64.sqrt() / 4.0) * (3.0 * z * z - 1.0)),
            (2, 1, k(15f64.sqrt() / 2.0) * x * z),
            (2, 2, k(15f64.sqrt() / 4.0) * (x * x - y * y)),
            (
                3,
                -3,
                k((35.0f64 / 2.0).sqrt() / 4.0) * y * (3.0 * x * x - y * y),
            ),
            (3, -2, k(105f64.sqrt() / 2.0) * x * y * z),
            (
                3,
                -1,
                k((21.0f64 / 2.0).sqrt() / 4.0) * y * (5.0 * z * z - 1.0),
            ),
            (3, 0, k(7f64.sqrt() / 4.0) * (5.0 * z * z * z - 3.0 * z)),
            (
                3,
                1,
                k((21.0f64 / 2.0).sqrt() / 4.0) * x * (5.0 * z * z - 1.0),
            ),
            (3, 2, k(105f64.sqrt() / 4.0) * (x * x - y * y) * z),
            (
                3,
                3,
                k((35.0f64 / 2.0).sqrt() / 4.0) * x * (x * x - 3.0 * y * y),
            ),
        ];
        for (l, m, want) in expected {
            let got = v[index(l, m)];
            assert!(
                (got - want).abs() < 1e-14,
                "Y_{l},{m}({e:?}) = {got}, want {want}"
            );
        }
    }
}

fn legendre(l: usize, t: f64) -> f64 {
    let (mut p0, mut p1) = (1.0, t);
    if l == 0 {
        return 1.0;
    }
    for k in 2..=l {
        let p2 = ((2 * k - 1) as f64 * t * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    p1
}

#[test]
fn addition_theorem() {
    let dirs = common::test_directions(60);
    for pair in dirs.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (ya, yb) = (all(&a), all(&b));
        for l in 0..=MAX_DEGREE {
            let sum: f64 = (-(l as isize)..=l as isize)
                .map(|m| ya[index(l, m)] * yb[index(l, m)])
                .sum();
            let want = (2 * l + 1) as f64 / (4.0 * PI) * legendre(l, a.dot(&b).clamp(-1.0, 1.0));
            assert!((sum - want).abs() < 1e-12, "l = {l}: {sum} vs {want}");
        }
    }
}

#[test]
fn f32_agrees_with_f64() {
    for e in common::test_directions(100) {
        let y64 = all(&e);
        let mut y32 = [0.0f32; MAX_COEFFS];
        evaluate(MAX_DEGREE, &e.map(|v| v as f32), &mut y32);
        for (a, b) in y64.iter().zip(&y32) {
            assert!((a - *b as f64).abs() < 2e-5, "{a} vs {b}");
        }
    }
}

#[test]
fn lower_degree_is_a_prefix() {
    let e = Vector3::new(0.3, -0.4, 0.5).normalize();
    let full = all(&e);
    for n in 0..MAX_DEGREE {
        let mut y = [f64::NAN; MAX_COEFFS];
        assert_eq!(evaluate(n, &e, &mut y), coeff_count(n));
        assert_eq!(&y[..coeff_count(n)], &full[..coeff_count(n)]);
        assert!(y[coeff_count(n)].is_nan(), "wrote past degree {n}");
    }
}
