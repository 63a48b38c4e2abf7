//! Eqs. (1)-(2) and the RK4 step of [`crate::integrate`] for eight bodies
//! at once (one per lane) under one coefficient set, body and environment:
//! the same operations as [`crate::integrate::rk4_step`] with
//! [`crate::rigid_body::AirForces`], lane by lane, so each lane's next
//! state is bit for bit the single-body one (on the portable path).

use super::lane_ops::both;
use super::vec::{
    add3, cross3, div3, mat_vec, quat_mul, rotate, rotate_back, scale3, scale4, splat3, sub3,
};
use super::vec::{Q4, V3};
use super::wrench::{lane, set_lane, WrenchLanes};
use crate::coefficients::Coefficients;
use crate::effect::EffectKind;
use crate::integrate::rk4_step;
use crate::lanes::LANES;
use crate::lanes::{run_wide, LaneScalar, Lanes, SimdKernel};
use crate::math::Real;
use crate::rigid_body::{AirForces, Environment, RigidBody, State};
use nalgebra::{Quaternion, UnitQuaternion};

/// Eight rigid-body states `(y, q, v, Ω)` (§4.3), one per lane, frames and
/// units as [`State`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct StateLanes<T> {
    /// Centre of mass y, world frame, m.
    pub position: V3<T>,
    /// Orientation body -> world, nalgebra order `[i, j, k, w]`.
    pub orientation: Q4<T>,
    /// Velocity v, world frame, m/s.
    pub velocity: V3<T>,
    /// Angular velocity Ω, body frame, rad/s.
    pub angular_velocity: V3<T>,
}

impl<T: Real> StateLanes<T> {
    /// `s` in every lane.
    pub fn splat(s: &State<T>) -> Self {
        let mut out = Self {
            position: splat3(&s.position),
            orientation: super::vec::splat4(s.orientation.quaternion()),
            velocity: splat3(&s.velocity),
            angular_velocity: splat3(&s.angular_velocity),
        };
        out.set(0, s);
        out
    }

    /// Lane `i` (lanes beyond the eight read as zero).
    pub fn get(&self, i: usize) -> State<T> {
        let q = |k: usize| {
            self.orientation
                .get(k)
                .and_then(|l| l.0.get(i))
                .copied()
                .unwrap_or_else(T::zero)
        };
        State {
            position: lane(&self.position, i),
            orientation: UnitQuaternion::new_unchecked(Quaternion::new(q(3), q(0), q(1), q(2))),
            velocity: lane(&self.velocity, i),
            angular_velocity: lane(&self.angular_velocity, i),
        }
    }

    /// Sets lane `i` to `s` (ignored beyond the eight).
    pub fn set(&mut self, i: usize, s: &State<T>) {
        set_lane(&mut self.position, i, &s.position);
        for (l, x) in self.orientation.iter_mut().zip(s.orientation.coords.iter()) {
            if let Some(slot) = l.0.get_mut(i) {
                *slot = *x;
            }
        }
        set_lane(&mut self.velocity, i, &s.velocity);
        set_lane(&mut self.angular_velocity, i, &s.angular_velocity);
    }
}

/// `ṡ` per lane: [`crate::rigid_body::StateRate`].
#[derive(Clone, Copy)]
struct RateLanes<T> {
    position: V3<T>,
    orientation: Q4<T>,
    velocity: V3<T>,
    angular_velocity: V3<T>,
}

/// Eqs. (1)-(2): `M v̇ = M g + R F`, `I Ω̇ = -Ω × I Ω + T`
/// ([`crate::rigid_body::state_rate`]).
#[inline(always)]
fn state_rate<T: Real>(
    body: &RigidBody<T>,
    g: &V3<T>,
    s: &StateLanes<T>,
    w: &WrenchLanes<T>,
) -> RateLanes<T> {
    let omega = s.angular_velocity;
    let [ox, oy, oz] = omega;
    let omega_q = [ox, oy, oz, Lanes::splat(T::zero())];
    let accel = add3(
        g,
        &div3(&rotate(&s.orientation, &w.force), Lanes::splat(body.mass)),
    );
    let i_omega = mat_vec(&body.inertia, &omega);
    let alpha = mat_vec(
        &body.inverse_inertia,
        &sub3(&w.torque, &cross3(&omega, &i_omega)),
    );
    let half = Lanes::splat(T::of_f64(0.5));
    RateLanes {
        position: s.velocity,
        orientation: scale4(&quat_mul(&s.orientation, &omega_q), half),
        velocity: accel,
        angular_velocity: alpha,
    }
}

/// `s + h ṡ` with the quaternion re-normalised, falling back to the
/// unadvanced orientation where that fails ([`crate::integrate`]'s
/// `advance`).
#[inline(always)]
fn advance<T: Real>(s: &StateLanes<T>, r: &RateLanes<T>, h: T) -> StateLanes<T> {
    let h = Lanes::splat(h);
    let mut raw = s.orientation;
    for (q, d) in raw.iter_mut().zip(&r.orientation) {
        *q = *q + *d * h;
    }
    // nalgebra's 4-vector dot: (i² + k²) + (j² + w²).
    let [i, j, k, w] = raw;
    let n = (i * i + k * k + (j * j + w * w)).root();
    let ok = both(&n.above(T::zero()), &n.finite());
    let mut orientation = s.orientation;
    for (o, q) in orientation.iter_mut().zip(raw) {
        *o = (q / n).select(&ok, *o);
    }
    StateLanes {
        position: add3(&s.position, &scale3(&r.position, h)),
        orientation,
        velocity: add3(&s.velocity, &scale3(&r.velocity, h)),
        angular_velocity: add3(&s.angular_velocity, &scale3(&r.angular_velocity, h)),
    }
}

/// `a + (b + c) 2 + d`: RK4's weighted sum, in the single-body order.
#[inline(always)]
fn sum3<T: Real>(a: &V3<T>, b: &V3<T>, c: &V3<T>, d: &V3<T>, two: Lanes<T>) -> V3<T> {
    add3(&add3(a, &scale3(&add3(b, c), two)), d)
}

/// What one RK4 stage needs besides the state.
struct Scene<'a, T: LaneScalar> {
    model: &'a Coefficients<T>,
    body: &'a RigidBody<T>,
    environment: &'a Environment<T>,
}

impl<T: LaneScalar> Scene<'_, T> {
    /// `ṡ` under gravity and the air ([`crate::rigid_body::AirForces`]).
    #[inline(always)]
    fn rate(&self, s: &StateLanes<T>) -> RateLanes<T> {
        let env = self.environment;
        let g = splat3(&env.gravity);
        let v = rotate_back(&s.orientation, &sub3(&s.velocity, &splat3(&env.wind)));
        let g_body = rotate_back(&s.orientation, &g);
        let w =
            self.model
                .wrench_lanes_inline(&v, &s.angular_velocity, Some(&g_body), env.air_density);
        state_rate(self.body, &g, s, &w)
    }

    /// One classical RK4 step ([`crate::integrate::rk4_step`]).
    #[inline(always)]
    fn step(&self, dt: T, s: &StateLanes<T>) -> StateLanes<T> {
        let half = T::of_f64(0.5);
        let k1 = self.rate(s);
        let k2 = self.rate(&advance(s, &k1, dt * half));
        let k3 = self.rate(&advance(s, &k2, dt * half));
        let k4 = self.rate(&advance(s, &k3, dt));
        let two = Lanes::splat(T::of_f64(2.0));
        let mut orientation = k1.orientation;
        for (((o, b), c), d) in orientation
            .iter_mut()
            .zip(k2.orientation)
            .zip(k3.orientation)
            .zip(k4.orientation)
        {
            *o = *o + (b + c) * two + d;
        }
        let combined = RateLanes {
            position: sum3(&k1.position, &k2.position, &k3.position, &k4.position, two),
            orientation,
            velocity: sum3(&k1.velocity, &k2.velocity, &k3.velocity, &k4.velocity, two),
            angular_velocity: sum3(
                &k1.angular_velocity,
                &k2.angular_velocity,
                &k3.angular_velocity,
                &k4.angular_velocity,
                two,
            ),
        };
        advance(s, &combined, dt / T::of_f64(6.0))
    }
}

/// `steps` RK4 steps of length `dt` (s) in place for every block of eight
/// bodies in `states`, under the air model `model` (eqs. 5-6 and its
/// extensions) in `environment`, all bodies of mass properties `body`.
/// The air model does not depend on time, so no clock is passed. Runs
/// compiled with AVX where the machine has it; each lane's result is bit
/// for bit that of [`crate::integrate::rk4_step`] with
/// [`crate::rigid_body::AirForces`] on the portable path.
pub fn rk4_lanes<T: LaneScalar>(
    model: &Coefficients<T>,
    body: &RigidBody<T>,
    environment: &Environment<T>,
    dt: T,
    steps: usize,
    states: &mut [StateLanes<T>],
) {
    run_wide(&Rk4Kernel {
        scene: Scene {
            model,
            body,
            environment,
        },
        dt,
        steps,
        states: core::cell::RefCell::new(states),
    });
}

/// [`rk4_lanes`] as a [`SimdKernel`] (the states are mutated through the
/// cell: `SimdKernel::run` takes `&self`).
struct Rk4Kernel<'a, 's, T: LaneScalar> {
    scene: Scene<'a, T>,
    dt: T,
    steps: usize,
    states: core::cell::RefCell<&'s mut [StateLanes<T>]>,
}

impl<T: LaneScalar> SimdKernel for Rk4Kernel<'_, '_, T> {
    type Output = ();
    #[inline(always)]
    fn run(&self) {
        let Ok(mut states) = self.states.try_borrow_mut() else {
            return;
        };
        let scene = &self.scene;
        if scene.model.effect(EffectKind::AddedMass).is_some() {
            // Added mass changes the equations of motion: each lane through
            // the single-body step, which carries it.
            let air = AirForces {
                model: scene.model,
                environment: *scene.environment,
            };
            for s in states.iter_mut() {
                for i in 0..LANES {
                    let mut one = s.get(i);
                    for k in 0..self.steps {
                        let t = T::of_f64(k as f64) * self.dt;
                        one = rk4_step(scene.body, scene.environment, &air, t, self.dt, &one);
                    }
                    s.set(i, &one);
                }
            }
            return;
        }
        for s in states.iter_mut() {
            for _ in 0..self.steps {
                *s = scene.step(self.dt, s);
            }
        }
    }
}
