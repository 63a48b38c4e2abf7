//! Rigid-body dynamics, eqs. (1)-(2), and the RK4 integrator.
#![allow(clippy::unwrap_used)]

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use omniad_core::integrate::{integrate, rk4_step};
use omniad_core::rigid_body::{AirForces, NoForces};
use omniad_core::{Coefficients, Environment, RigidBody, State};

fn asymmetric_body() -> RigidBody<f64> {
    RigidBody::new(
        0.05,
        Matrix3::new(1.0e-3, 1.0e-4, 0.0, 1.0e-4, 2.0e-3, 0.0, 0.0, 0.0, 3.5e-3),
    )
    .unwrap()
}

fn spinning_state() -> State<f64> {
    State {
        position: Vector3::new(1.0, -2.0, 6.0),
        orientation: UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
        velocity: Vector3::new(0.5, 0.25, 3.0),
        angular_velocity: Vector3::new(2.0, -3.0, 1.5),
    }
}

#[test]
fn vacuum_free_fall_is_exact_to_rounding() {
    let body = asymmetric_body();
    let env = Environment::vacuum();
    let mut s = spinning_state();
    let s0 = s;
    let (dt, steps) = (0.01, 200);
    let t = integrate(&body, &env, &NoForces, 0.0, dt, steps, &mut s);
    let want = s0.position + s0.velocity * t + env.gravity * (0.5 * t * t);
    assert!(
        (s.position - want).norm() < 1e-12,
        "{:?} vs {want:?}",
        s.position
    );
    assert!((s.velocity - (s0.velocity + env.gravity * t)).norm() < 1e-12);
}

#[test]
fn torque_free_body_conserves_energy_and_angular_momentum() {
    let body = asymmetric_body();
    let env = Environment {
        gravity: Vector3::zeros(),
        ..Environment::vacuum()
    };
    let mut s = spinning_state();
    let e0 = s.kinetic_energy(&body);
    let l0 = s.angular_momentum_world(&body);
    integrate(&body, &env, &NoForces, 0.0, 1e-3, 10_000, &mut s);
    let de = (s.kinetic_energy(&body) - e0).abs() / e0;
    let dl = (s.angular_momentum_world(&body) - l0).norm() / l0.norm();
    assert!(de <= 1e-9, "energy drift {de:e}");
    assert!(dl <= 1e-9, "angular momentum drift {dl:e}");
    assert!((s.orientation.quaternion().norm() - 1.0).abs() < 1e-14);
}

/// Error of the torque-free state at t = 1 s against a fine reference.
fn error_at(dt: f64, reference: &State<f64>) -> f64 {
    let body = asymmetric_body();
    let env = Environment::vacuum();
    let mut s = spinning_state();
    integrate(
        &body,
        &env,
        &NoForces,
        0.0,
        dt,
        (1.0 / dt).round() as usize,
        &mut s,
    );
    (s.angular_velocity - reference.angular_velocity).norm()
        + s.orientation.angle_to(&reference.orientation)
}

#[test]
fn rk4_converges_at_fourth_order() {
    let body = asymmetric_body();
    let mut reference = spinning_state();
    integrate(
        &body,
        &Environment::vacuum(),
        &NoForces,
        0.0,
        1e-4,
        10_000,
        &mut reference,
    );
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&dt| error_at(dt, &reference))
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!(
            (3.6..=4.4).contains(&order),
            "observed order {order} from errors {errors:?}"
        );
    }
}

#[test]
fn air_never_adds_energy_to_a_falling_isotropic_body() {
    // Isotropic drag (C_F = -E) and damping: mechanical energy only decreases.
    let mut m = Coefficients::<f64>::zeros(0, Vector3::z(), 0.5).unwrap();
    m.set_alpha(0, 0, -(4.0 * std::f64::consts::PI).sqrt())
        .unwrap();
    m.set_damping(&(Matrix3::identity() * 0.05)).unwrap();
    let body = asymmetric_body();
    let env = Environment::standard();
    let forces = AirForces {
        model: &m,
        environment: env,
    };
    let mut s = spinning_state();
    let energy =
        |s: &State<f64>| s.kinetic_energy(&body) - body.mass * env.gravity.dot(&s.position);
    let mut previous = energy(&s);
    for k in 0..2000 {
        s = rk4_step(&body, &env, &forces, k as f64 * 1e-3, 1e-3, &s);
        let e = energy(&s);
        assert!(e <= previous + 1e-12, "energy rose at step {k}");
        previous = e;
    }
    assert!(s.is_finite());
}
