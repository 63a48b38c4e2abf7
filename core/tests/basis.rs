//! The §4.2 vector basis: orthonormal and right-handed everywhere,
//! including within 1e-9 of the poles.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

mod common;

use nalgebra::Vector3;
use omniad_core::basis::vector_basis;

fn check(e: &Vector3<f64>, pole: &Vector3<f64>) {
    let [e1, e2, e3] = vector_basis(e, pole);
    for (i, v) in [e1, e2, e3].iter().enumerate() {
        assert!(
            v.iter().all(|x| x.is_finite()),
            "NaN in E{} at {e:?}",
            i + 1
        );
        assert!(
            (v.norm() - 1.0).abs() < 1e-12,
            "|E{}| = {} at {e:?}",
            i + 1,
            v.norm()
        );
    }
    assert!(
        e1.dot(&e2).abs() < 1e-12 && e1.dot(&e3).abs() < 1e-12 && e2.dot(&e3).abs() < 1e-12,
        "not orthogonal at {e:?}"
    );
    assert!(
        (e1.cross(&e2) - e3).norm() < 1e-12,
        "not right-handed at {e:?}"
    );
    assert_eq!(e1, *e);
    // E2 is longitudinal: orthogonal to the pole.
    assert!(
        e2.dot(pole).abs() < 1e-12,
        "E2 not orthogonal to Z at {e:?}"
    );
}

#[test]
fn orthonormal_and_right_handed_for_many_directions_and_poles() {
    let dirs = common::test_directions(2000);
    for pole in [
        Vector3::z(),
        Vector3::x(),
        -Vector3::y(),
        Vector3::new(0.0, 0.6, 0.8),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
    ] {
        for e in &dirs {
            check(e, &pole);
        }
        for sign in [1.0, -1.0] {
            for eps in [0.0, 1e-15, 1e-12, 1e-9, 1e-6] {
                let nudge = pole.cross(&Vector3::new(0.3, 0.5, 0.7)).normalize() * eps;
                check(&(pole * sign + nudge).normalize(), &pole);
            }
        }
    }
}

#[test]
fn matches_the_paper_formula_away_from_the_poles() {
    let pole = Vector3::z();
    let e = Vector3::new(0.6, 0.0, 0.8);
    let [_, e2, e3] = vector_basis(&e, &pole);
    let want2 = e.cross(&pole).normalize();
    assert!((e2 - want2).norm() < 1e-15);
    assert!((e3 - e.cross(&want2)).norm() < 1e-15);
}

#[test]
fn f32_is_finite_at_the_poles() {
    for e in [Vector3::<f32>::z(), -Vector3::<f32>::z()] {
        let b = vector_basis(&e, &Vector3::z());
        assert!(b
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()) && (v.norm() - 1.0).abs() < 1e-6));
    }
}

/// A pole of huge components is a direction like any other: its squares
/// overflow, and the pole was normalised to the zero vector (a file that
/// then evaluated with flipped signs, and whose copy no reader took).
#[test]
fn a_pole_of_huge_components_is_normalised_not_zeroed() {
    use omniad_core::Coefficients;
    let m = Coefficients::<f64>::zeros(2, Vector3::new(0.0, 0.0, 1e200), 0.5).expect("model");
    assert!((m.pole() - Vector3::z()).norm() < 1e-15, "{}", m.pole());
    let m =
        Coefficients::<f64>::zeros(2, Vector3::new(-f64::MAX, 0.0, f64::MAX), 0.5).expect("model");
    let want = Vector3::new(-1.0, 0.0, 1.0) / 2f64.sqrt();
    assert!((m.pole() - want).norm() < 1e-15, "{}", m.pole());
    let m = Coefficients::<f32>::zeros(2, Vector3::new(3e30, 4e30, 0.0), 0.5).expect("f32");
    assert!(
        (m.pole() - Vector3::new(0.6, 0.8, 0.0)).norm() < 1e-6,
        "{}",
        m.pole()
    );
    // Subnormal squares: the plain norm is finite but imprecise.
    let m = Coefficients::<f64>::zeros(2, Vector3::new(3e-162, 0.0, 0.0), 0.5).expect("tiny");
    assert_eq!(m.pole(), Vector3::x());
    assert!(Coefficients::<f64>::zeros(2, Vector3::zeros(), 0.5).is_err());
}
