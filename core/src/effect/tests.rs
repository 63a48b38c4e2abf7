#![allow(
    clippy::indexing_slicing,
    clippy::unwrap_used,
    reason = "test code: a failed unwrap or index is a failed test"
)]

use super::*;

fn inputs() -> EffectInputs<f64> {
    EffectInputs {
        velocity: Vector3::new(1.0, -2.0, 3.0),
        angular_velocity: Vector3::new(0.5, 4.0, -1.0),
        gravity: Vector3::new(0.0, -3.0, -9.0),
        velocity_rate: Vector3::new(0.2, 0.1, -0.4),
        air_density: 1.2,
        reference_length: 0.6,
    }
}

#[test]
fn names_tags_and_counts_round_trip() {
    for k in EffectKind::ALL {
        assert_eq!(EffectKind::from_name(k.name()), Some(k));
        assert_eq!(EffectKind::from_extension_kind(k.extension_kind()), Some(k));
        assert!(k.param_count() <= MAX_PARAMS);
    }
    assert_eq!(EffectKind::from_name("magnus"), None);
}

/// Linear in the parameters: the wrench of any parameter vector is the
/// sum of the unit columns — what the fit relies on.
#[test]
fn every_effect_is_linear_in_its_parameters() {
    let x = inputs();
    for k in EffectKind::ALL {
        let params: [f64; MAX_PARAMS] = core::array::from_fn(|j| 0.3 + 0.7 * j as f64);
        let e = Effect::new(k, &params[..k.param_count()]).unwrap();
        let whole = e.wrench(&x);
        let mut sum = Wrench::<f64>::zero();
        for (j, p) in params.iter().enumerate().take(k.param_count()) {
            let c = Effect::<f64>::unit(k, j).wrench(&x);
            sum.force += c.force * *p;
            sum.torque += c.torque * *p;
        }
        assert!((whole.force - sum.force).norm() < 1e-12, "{k:?}");
        assert!((whole.torque - sum.torque).norm() < 1e-12, "{k:?}");
    }
}

#[test]
fn the_formulas_as_documented() {
    let x = inputs();
    let w = |k, p: &[f64]| Effect::new(k, p).unwrap().wrench(&x);
    // Buoyancy: up against gravity, ρ V_b |g|.
    let b = w(EffectKind::Buoyancy, &[0.01]);
    assert!((b.force - x.gravity * (-1.2 * 0.01)).norm() < 1e-15);
    // Rotational lift ⟂ to V and Ω.
    let r = w(EffectKind::RotationalLift, &[0.8]);
    assert!(r.force.dot(&x.velocity).abs() < 1e-12);
    assert!(r.force.dot(&x.angular_velocity).abs() < 1e-12);
    // Linear drag opposes V with k μ L |V|.
    let d = w(EffectKind::LinearDrag, &[3.0 * core::f64::consts::PI]);
    let expect = 3.0 * core::f64::consts::PI * AIR_VISCOSITY * 0.6 * x.velocity.norm();
    assert!((d.force.norm() - expect).abs() < 1e-15 && d.force.dot(&x.velocity) < 0.0);
    // Propeller thrust with K = I is along Ω, ½ρL⁴|Ω|².
    let id = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let p = w(EffectKind::PropellerThrust, &id);
    let n = x.angular_velocity.norm();
    assert!((p.force - x.angular_velocity * (0.5 * 1.2 * 0.6f64.powi(4) * n)).norm() < 1e-12);
    // Added mass: isotropic M_a = m I gives -m dV/dt and no Munk moment.
    let a = w(EffectKind::AddedMass, &[0.05, 0.05, 0.05, 0.0, 0.0, 0.0]);
    let expect = -x.velocity_rate * 0.05 - x.angular_velocity.cross(&(x.velocity * 0.05));
    assert!((a.force - expect).norm() < 1e-15);
    assert!(a.torque.norm() < 1e-15, "no Munk moment for a sphere");
}

/// The coupling is added mass without its acceleration reaction (same
/// Munk moment, force short of `-M_a dV/dt`), changes no motion, and its
/// isotropic part is a rotational lift with `c = -m / (ρL³)`.
#[test]
fn added_mass_coupling_is_added_mass_without_the_acceleration_reaction() {
    let x = inputs();
    let six = [0.004, 0.001, 0.02, 0.0005, -0.0002, 0.0001];
    let full = Effect::new(EffectKind::AddedMass, &six).unwrap().wrench(&x);
    let coupling = Effect::new(EffectKind::AddedMassCoupling, &six).unwrap();
    let c = coupling.wrench(&x);
    let m = crate::math::symmetric_from_six(six);
    assert!((c.force - (full.force + m * x.velocity_rate)).norm() < 1e-15);
    assert_eq!(c.torque, full.torque);
    assert!(coupling.added_mass().is_none(), "a force, not a mass");
    assert!(!EffectKind::AddedMassCoupling.changes_motion());
    let (rho, l) = (x.air_density, x.reference_length);
    let lift = Effect::new(EffectKind::RotationalLift, &[0.3])
        .unwrap()
        .wrench(&x);
    let m_iso = -0.3 * rho * l * l * l;
    let iso = Effect::new(
        EffectKind::AddedMassCoupling,
        &[m_iso, m_iso, m_iso, 0.0, 0.0, 0.0],
    );
    let iso = iso.unwrap().wrench(&x);
    assert!(
        (iso.force - lift.force).norm() < 1e-14,
        "{:?} vs {:?}",
        iso.force,
        lift.force
    );
    assert!(iso.torque.norm() < 1e-15);
}

/// The Munk moment of a plate-like M_a turns the plate broadside to the
/// flow (the classic result: a falling card turns flat).
#[test]
fn munk_moment_turns_a_plate_broadside() {
    let mut x = inputs();
    x.velocity = Vector3::new(1.0, 0.0, 1.0); // 45° between the plate's axes
    x.angular_velocity = Vector3::zeros();
    // Plate normal z: large added mass along z.
    let e = Effect::new(EffectKind::AddedMass, &[0.001, 0.001, 0.1, 0.0, 0.0, 0.0]).unwrap();
    let t = e.wrench(&x).torque;
    // Rotating about +y by the torque's sign moves the normal towards V:
    // for V = (1,0,1) the normal z must rotate towards x, i.e. torque_y > 0
    // would rotate z towards x.
    assert!(t.y > 0.0, "{t:?}");
    assert!(e.added_mass().is_some());
    assert!(Effect::<f64>::unit(EffectKind::Buoyancy, 0)
        .added_mass()
        .is_none());
}

#[test]
fn bad_parameters_are_refused() {
    assert!(Effect::new(EffectKind::Buoyancy, &[1.0, 2.0]).is_none());
    assert!(Effect::new(EffectKind::Buoyancy, &[f64::NAN]).is_none());
}
