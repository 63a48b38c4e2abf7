//! Named effects (`omniad_core::effect`) in models: stored in `.omni` files,
//! added by the air forces, and added mass in the equations of motion.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::file::{decode, encode, MAX_FILE_SIZE};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::{AirForces, Forces};
use omniad_core::{Coefficients, Environment, RigidBody, State};

fn zero_model() -> Coefficients<f64> {
    Coefficients::zeros(4, Vector3::z(), 0.6).unwrap()
}

fn every_effect() -> Vec<Effect<f64>> {
    EffectKind::ALL
        .iter()
        .map(|&k| {
            let p: Vec<f64> = (0..k.param_count())
                .map(|j| 0.01 * (j as f64 + 1.0))
                .collect();
            Effect::new(k, &p).unwrap()
        })
        .collect()
}

#[test]
fn effects_survive_the_file_and_the_cast() {
    let mut m = zero_model();
    for e in every_effect() {
        m.set_effect(e).unwrap();
    }
    assert_eq!(m.effects().len(), EffectKind::ALL.len());
    let mut buf = vec![0u8; MAX_FILE_SIZE];
    let n = encode(&m, &mut buf).unwrap();
    let back = decode::<f64>(&buf[..n]).unwrap();
    for e in every_effect() {
        let got = back.effect(e.kind).expect("stored");
        for (a, b) in got.params.iter().zip(e.params) {
            assert!((a - b).abs() <= 1e-7 * b.abs().max(1e-3), "{:?}", e.kind);
        }
    }
    let f32_model = back.cast::<f32>();
    assert_eq!(f32_model.effects().len(), EffectKind::ALL.len());
}

#[test]
fn setting_an_effect_replaces_it_and_removing_forgets_it() {
    let mut m = zero_model();
    m.set_effect(Effect::new(EffectKind::Buoyancy, &[0.001]).unwrap())
        .unwrap();
    m.set_effect(Effect::new(EffectKind::Buoyancy, &[0.002]).unwrap())
        .unwrap();
    assert_eq!(m.effects().len(), 1);
    assert_eq!(m.extensions().len(), 1);
    let stored = m.effect(EffectKind::Buoyancy).unwrap().params[0];
    assert!(
        (stored - 0.002).abs() < 1e-9,
        "stored as f32, as in the file"
    );
    m.remove_effect(EffectKind::Buoyancy);
    assert!(m.effects().is_empty() && m.extensions().is_empty());
    // A second extension of a named kind added directly is refused.
    let ext = Effect::new(EffectKind::LinearDrag, &[1.0])
        .unwrap()
        .to_extension()
        .unwrap();
    m.add_extension(ext.clone()).unwrap();
    assert!(m.add_extension(ext).is_err(), "one effect of a kind");
}

#[test]
fn air_forces_add_the_stored_effects() {
    let mut m = zero_model();
    m.set_effect(Effect::new(EffectKind::Buoyancy, &[0.003]).unwrap())
        .unwrap();
    let env = Environment::<f64>::standard();
    let air = AirForces {
        model: &m,
        environment: env,
    };
    // Tilted body at rest: buoyancy is still straight up in the world.
    let mut s = State::at_rest(Vector3::new(0.0, 0.0, 5.0));
    s.orientation = UnitQuaternion::from_euler_angles(0.4, -0.2, 1.0);
    let w = air.wrench(0.0, &s);
    let up = s.orientation.transform_vector(&w.force);
    assert!(
        (up - Vector3::new(0.0, 0.0, 1.2 * 0.003 * 9.81)).norm() < 1e-9,
        "{up:?}"
    );
    assert!(air.added_mass().is_none());
}

/// Released at rest with isotropic added mass m_a and no other air force,
/// a body accelerates at `M g / (M + m_a)` (the classic added-mass result),
/// and a model without added mass falls at g.
#[test]
fn added_mass_slows_the_start_of_a_fall() {
    let body = RigidBody::new(0.05, nalgebra::Matrix3::identity() * 1e-4).unwrap();
    let env = Environment::<f64>::standard();
    let start = State::at_rest(Vector3::new(0.0, 0.0, 5.0));
    let dt = 1e-3;
    let fall = |m: &Coefficients<f64>| {
        let air = AirForces {
            model: m,
            environment: env,
        };
        rk4_step(&body, &env, &air, 0.0, dt, &start).velocity.z / dt
    };
    let plain = zero_model();
    assert!((fall(&plain) + 9.81).abs() < 1e-9);
    let mut heavy = zero_model();
    heavy
        .set_effect(Effect::new(EffectKind::AddedMass, &[0.02, 0.02, 0.02, 0.0, 0.0, 0.0]).unwrap())
        .unwrap();
    let expected = -9.81 * 0.05 / (0.05 + 0.02);
    assert!((fall(&heavy) - expected).abs() < 1e-6, "{}", fall(&heavy));
}

/// Anisotropic added mass (a plate, heavy along its normal) released
/// edge-on at 45°: the body accelerates along the direction of least added
/// mass more, so the velocity turns away from straight down towards the
/// plate's plane.
#[test]
fn anisotropic_added_mass_deflects_a_tilted_fall() {
    let body = RigidBody::new(0.05, nalgebra::Matrix3::identity() * 1e-4).unwrap();
    let env = Environment::<f64>::standard();
    let mut m = zero_model();
    m.set_effect(Effect::new(EffectKind::AddedMass, &[0.0, 0.0, 0.1, 0.0, 0.0, 0.0]).unwrap())
        .unwrap();
    let air = AirForces {
        model: &m,
        environment: env,
    };
    let mut s = State::at_rest(Vector3::new(0.0, 0.0, 5.0));
    s.orientation = UnitQuaternion::from_euler_angles(0.0, std::f64::consts::FRAC_PI_4, 0.0);
    let next = rk4_step(&body, &env, &air, 0.0, 1e-3, &s);
    assert!(
        next.velocity.x.abs() > 1e-5,
        "deflected sideways: {:?}",
        next.velocity
    );
    assert!(next.velocity.z < 0.0 && next.velocity.z > -9.81e-3);
}

/// Files written before the effect layout, with a reserved added-mass tag
/// holding a version-1 stand-in payload, still load; the payload is kept
/// and not evaluated.
#[test]
fn the_version_1_golden_file_loads_without_effects() {
    let bytes = include_bytes!("golden/v1.omni");
    let m = decode::<f64>(bytes).unwrap();
    assert!(m.effects().is_empty());
    assert!(m
        .extensions()
        .iter()
        .any(|e| e.kind == EffectKind::AddedMass.extension_kind()));
}
