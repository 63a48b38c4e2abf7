//! Force and torque, eqs. (5)-(8), against a hand-computed case.
#![allow(clippy::unwrap_used)]

use nalgebra::{Matrix3, Vector3};
use omniad_core::Coefficients;
use std::f64::consts::PI;

/// Degree 0, pole +x: C_F = -E + 0.5 E2, C_T = 0.2 E3, D = diag(.1,.2,.3).
fn hand_model<T: omniad_core::LaneScalar>() -> Coefficients<T> {
    let s = (4.0 * PI).sqrt();
    let c = T::of_f64;
    let mut m = Coefficients::zeros(0, Vector3::x(), c(0.5)).unwrap();
    m.set_alpha(0, 0, c(-s)).unwrap();
    m.set_alpha(1, 0, c(0.5 * s)).unwrap();
    m.set_beta(2, 0, c(0.2 * s)).unwrap();
    m.set_damping(&Matrix3::from_diagonal(&Vector3::new(
        c(0.1),
        c(0.2),
        c(0.3),
    )))
    .unwrap();
    m
}

#[test]
fn hand_computed_force_and_torque() {
    // V = (0,0,-2): E = -z, E2 = E x Z / |.| = -y, E3 = E x E2 = -x.
    // q = ½ρ|V|² = 2.4; F = q L² C_F = 0.6 (0, -0.5, 1).
    // T = q L³ C_T - ½ρ D|Ω|Ω L⁵ with Ω = (1,2,2), |Ω| = 3.
    let m = hand_model::<f64>();
    let w = m.wrench(
        &Vector3::new(0.0, 0.0, -2.0),
        &Vector3::new(1.0, 2.0, 2.0),
        1.2,
    );
    let f_want = Vector3::new(0.0, -0.3, 0.6);
    let t_want =
        Vector3::new(-0.06, 0.0, 0.0) - Vector3::new(0.1, 0.4, 0.6) * (0.6 * 3.0 * 0.03125);
    assert!((w.force - f_want).norm() < 1e-14, "{:?}", w.force);
    assert!((w.torque - t_want).norm() < 1e-14, "{:?}", w.torque);
    let w32 = hand_model::<f32>().wrench(
        &Vector3::new(0.0, 0.0, -2.0),
        &Vector3::new(1.0, 2.0, 2.0),
        1.2,
    );
    assert!((w32.force.map(f64::from) - f_want).norm() < 1e-6);
    assert!((w32.torque.map(f64::from) - t_want).norm() < 1e-6);
}

#[test]
fn zero_velocity_and_zero_spin_are_valid() {
    let m = hand_model::<f64>();
    let w = m.wrench(&Vector3::zeros(), &Vector3::zeros(), 1.2);
    assert_eq!(w.force, Vector3::zeros());
    assert_eq!(w.torque, Vector3::zeros());
    // Spin only: damping only.
    let w = m.wrench(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 2.0), 1.2);
    assert_eq!(w.force, Vector3::zeros());
    assert!((w.torque.z + 0.5 * 1.2 * 0.3 * 4.0 * 0.5f64.powi(5)).abs() < 1e-15);
    assert!(m.at_direction(&Vector3::zeros()).is_none());
    assert!(m.at_direction(&Vector3::new(f64::NAN, 0.0, 1.0)).is_none());
}

#[test]
fn force_scales_with_speed_squared_and_length_squared() {
    let mut m = hand_model::<f64>();
    let v = Vector3::new(0.3, -0.4, 1.2);
    let f1 = m.wrench(&v, &Vector3::zeros(), 1.2).force;
    let f2 = m.wrench(&(v * 3.0), &Vector3::zeros(), 1.2).force;
    assert!((f2 - f1 * 9.0).norm() < 1e-12);
    m.set_reference_length(1.0).unwrap();
    let f3 = m.wrench(&v, &Vector3::zeros(), 1.2).force;
    assert!((f3 - f1 * 4.0).norm() < 1e-12);
}

/// The SIMD path (where this machine has one) agrees with the portable
/// path to single-precision rounding, and the portable path's f32 sums
/// with its f64 ones, at every degree and many directions.
#[test]
fn simd_and_portable_paths_agree() {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    for degree in 0..=12u8 {
        let mut m = Coefficients::<f32>::zeros(degree, Vector3::z(), 0.58).unwrap();
        for k in 0..m.coeff_count() {
            for i in 0..3 {
                m.set_alpha(i, k, next() * 3.0).unwrap();
                m.set_beta(i, k, next()).unwrap();
            }
        }
        let wide = m.cast::<f64>();
        for _ in 0..200 {
            let e = Vector3::new(next(), next(), next());
            let Some(e) = e.try_normalize(1e-3) else {
                continue;
            };
            let fast = m.sh_sums(&e);
            let portable = m.sh_sums_portable(&e);
            let exact = wide.sh_sums(&e.cast::<f64>());
            // Rounding scales with the sum of |terms|: at most (N+1)^2
            // terms of |w Y| <= 3 * 1.3.
            let scale = 4.0 * m.coeff_count() as f64;
            for ((f, p), x) in fast.iter().zip(portable).zip(exact) {
                assert!(
                    (*f as f64 - x).abs() <= 1e-6 * scale,
                    "degree {degree}: {f} vs {x}"
                );
                assert!(
                    (p as f64 - x).abs() <= 1e-6 * scale,
                    "degree {degree}: {p} vs {x}"
                );
            }
        }
    }
}

/// `set_portable` switches the evaluation to the portable path exactly.
#[test]
fn portable_switch_gives_the_portable_bits() {
    let mut m = hand_model::<f32>();
    m.set_portable(true);
    let e = Vector3::new(0.36f32, -0.48, 0.8);
    assert_eq!(
        m.sh_sums(&e).map(f32::to_bits),
        m.sh_sums_portable(&e).map(f32::to_bits)
    );
}
