//! Pure fixed-step RK4 (§4.3: `s_{k+1} = f(s_k)`).

use crate::math::Real;
use crate::rigid_body::{
    state_rate, state_rate_with_added_mass, Environment, Forces, RigidBody, State, StateRate,
};
use nalgebra::{Quaternion, UnitQuaternion};

/// `s + h ṡ`, with the quaternion advanced in its raw coordinates and
/// re-normalised (a zero quaternion, impossible for finite small steps,
/// falls back to the unadvanced orientation).
fn advance<T: Real>(s: &State<T>, rate: &StateRate<T>, h: T) -> State<T> {
    let raw: Quaternion<T> = s.orientation.quaternion() + rate.orientation * h;
    State {
        position: s.position + rate.position * h,
        orientation: normalise(raw).unwrap_or(s.orientation),
        velocity: s.velocity + rate.velocity * h,
        angular_velocity: s.angular_velocity + rate.angular_velocity * h,
    }
}

fn normalise<T: Real>(q: Quaternion<T>) -> Option<UnitQuaternion<T>> {
    let n = q.coords.dot(&q.coords).root();
    if n > T::zero() && n.finite() {
        Some(UnitQuaternion::new_unchecked(q / n))
    } else {
        None
    }
}

/// One classical RK4 step of length `dt` (s) from time `t` (s).
///
/// Pure: reads the state, returns the next. The orientation quaternion is
/// re-normalised at each stage and at the end.
pub fn rk4_step<T: Real, F: Forces<T>>(
    body: &RigidBody<T>,
    environment: &Environment<T>,
    forces: &F,
    t: T,
    dt: T,
    state: &State<T>,
) -> State<T> {
    let g = &environment.gravity;
    let half = T::of_f64(0.5);
    let added = forces.added_mass();
    let rate = |tt: T, s: &State<T>| {
        let w = forces.wrench(tt, s);
        match &added {
            None => state_rate(body, g, s, &w),
            Some(m) => state_rate_with_added_mass(body, environment, s, &w, m),
        }
    };
    let k1 = rate(t, state);
    let k2 = rate(t + dt * half, &advance(state, &k1, dt * half));
    let k3 = rate(t + dt * half, &advance(state, &k2, dt * half));
    let k4 = rate(t + dt, &advance(state, &k3, dt));
    let sixth = dt / T::of_f64(6.0);
    let two = T::of_f64(2.0);
    let combined = StateRate {
        position: k1.position + (k2.position + k3.position) * two + k4.position,
        orientation: k1.orientation + (k2.orientation + k3.orientation) * two + k4.orientation,
        velocity: k1.velocity + (k2.velocity + k3.velocity) * two + k4.velocity,
        angular_velocity: k1.angular_velocity
            + (k2.angular_velocity + k3.angular_velocity) * two
            + k4.angular_velocity,
    };
    advance(state, &combined, sixth)
}

/// `steps` RK4 steps in place; returns the final time.
pub fn integrate<T: Real, F: Forces<T>>(
    body: &RigidBody<T>,
    environment: &Environment<T>,
    forces: &F,
    t0: T,
    dt: T,
    steps: usize,
    state: &mut State<T>,
) -> T {
    let mut t = t0;
    for _ in 0..steps {
        *state = rk4_step(body, environment, forces, t, dt, state);
        t += dt;
    }
    t
}
