//! The benchmark model and inputs, one definition for the suite and the
//! criterion benches (`core/benches/aero.rs` includes this file by path):
//! a degree-8 model with every coefficient non-zero (the cost does not
//! depend on the values), a 48 g body, a moving state, lane inputs.

use nalgebra::{Matrix3, Vector3};
use omniad_core::lanes::Lanes;
use omniad_core::{Coefficients, LaneScalar, RigidBody, State};

/// A degree-8 model with every coefficient non-zero.
pub fn model<T: LaneScalar>() -> Coefficients<T> {
    let mut m = Coefficients::zeros(8, Vector3::z(), T::of_f64(0.58))
        .expect("degree 8, a unit pole and L > 0 are valid");
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            let v = T::of_f64(((k * 7 + i * 3) % 11) as f64 * 0.01 - 0.05);
            let _ = m.set_alpha(i, k, v);
            let _ = m.set_beta(i, k, v * T::of_f64(0.1));
        }
    }
    let _ = m.set_damping(&(Matrix3::identity() * T::of_f64(0.02)));
    m
}

/// A 48 g body with a plate-like inertia.
pub fn body() -> RigidBody<f64> {
    let inertia = Matrix3::from_diagonal(&Vector3::new(1.0e-3, 3.6e-4, 1.36e-3));
    RigidBody::new(0.048, inertia).expect("positive mass and inertia")
}

/// A body moving and spinning 6 m up.
pub fn moving() -> State<f64> {
    let mut s = State::at_rest(Vector3::new(0.0, 0.0, 6.0));
    s.velocity = Vector3::new(0.2, 0.1, -2.0);
    s.angular_velocity = Vector3::new(1.0, 0.5, -0.3);
    s
}

/// Eight vectors `base + i step` (per component), one per lane.
pub fn lanes<T: LaneScalar>(base: [f64; 3], step: f64) -> [Lanes<T>; 3] {
    base.map(|b| Lanes(std::array::from_fn(|i| T::of_f64(b + step * i as f64))))
}
