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

/// A model whose force has degree 8 and torque degree 10.
fn mixed_model<T: omniad_core::LaneScalar>() -> Coefficients<T> {
    let c = T::of_f64;
    let mut m = Coefficients::<T>::zeros(8, Vector3::new(c(0.1), c(0.3), c(1.0)), c(0.58))
        .unwrap()
        .with_torque_degree(10)
        .unwrap();
    for k in 0..m.torque_coeff_count() {
        for i in 0..3 {
            let v = ((k * 29 + i * 11) % 31) as f64 / 31.0 - 0.5;
            if k < m.coeff_count() {
                m.set_alpha(i, k, c(2.0 * v)).unwrap();
            }
            m.set_beta(i, k, c(0.3 * v + 0.01)).unwrap();
        }
    }
    m
}

/// Directions spread over the sphere, the poles included.
fn directions() -> Vec<Vector3<f64>> {
    let mut d: Vec<Vector3<f64>> = omniad_core::quadrature::fibonacci_sphere(150).collect();
    d.extend([
        Vector3::z(),
        -Vector3::z(),
        Vector3::new(0.1, 0.3, 1.0).normalize(),
    ]);
    d
}

/// The torque of degree N_T = 10 is the degree-10 SH sum of its
/// coefficients, the force of degree 8 the degree-8 one (eqs. 7-8).
#[test]
fn a_torque_of_its_own_degree_evaluates_as_that_degrees_sh_sum() {
    use omniad_core::sh::{coeff_count, evaluate, MAX_COEFFS};
    let m = mixed_model::<f64>();
    assert_eq!(
        (m.degree(), m.torque_degree(), m.basis_degree()),
        (8, 10, 10)
    );
    assert_eq!(m.alpha(0, coeff_count(8)), None);
    assert!(m.beta(0, coeff_count(10) - 1).is_some());
    for e in directions() {
        let mut y = [0.0; MAX_COEFFS];
        evaluate(10, &e, &mut y);
        let want: [f64; 6] = std::array::from_fn(|set| {
            let (n, c) = if set < 3 { (8, set) } else { (10, set - 3) };
            (0..coeff_count(n))
                .zip(y)
                .map(|(k, yk)| {
                    let v = if set < 3 { m.alpha(c, k) } else { m.beta(c, k) };
                    v.unwrap() * yk
                })
                .sum()
        });
        let got = m.sh_sums(&e);
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{e}: {g} vs {w}");
        }
        // The f32 paths (SIMD where the machine has it, and portable).
        let m32 = m.cast::<f32>();
        let e32 = e.cast::<f32>();
        for sums in [m32.sh_sums(&e32), m32.sh_sums_portable(&e32)] {
            for (g, w) in sums.iter().zip(want) {
                assert!((f64::from(*g) - w).abs() < 1e-4, "{e}: {g} vs {w}");
            }
        }
    }
}

/// Giving the torque a degree of its own changes neither the force nor a
/// torque whose coefficients stop at the force's degree, bit for bit, on
/// every path (the extra basis terms have zero weights: `x + 0·y = x`).
#[test]
fn the_torque_degree_leaves_the_force_bit_for_bit() {
    fn check<T: omniad_core::LaneScalar>(portable: bool) {
        let mut wide = mixed_model::<T>();
        let mut same = wide.with_torque_degree(8).unwrap();
        let mut back = same.with_torque_degree(10).unwrap();
        assert_eq!(same.torque_degree(), 8);
        for m in [&mut wide, &mut same, &mut back] {
            m.set_portable(portable);
        }
        let w = Vector3::new(T::of_f64(1.0), T::of_f64(0.5), T::of_f64(-2.0));
        for e in directions() {
            let e = e.map(T::of_f64);
            let (a, b, c) = (wide.sh_sums(&e), same.sh_sums(&e), back.sh_sums(&e));
            let bits = |s: &[T]| s.iter().map(|x| x.as_f64().to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a[..3]), bits(&b[..3]), "force, {e}");
            assert_eq!(bits(&c), bits(&b), "torque truncated at 8, {e}");
            let v = e * T::of_f64(3.0);
            let (fa, fb) = (
                wide.wrench(&v, &w, T::of_f64(1.2)),
                same.wrench(&v, &w, T::of_f64(1.2)),
            );
            assert_eq!(bits(fa.force.as_slice()), bits(fb.force.as_slice()));
        }
    }
    check::<f32>(false);
    check::<f32>(true);
    check::<f64>(false);
}
