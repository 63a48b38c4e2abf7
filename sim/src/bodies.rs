//! [`Bodies`]: independent bodies in lane groups of eight, stepped on all
//! cores.
//!
//! Why lane groups: the core's batch RK4 ([`rk4_lanes`]) runs eight
//! bodies per vector register; every body is independent, so work is cut
//! at lane-group boundaries and each group's result is the same whichever
//! thread computes it (bit for bit, for any thread count; tested), and bit
//! for bit [`omniad_core::integrate::rk4_step`] on the portable path.

use omniad_core::batch::{rk4_lanes, StateLanes};
use omniad_core::lanes::LANES;
use omniad_core::{Coefficients, Environment, LaneScalar, RigidBody, State};
use rayon::prelude::*;

/// Lane groups per parallel task: large enough that scheduling costs
/// nothing next to the RK4 steps (a group-step is a few µs), small enough
/// to balance 10,000 bodies over the cores.
const GROUPS_PER_TASK: usize = 16;

/// The states of `len` bodies, eight per lane group; lanes past `len` hold
/// a body at rest (stepped, never read).
#[derive(Clone, Debug, Default)]
pub struct Bodies<T: LaneScalar> {
    groups: Vec<StateLanes<T>>,
    len: usize,
}

impl<T: LaneScalar> Bodies<T> {
    /// No bodies.
    pub fn new() -> Self {
        Self {
            groups: Vec::new(),
            len: 0,
        }
    }

    /// The bodies `states`, in order (the buffers grow only when the count
    /// does).
    pub fn load(&mut self, states: &[State<T>]) {
        let rest = StateLanes::splat(&State::at_rest(nalgebra::Vector3::zeros()));
        self.groups.resize(states.len().div_ceil(LANES), rest);
        for (group, chunk) in self.groups.iter_mut().zip(states.chunks(LANES)) {
            *group = rest;
            for (i, s) in chunk.iter().enumerate() {
                group.set(i, s);
            }
        }
        self.len = states.len();
    }

    /// Writes the states into `out` (the first `min(len, out.len())`).
    pub fn store(&self, out: &mut [State<T>]) {
        for (i, o) in out.iter_mut().take(self.len).enumerate() {
            if let Some(g) = self.groups.get(i / LANES) {
                *o = g.get(i % LANES);
            }
        }
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<T: LaneScalar + Send + Sync> Bodies<T>
where
    Coefficients<T>: Sync,
{
    /// `steps` RK4 steps of `dt` (s) of every body under the air model
    /// `model` in `environment`, each of mass properties `body`, on all
    /// cores (rayon's pool). Allocates nothing.
    pub fn step(
        &mut self,
        model: &Coefficients<T>,
        body: &RigidBody<T>,
        environment: &Environment<T>,
        dt: T,
        steps: usize,
    ) {
        self.groups
            .par_chunks_mut(GROUPS_PER_TASK)
            .for_each(|part| rk4_lanes(model, body, environment, dt, steps, part));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
    use omniad_core::integrate::rk4_step;
    use omniad_core::rigid_body::AirForces;

    fn model() -> Coefficients<f64> {
        let mut m = Coefficients::zeros(8, Vector3::z(), 0.58).unwrap();
        for k in 0..m.coeff_count() {
            for i in 0..3 {
                let v = ((k * 7 + i * 3) % 11) as f64 * 0.01 - 0.05;
                m.set_alpha(i, k, v).unwrap();
                m.set_beta(i, k, v * 0.1).unwrap();
            }
        }
        m.set_damping(&(Matrix3::identity() * 0.02)).unwrap();
        m
    }

    fn states(n: usize) -> Vec<State<f64>> {
        (0..n)
            .map(|i| {
                let f = i as f64;
                let mut s = State::at_rest(Vector3::new(f.sin(), f.cos(), 5.0 + f * 0.01));
                let q = Quaternion::new(f.cos(), 0.3, f.sin(), -0.2);
                s.orientation = UnitQuaternion::from_quaternion(q);
                s.velocity = Vector3::new(0.1 * f.cos(), 0.0, -0.5);
                s.angular_velocity = Vector3::new(0.2, -0.1 * f.sin(), 0.3);
                s
            })
            .collect()
    }

    fn run(threads: usize, start: &[State<f64>]) -> Vec<State<f64>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let body = RigidBody::new(
            0.048,
            Matrix3::from_diagonal(&Vector3::new(1e-3, 3.6e-4, 1.36e-3)),
        )
        .unwrap();
        let (m, env) = (model(), Environment::standard());
        let mut b = Bodies::new();
        b.load(start);
        pool.install(|| b.step(&m, &body, &env, 1.0 / 240.0, 40));
        let mut out = start.to_vec();
        b.store(&mut out);
        out
    }

    fn bits(s: &[State<f64>]) -> Vec<u64> {
        s.iter()
            .flat_map(|s| {
                let q = s.orientation.coords;
                [s.position, s.velocity, s.angular_velocity]
                    .into_iter()
                    .flat_map(|v| [v.x, v.y, v.z])
                    .chain(q.iter().copied())
                    .collect::<Vec<_>>()
            })
            .map(f64::to_bits)
            .collect()
    }

    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let start = states(1003);
        let one = bits(&run(1, &start));
        assert_eq!(one, bits(&run(2, &start)));
        assert_eq!(one, bits(&run(5, &start)));
    }

    #[test]
    fn each_body_steps_as_the_single_body_rk4() {
        let start = states(19);
        let got = run(2, &start);
        let body = RigidBody::new(
            0.048,
            Matrix3::from_diagonal(&Vector3::new(1e-3, 3.6e-4, 1.36e-3)),
        )
        .unwrap();
        let (m, env) = (model(), Environment::standard());
        let forces = AirForces {
            model: &m,
            environment: env,
        };
        let want: Vec<State<f64>> = start
            .iter()
            .map(|s| {
                let mut s = *s;
                for _ in 0..40 {
                    s = rk4_step(&body, &env, &forces, 0.0, 1.0 / 240.0, &s);
                }
                s
            })
            .collect();
        assert_eq!(bits(&got), bits(&want));
    }
}
