//! The filter's process model f(s) (§4.3, §5): one RK4 step of eqs. (1)-(2)
//! with the OmniAD air model (eqs. 5-6) plus the random-walk bias wrench of
//! [`FilterState`], its Jacobian in error-state coordinates, and the
//! process noise. A model with added mass steps the equations of motion
//! with the air's mass on the mass side
//! ([`omniad_core::rigid_body::state_rate_with_added_mass`]); a wind in
//! [`Process::environment`] makes the air velocity `Rᵀ(v - w)`.

use crate::reconstruct::state::{boxminus, boxplus, Cov, Delta, FilterState, N};
use nalgebra::{Matrix3, SMatrix, Vector3};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::Forces;
use omniad_core::{Coefficients, Environment, RigidBody, State, Wrench};

/// Step of the finite-difference process Jacobian (error-state units).
const FD_STEP: f64 = 1e-6;

/// The physics the filter predicts with.
pub struct Process<'a> {
    /// Mass properties.
    pub body: RigidBody<f64>,
    /// Gravity, air density, wind.
    pub environment: Environment<f64>,
    /// Current OmniAD model (zero in the first refinement iteration, §6).
    pub model: &'a Coefficients<f64>,
    /// Per-step white acceleration noise, 1 sigma per world axis, m/s².
    pub accel_noise: f64,
    /// Per-step white angular acceleration noise, 1 sigma per body axis, rad/s².
    pub angular_accel_noise: f64,
    /// Bias force random walk, 1 sigma per body axis per √s, N/√s.
    pub force_walk: f64,
    /// Bias torque random walk, 1 sigma per body axis per √s, N m/√s.
    pub torque_walk: f64,
    /// Correlation time of the bias, s: the bias is a first-order
    /// Gauss-Markov process that decays as `exp(-dt/τ_b)` with stationary
    /// RMS `walk·sqrt(τ_b/2)`; `f64::INFINITY` makes it a random walk.
    pub bias_time: f64,
    /// Angle (rad) the air's direction `E` must turn through in the body
    /// frame for the unexplained TORQUE to decorrelate: its correlation
    /// time is state-dependent, `1/τ_T = 1/τ_b + |Ω × E|/θ_T` (see
    /// [`Self::torque_bias_time`]); `f64::INFINITY`: `τ_T = τ_b`.
    pub torque_turn: f64,
}

/// The OmniAD wrench plus a constant body-frame bias.
struct Biased<'a> {
    model: &'a Coefficients<f64>,
    environment: Environment<f64>,
    force: Vector3<f64>,
    torque: Vector3<f64>,
}

impl Forces<f64> for Biased<'_> {
    fn wrench(&self, _t: f64, s: &State<f64>) -> Wrench<f64> {
        // The model's own wrench and extensions (gravity coupling included).
        let w = omniad_core::rigid_body::AirForces {
            model: self.model,
            environment: self.environment,
        }
        .wrench(0.0, s);
        Wrench {
            force: w.force + self.force,
            torque: w.torque + self.torque,
        }
    }

    /// The model's added mass M_a (kg, body frame), if it has one: the
    /// RK4 step then solves `(M I + M_a) dU/dt = ...` (the bias is a force
    /// like any other on the right-hand side).
    fn added_mass(&self) -> Option<Matrix3<f64>> {
        self.model
            .effect(omniad_core::effect::EffectKind::AddedMass)
            .and_then(|e| e.added_mass())
    }
}

impl Process<'_> {
    /// `s_{k+1} = f(s_k)` over `dt` seconds (the bias is held through the
    /// step, then decays by `exp(-dt/τ_b)`, see [`Self::bias_time`]).
    pub fn step(&self, s: &FilterState, dt: f64) -> FilterState {
        let forces = Biased {
            model: self.model,
            environment: self.environment,
            force: s.force,
            torque: s.torque,
        };
        FilterState {
            body: rk4_step(&self.body, &self.environment, &forces, 0.0, dt, &s.body),
            force: s.force * decay(self.bias_time, dt),
            torque: s.torque * decay(self.torque_bias_time(s), dt),
        }
    }

    /// Correlation time (s) of the unexplained torque at state `s`:
    /// `1/τ_T = 1/τ_b + |Ω × E|/θ_T` ([`Self::torque_turn`]; `E` the
    /// body-frame direction of the air velocity `V = Rᵀ(v - w)`, `Ω` the
    /// body rate, rad/s; `|Ω|` when `V = 0`). Why: once a model is fitted,
    /// the unexplained torque is the model's error, a function of the state,
    /// mostly of `E` (eq. 8's `Σ_lm β_lm Y_lm(E)`); along a trajectory it
    /// changes as `E` turns, and `dE/dt = -Ω × E` (body frame), so a
    /// spinning body sweeps the error field at `|Ω × E|` rad/s and its
    /// unexplained torque decorrelates in `θ_T/|Ω × E|` seconds, however
    /// slowly the air's wrench changes at rest (`τ_b`). A fixed `τ_b`
    /// makes the bias too slow to follow it at high spin, so the smoother's
    /// `dΩ/dt` follows the model there (BENCHMARKS.md issue 20, stop 18).
    /// A random-walk bias (no model yet) stays one.
    pub fn torque_bias_time(&self, s: &FilterState) -> f64 {
        if !(self.bias_time.is_finite() && self.bias_time > 0.0) {
            return self.bias_time;
        }
        let omega = s.body.angular_velocity;
        let v = s.body.air_velocity_body(&self.environment.wind);
        let sweep = v
            .try_normalize(0.0)
            .map_or(omega.norm(), |e| omega.cross(&e).norm());
        let rate = 1.0 / self.bias_time + sweep / self.torque_turn;
        if rate.is_finite() && rate > 0.0 {
            1.0 / rate
        } else {
            self.bias_time
        }
    }

    /// The next state and the error-state Jacobian `F = ∂(f(s ⊕ δ) ⊖ f(s))/∂δ`
    /// by forward differences (numerical: f is an RK4 step).
    pub fn step_with_jacobian(&self, s: &FilterState, dt: f64) -> (FilterState, Cov) {
        let next = self.step(s, dt);
        let mut f = Cov::zeros();
        for j in 0..N {
            let mut d = Delta::zeros();
            d[j] = FD_STEP;
            let col = boxminus(&self.step(&boxplus(s, &d), dt), &next) / FD_STEP;
            f.set_column(j, &col);
        }
        (next, f)
    }

    /// Discrete process noise for a step of `dt` s from state `s`:
    /// piecewise-constant white acceleration (`σ² G Gᵀ`, `G = [dt²/2, dt]`)
    /// and the bias's driving noise ([`bias_variance`]; the torque's with
    /// its state-dependent correlation time, [`Self::torque_bias_time`],
    /// and the same stationary RMS `walk·sqrt(τ_b/2)`).
    pub fn noise(&self, s: &FilterState, dt: f64) -> Cov {
        let mut q = Cov::zeros();
        let i3 = Matrix3::<f64>::identity();
        let g = SMatrix::<f64, 2, 1>::new(0.5 * dt * dt, dt);
        let gg = g * g.transpose();
        for (pos, vel, sigma) in [(0, 6, self.accel_noise), (3, 9, self.angular_accel_noise)] {
            let s2 = sigma * sigma;
            for (a, ia) in [(0, pos), (1, vel)] {
                for (b, ib) in [(0, pos), (1, vel)] {
                    q.fixed_view_mut::<3, 3>(ia, ib)
                        .copy_from(&(i3 * (gg[(a, b)] * s2)));
                }
            }
        }
        let v = bias_variance(self.bias_time, self.bias_time, dt);
        q.fixed_view_mut::<3, 3>(12, 12)
            .copy_from(&(i3 * (self.force_walk.powi(2) * v)));
        let v = bias_variance(self.bias_time, self.torque_bias_time(s), dt);
        q.fixed_view_mut::<3, 3>(15, 15)
            .copy_from(&(i3 * (self.torque_walk.powi(2) * v)));
        q
    }
}

/// A bias's decay over `dt` with correlation time `tau`, `exp(-dt/τ)` (1
/// for a random walk, `τ` infinite).
fn decay(tau: f64, dt: f64) -> f64 {
    if tau.is_finite() && tau > 0.0 {
        (-dt / tau).exp()
    } else {
        1.0
    }
}

/// Variance added to a bias over `dt` per unit walk², the walk being that
/// of correlation time `tau_b` and the bias decaying with `tau`: `dt` for a
/// random walk, `τ_b (1 - exp(-2 dt/τ)) / 2` for a Gauss-Markov bias (its
/// stationary variance `walk² τ_b/2` whatever `τ`; the same as `walk² dt`
/// to first order in `dt` when `τ = τ_b`).
fn bias_variance(tau_b: f64, tau: f64, dt: f64) -> f64 {
    let d = decay(tau, dt);
    if d < 1.0 {
        0.5 * tau_b * (1.0 - d * d)
    } else {
        dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::recording::Object;
    use nalgebra::UnitQuaternion;

    /// A markerless 50 g object of 0.3 m.
    fn object(name: &str) -> Object {
        Object {
            name: name.into(),
            mass: 0.05,
            inertia: Matrix3::identity() * 1e-3,
            reference_length: 0.3,
            pole: Vector3::z(),
            markers: Vec::new(),
        }
    }

    fn process(model: &Coefficients<f64>, bias_time: f64) -> Process<'_> {
        Process {
            body: RigidBody::new(0.05, Matrix3::identity() * 1e-3).expect("body"),
            environment: Environment::standard(),
            model,
            accel_noise: 1.0,
            angular_accel_noise: 1.0,
            force_walk: 0.2,
            torque_walk: 0.02,
            bias_time,
            torque_turn: f64::INFINITY,
        }
    }

    #[test]
    fn gauss_markov_bias_decays_to_its_stationary_variance() {
        let object = object("cube");
        let model = crate::fit::model::zero_model(&object, 2).expect("model");
        let (dt, tau) = (0.01, 0.5);
        let walk = process(&model, f64::INFINITY);
        let gm = process(&model, tau);
        let mut s = FilterState::new(State {
            position: Vector3::zeros(),
            orientation: UnitQuaternion::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
        });
        s.force = Vector3::new(1.0, 0.0, 0.0);
        assert_eq!(walk.step(&s, dt).force, s.force);
        let decayed = gm.step(&s, dt).force.x;
        assert!((decayed - (-dt / tau).exp()).abs() < 1e-12);
        // Random walk: walk² dt per step; Gauss-Markov: the same to first
        // order, and the variance tends to walk² τ/2.
        assert!((walk.noise(&s, dt)[(12, 12)] - 0.04 * dt).abs() < 1e-15);
        assert!((gm.noise(&s, dt)[(12, 12)] / (0.04 * dt) - 1.0).abs() < 0.03);
        let (mut v, d2) = (0.0, (-2.0 * dt / tau).exp());
        for _ in 0..2000 {
            v = d2 * v + gm.noise(&s, dt)[(12, 12)];
        }
        assert!((v / (0.04 * tau / 2.0) - 1.0).abs() < 1e-6);
    }

    /// The unexplained torque's correlation time shrinks with the rate
    /// `|Ω × E|` at which the air's direction turns in the body frame (a
    /// spin about `E` does not turn it), its stationary variance is kept,
    /// and a random walk or `torque_turn = ∞` is left as it was.
    #[test]
    fn torque_bias_time_follows_the_sweep_of_the_air_direction() {
        let object = object("cube");
        let model = crate::fit::model::zero_model(&object, 2).expect("model");
        let (dt, tau) = (0.01, 0.5);
        let mut p = process(&model, tau);
        p.torque_turn = 2.0;
        let state = |w: Vector3<f64>| {
            FilterState::new(State {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
                velocity: Vector3::new(0.0, 0.0, -3.0),
                angular_velocity: w,
            })
        };
        let about_e = state(Vector3::new(0.0, 0.0, 10.0));
        let across = state(Vector3::new(10.0, 0.0, 0.0));
        assert!((p.torque_bias_time(&about_e) - tau).abs() < 1e-12);
        // 1/τ_T = 1/0.5 + 10/2 = 7 per second.
        assert!((p.torque_bias_time(&across) - 1.0 / 7.0).abs() < 1e-12);
        // The force's bias is untouched; the torque decays faster.
        let mut s = across;
        s.force = Vector3::x();
        s.torque = Vector3::x();
        let next = p.step(&s, dt);
        assert!((next.force.x - (-dt / tau).exp()).abs() < 1e-12);
        assert!((next.torque.x - (-7.0 * dt).exp()).abs() < 1e-12);
        // Stationary variance walk² τ_b / 2 whatever the sweep.
        let (mut v, d2) = (0.0, (-14.0 * dt).exp());
        for _ in 0..2000 {
            v = d2 * v + p.noise(&across, dt)[(15, 15)];
        }
        assert!((v / (0.02f64.powi(2) * tau / 2.0) - 1.0).abs() < 1e-6);
        // Off: the same as the force's.
        p.torque_turn = f64::INFINITY;
        assert!((p.torque_bias_time(&across) - tau).abs() < 1e-12);
        let walk = process(&model, f64::INFINITY);
        assert!(walk.torque_bias_time(&across).is_infinite());
    }

    /// A model with added mass: the step puts M_a on the mass side (a
    /// body at rest falls with `M g / (M + m_zz)` along z), and the
    /// forward-difference Jacobian agrees with central differences.
    #[test]
    fn added_mass_step_and_jacobian() {
        use crate::reconstruct::state::{boxminus, boxplus, Delta};
        use omniad_core::effect::{Effect, EffectKind};
        let object = object("plate");
        let mut model = crate::fit::model::zero_model(&object, 2).expect("model");
        let m_zz = 0.02;
        let am = Effect::new(
            EffectKind::AddedMass,
            &[0.002, 0.001, m_zz, 0.0005, 0.0, 0.0],
        )
        .expect("effect");
        model.set_effect(am).expect("added mass");
        let p = process(&model, f64::INFINITY);
        let dt = 0.01;
        let rest = FilterState::new(State::at_rest(Vector3::zeros()));
        let fall = p.step(&rest, dt).body.velocity.z;
        let g = p.environment.gravity.z;
        let expected = g * dt * 0.05 / (0.05 + m_zz);
        assert!((fall - expected).abs() < 1e-9, "{fall} vs {expected}");
        let s = FilterState::new(State {
            position: Vector3::new(0.1, 0.2, 1.0),
            orientation: UnitQuaternion::from_euler_angles(0.3, -0.5, 1.2),
            velocity: Vector3::new(1.5, -0.5, -3.0),
            angular_velocity: Vector3::new(4.0, -2.0, 6.0),
        });
        let (next, f) = p.step_with_jacobian(&s, dt);
        for j in 0..N {
            let mut d = Delta::zeros();
            d[j] = 1e-5;
            let a = boxminus(&p.step(&boxplus(&s, &d), dt), &next);
            d[j] = -1e-5;
            let b = boxminus(&p.step(&boxplus(&s, &d), dt), &next);
            let fd = (a - b) / 2e-5;
            assert!(
                (fd - f.column(j)).norm() < 1e-4 * (1.0 + fd.norm()),
                "column {j}: {fd} vs {}",
                f.column(j)
            );
        }
        // The added mass changes the Jacobian (a no-op would pass above).
        let plain = crate::fit::model::zero_model(&object, 2).expect("model");
        let (_, f0) = process(&plain, f64::INFINITY).step_with_jacobian(&s, dt);
        assert!((f - f0).norm() > 1e-3);
    }
}
