//! Evaluation and many-body RK4 figures with the degree-8 model of
//! [`crate::model`] (shared with the criterion benches).

use crate::model::{lanes, model};
use crate::timer::per_call;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use omniad_core::batch::{rk4_lanes, StateLanes};
use omniad_core::integrate::rk4_step;
use omniad_core::lanes::LANES;
use omniad_core::reference::shape::Shape;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Environment, LaneScalar, RigidBody, State};
use omniad_sim::Bodies;
use std::hint::black_box;
use std::time::Instant;

/// The RK4 step of the many-body figures, s (MuJoCo's peer runs at the
/// same 1/240 s).
pub const DT: f64 = 1.0 / 240.0;
/// Bodies of the one-thread figure (as the MuJoCo peer).
pub const BODIES_ONE_THREAD: usize = 1000;
/// Bodies of the all-cores figure.
pub const BODIES_ALL_CORES: usize = 24_000;

/// The physics figures of one run.
#[derive(Clone, Copy, Debug)]
pub struct Figures {
    /// One f32 evaluation (AVX single-body path), ns.
    pub eval_single_ns: f64,
    /// The f32 batch, per body, ns.
    pub eval_batch_ns: f64,
    /// One f64 evaluation, ns.
    pub eval_single_f64_ns: f64,
    /// The f64 batch, per body, ns.
    pub eval_batch_f64_ns: f64,
    /// One f64 RK4 step of one body by the single-body path, ns.
    pub rk4_single_ns: f64,
    /// f64 batch RK4 body-steps per second on one thread, 1,000 bodies.
    pub body_steps_per_second_per_thread: f64,
    /// f64 batch RK4 body-steps per second on all cores, 24,000 bodies.
    pub body_steps_per_second_all_cores: f64,
    /// Threads used for the all-cores figure.
    pub threads: usize,
    /// The most bodies stepped at 240 Hz in real time on all cores.
    pub bodies_realtime: u64,
}

/// The 30 x 50 x 2 cm, 48 g foam plate (the MuJoCo peer's body):
/// [`Shape::PAPER_PLATE`] as a uniform solid.
pub fn plate() -> RigidBody<f64> {
    let shape = Shape::PAPER_PLATE;
    RigidBody::new(shape.mass, shape.inertia()).unwrap_or(RigidBody {
        mass: 1.0,
        inertia: Matrix3::identity(),
        inverse_inertia: Matrix3::identity(),
    })
}

/// `n` plates tumbling from rest at random attitudes (fixed seed).
pub fn start_states(n: usize) -> Vec<State<f64>> {
    (0..n)
        .map(|i| {
            let f = i as f64;
            let mut s = State::at_rest(Vector3::new(f.sin(), f.cos(), 100.0));
            let axis = Vector3::new(f.cos(), (f * 0.7).sin(), 0.5);
            s.orientation = UnitQuaternion::from_scaled_axis(axis * (f * 0.37 % 3.0));
            s.angular_velocity = Vector3::new(0.3 * f.cos(), 0.2, -0.1 * f.sin());
            s
        })
        .collect()
}

fn eval_ns<T: LaneScalar>(batches: usize) -> (f64, f64) {
    let m = model::<T>();
    let c = |x: f64| T::of_f64(x);
    let (v, w) = (
        Vector3::new(c(0.3), c(-1.2), c(-3.1)),
        Vector3::new(c(0.5), c(0.1), c(-0.7)),
    );
    let single = per_call(batches, 2000, || {
        black_box(m.wrench(black_box(&v), black_box(&w), c(1.2)));
    });
    let (vl, wl) = (
        lanes::<T>([0.3, -1.2, -3.1], 0.05),
        lanes::<T>([0.5, 0.1, -0.7], 0.02),
    );
    let batch = per_call(batches, 250, || {
        black_box(m.wrench_lanes(black_box(&vl), black_box(&wl), c(1.2)));
    });
    (single * 1e9, batch * 1e9 / LANES as f64)
}

/// Measures every physics figure.
pub fn measure(quick: bool) -> Figures {
    let batches = if quick { 200 } else { 2000 };
    let (eval_single_ns, eval_batch_ns) = eval_ns::<f32>(batches);
    let (eval_single_f64_ns, eval_batch_f64_ns) = eval_ns::<f64>(batches);
    let (m, body, env) = (model::<f64>(), plate(), Environment::standard());
    let forces = AirForces {
        model: &m,
        environment: env,
    };
    let s0 = start_states(1)
        .first()
        .copied()
        .unwrap_or(State::at_rest(Vector3::zeros()));
    let rk4_single_ns = 1e9
        * per_call(batches / 4, 200, || {
            black_box(rk4_step(&body, &env, &forces, 0.0, DT, black_box(&s0)));
        });
    // One thread: the lane groups of 1,000 bodies, 20 steps per run.
    let start = start_states(BODIES_ONE_THREAD);
    let mut groups: Vec<StateLanes<f64>> = start
        .chunks(LANES)
        .map(|c| {
            let mut g = StateLanes::splat(&c[0]);
            for (i, s) in c.iter().enumerate() {
                g.set(i, s);
            }
            g
        })
        .collect();
    let steps = 20;
    let per_run = per_call(if quick { 3 } else { 10 }, 1, || {
        rk4_lanes(&m, &body, &env, DT, steps, &mut groups);
    });
    let body_steps_per_second_per_thread = (BODIES_ONE_THREAD * steps) as f64 / per_run;
    // All cores: 24,000 bodies through `omniad-sim`.
    let mut bodies = Bodies::new();
    bodies.load(&start_states(BODIES_ALL_CORES));
    let runs = if quick { 3 } else { 8 };
    let mut best = f64::INFINITY;
    for _ in 0..runs {
        let t = Instant::now();
        bodies.step(&m, &body, &env, DT, 4);
        best = best.min(t.elapsed().as_secs_f64());
    }
    let body_steps_per_second_all_cores = (BODIES_ALL_CORES * 4) as f64 / best;
    Figures {
        eval_single_ns,
        eval_batch_ns,
        eval_single_f64_ns,
        eval_batch_f64_ns,
        rk4_single_ns,
        body_steps_per_second_per_thread,
        body_steps_per_second_all_cores,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        bodies_realtime: (body_steps_per_second_all_cores / 240.0) as u64,
    }
}
