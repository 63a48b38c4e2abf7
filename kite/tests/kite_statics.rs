//! Statics and stability (paper §7, eqs. 14-16) on the shipped kites.

mod common;

use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::kite::{stability, statics};

/// Eq. (16): every point of the line gives the smallest |T_kite|, equal to
/// the part of T_air along the string; moving off the line only increases it.
#[test]
fn eq16_attachment_minimises_unbalanced_torque() {
    let design = common::kite("fig15-b");
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let cond = design.conditions(None);
    let r = design.orientation();
    let eq = statics::equilibrium(&kite, &cond, &r).unwrap();
    let f_hat = eq.string_body.normalize();
    let floor = eq.air.torque.dot(&f_hat).abs();
    assert!(
        eq.air.torque.norm() > 1e-3,
        "asymmetric kite must have a torque to cancel"
    );
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for gamma in [-0.05, 0.0, 0.02, 0.1] {
        let p = statics::attachment_point(&eq, gamma).unwrap();
        let best = statics::unbalanced_torque(&eq, &p).norm();
        assert!(
            (best - floor).abs() < 1e-12,
            "on the line |T| = {best}, expected {floor}"
        );
        for _ in 0..200 {
            let off = Vector3::new(rnd(), rnd(), rnd()) * 0.2;
            let t = statics::unbalanced_torque(&eq, &(p + off)).norm();
            assert!(
                t >= best - 1e-12,
                "point off the line beat eq. (16): {t} < {best}"
            );
        }
    }
    // The paper's printed operand order (F × T_air) is not the minimiser.
    let f = eq.string_body;
    let printed = f.cross(&eq.air.torque) / f.norm_squared();
    assert!(statics::unbalanced_torque(&eq, &printed).norm() > floor + 1e-3);
}

/// The chain-rule Jacobian agrees with central differences of eq. (15).
#[test]
fn jacobian_matches_finite_differences() {
    for (name, turn) in [
        ("fig15-b", [0.1, -0.2, 0.3]),
        ("box-classic", [0.0, 0.0, 0.0]),
        ("fig15-c", [-0.3, 0.1, 0.2]),
    ] {
        let design = common::kite(name);
        let prims = design.primitives();
        let kite = design.kite(&prims);
        let cond = design.conditions(None);
        let r = design.orientation() * UnitQuaternion::from_scaled_axis(Vector3::from(turn));
        let p = Vector3::new(-0.08, 0.03, -0.05);
        let j = stability::jacobian(&kite, &cond, &r, &p).unwrap();
        let n = stability::jacobian_numeric(&kite, &cond, &r, &p, 1e-5).unwrap();
        let scale = n.norm();
        assert!(scale > 1e-2, "{name}: degenerate Jacobian");
        assert!(
            (j - n).norm() < 1e-5 * scale,
            "{name}: analytic\n{j}\nnumeric\n{n}"
        );
    }
}

/// A kite symmetric about its x-z plane, in a wind in that plane: the
/// symmetric part of J decouples, so one eigen-axis is ±y and the other two
/// lie in the x-z plane.
#[test]
fn symmetric_kite_eigen_axes_follow_the_mirror_plane() {
    for name in ["box-classic", "box-three-cell", "winged-box", "plate-flat"] {
        let design = common::kite(name);
        let prims = design.primitives();
        let kite = design.kite(&prims);
        let cond = design.conditions(None);
        let r = design.orientation();
        let p = omniad_kite::check::attachment_point(&design, None, &r).unwrap();
        let st = stability::stability(&kite, &cond, &r, &p).unwrap();
        let along_y: Vec<f64> = st.axes.iter().map(|a| a.axis.y.abs()).collect();
        let ones = along_y.iter().filter(|y| (**y - 1.0).abs() < 1e-6).count();
        let zeros = along_y.iter().filter(|y| **y < 1e-6).count();
        assert_eq!((ones, zeros), (1, 2), "{name}: |axis.y| = {along_y:?}");
        // And J itself has the mirror structure: no x/z <-> y coupling.
        let j = st.jacobian;
        for (a, b) in [(0, 1), (1, 0), (2, 1), (1, 2)] {
            assert!(
                j[(a, b)].abs() < 1e-7 * j.norm(),
                "{name}: J[{a},{b}] = {}",
                j[(a, b)]
            );
        }
    }
}

/// Eigen-decomposition: reconstructs the matrix, ascending, unit axes.
#[test]
fn symmetric_eigen_reconstructs() {
    let m = nalgebra::Matrix3::new(2.0, -0.3, 0.5, 0.1, -1.0, 0.2, 0.5, 0.4, 0.7);
    let pairs: [(f64, Vector3<f64>); 3] = stability::symmetric_eigen(&m).unwrap();
    let sym = (m + m.transpose()) * 0.5;
    let mut rebuilt = nalgebra::Matrix3::zeros();
    for (l, v) in &pairs {
        assert!((v.norm() - 1.0).abs() < 1e-12);
        assert!((sym * v - v * *l).norm() < 1e-10);
        rebuilt += v * v.transpose() * *l;
    }
    assert!((rebuilt - sym).norm() < 1e-10);
    assert!(pairs[0].0 <= pairs[1].0 && pairs[1].0 <= pairs[2].0);
    let nan = nalgebra::Matrix3::from_element(f64::NAN);
    assert!(stability::symmetric_eigen(&nan).is_err());
}

/// The core statics also run in f32 (the firmware type) and agree.
#[test]
fn f32_statics_agree_with_f64() {
    let design = common::kite("box-classic");
    let c32: Vec<_> = design
        .coefficients
        .iter()
        .map(|c| c.cast::<f32>())
        .collect();
    let prims32: Vec<_> = c32
        .iter()
        .zip(&design.rotations)
        .zip(&design.offsets)
        .map(|((c, q), y)| omniad_core::kite::Primitive {
            coefficients: c,
            rotation: q.cast(),
            offset: y.cast(),
        })
        .collect();
    let kite32 = omniad_core::kite::Kite {
        primitives: &prims32,
        mass: design.mass.mass as f32,
    };
    let cond32 = omniad_core::kite::Conditions::<f32>::standard(5.0);
    let r32: UnitQuaternion<f32> = design.orientation().cast();
    let eq32 = statics::equilibrium(&kite32, &cond32, &r32).unwrap();
    let prims = design.primitives();
    let eq = statics::equilibrium(
        &design.kite(&prims),
        &design.conditions(None),
        &design.orientation(),
    )
    .unwrap();
    assert!(
        (eq32.string_world.cast::<f64>() - eq.string_world).norm() < 1e-4 * eq.string_world.norm()
    );
}
