//! Many bodies falling through air (paper Fig. 14): one air model (a
//! coefficient set, or a comparison model of Fig. 12 on the same body),
//! with air density ρ, size L and mass/inertia scale adjustable live.

use crate::models::Model;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use omniad_core::integrate::rk4_step;
use omniad_core::model::{Model as AirModel, ModelKind};
use omniad_core::reference::shape::Shape;
use omniad_core::{Coefficients, Environment, RigidBody, State};
use omniad_sim::Bodies;

/// Spawn box half-width (x, y), m.
pub const HALF_WIDTH: f64 = 2.0;
/// Spawn height range, m.
pub const SPAWN_Z: (f64, f64) = (4.0, 9.0);
/// Physics step, s.
pub const DT: f64 = 1.0 / 120.0;
/// Physics steps per displayed frame (1/30 s of simulated time).
pub const STEPS_PER_FRAME: usize = 4;
/// Fewest bodies a thread steps under a comparison model: below this a
/// thread's start costs more than its bodies (a per-element model's frame
/// is about 30-100 µs per body).
const MIN_BODIES_PER_THREAD: usize = 16;

/// The Fig. 14 controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Air density ρ, kg/m³.
    pub air_density: f64,
    /// Size factor applied to the model's reference length L.
    pub size: f64,
    /// Scale of mass and inertia.
    pub mass_scale: f64,
}

impl Params {
    /// Standard gravity, no wind, and the chosen air density.
    pub fn environment(&self) -> Environment<f64> {
        Environment {
            air_density: self.air_density,
            ..Environment::standard()
        }
    }
}

impl Default for Params {
    fn default() -> Self {
        Self {
            air_density: 1.2,
            size: 1.0,
            mass_scale: 1.0,
        }
    }
}

/// The falling bodies and their random source (deterministic seed).
#[derive(Clone, Debug)]
pub struct World {
    /// Body states (world frame, z up).
    pub bodies: Vec<State<f64>>,
    /// Simulated time, s.
    pub time: f64,
    /// Bodies that reached the ground and were re-spawned.
    pub landed: u64,
    rng: u64,
    /// The states in the batch layout while a frame is stepped (buffers
    /// kept between frames: no allocation per frame).
    lanes: Bodies<f64>,
}

/// splitmix64: small, fast, reproducible.
fn next(rng: &mut u64) -> f64 {
    *rng = rng.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *rng;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

impl World {
    /// `count` bodies spread over the spawn box, from seed `seed`.
    pub fn new(count: usize, seed: u64) -> Self {
        let mut w = Self {
            bodies: Vec::new(),
            time: 0.0,
            landed: 0,
            rng: seed,
            lanes: Bodies::new(),
        };
        w.resize(count);
        w
    }

    /// Adds or removes bodies to reach `count`.
    pub fn resize(&mut self, count: usize) {
        self.bodies.truncate(count);
        while self.bodies.len() < count {
            let z = SPAWN_Z.0 + (SPAWN_Z.1 - SPAWN_Z.0) * next(&mut self.rng);
            let s = self.spawn(z);
            self.bodies.push(s);
        }
    }

    fn spawn(&mut self, z: f64) -> State<f64> {
        let mut u = || next(&mut self.rng);
        let pos = Vector3::new(
            (2.0 * u() - 1.0) * HALF_WIDTH,
            (2.0 * u() - 1.0) * HALF_WIDTH,
            z,
        );
        let q = Quaternion::new(u() - 0.5, u() - 0.5, u() - 0.5, u() - 0.5);
        let mut s = State::at_rest(pos);
        s.orientation = UnitQuaternion::try_new(q, 1e-9).unwrap_or_else(UnitQuaternion::identity);
        s
    }

    /// Advances one displayed frame with `model` under `params`: the
    /// bodies are stepped by the batch RK4 of `omniad-sim` on all cores
    /// (independent, so the result does not depend on the thread count),
    /// then those that landed or left the
    /// field are re-spawned at the top.
    pub fn step_frame(&mut self, model: &Model, params: Params) {
        let (coeffs, body) = scaled(model, params);
        let env = params.environment();
        // The batch RK4 on all cores: each body bit for bit the core's
        // `rk4_step` with `AirForces` (the air model ignores the clock),
        // whatever the thread count.
        self.lanes.load(&self.bodies);
        self.lanes.step(&coeffs, &body, &env, DT, STEPS_PER_FRAME);
        self.lanes.store(&mut self.bodies);
        self.finish_frame();
    }

    /// Advances the clock by a frame and re-spawns at the top the bodies
    /// that landed or left the field.
    fn finish_frame(&mut self) {
        self.time += STEPS_PER_FRAME as f64 * DT;
        for i in 0..self.bodies.len() {
            let out = self.bodies.get(i).is_none_or(|n| {
                n.position.z < 0.0 || n.position.xy().norm() > 4.0 * HALF_WIDTH || !n.is_finite()
            });
            if out {
                self.landed += 1;
                let fresh = self.spawn(SPAWN_Z.1);
                if let Some(slot) = self.bodies.get_mut(i) {
                    *slot = fresh;
                }
            }
        }
    }

    /// Advances one displayed frame under the comparison model `kind` of
    /// Fig. 12 built on `shape` (the view's `air::comparison_shape` of
    /// `main`'s body), moving `main`'s body as scaled by `params`: each body
    /// by the core's `rk4_step`, the bodies split over the cores
    /// (independent, so the result does not depend on the thread count).
    /// Returns false, moving nothing, when the model cannot be built.
    pub fn step_comparison(
        &mut self,
        (kind, shape): (ModelKind, &Shape),
        main: &Model,
        params: Params,
    ) -> bool {
        let body = scaled_body(main, params);
        let env = params.environment();
        let Ok(air) = AirModel::new(kind, Some(shape), None, env) else {
            return false;
        };
        let step = |s: &mut State<f64>| {
            for _ in 0..STEPS_PER_FRAME {
                *s = rk4_step(&body, &env, &air, 0.0, DT, s);
            }
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let chunk = self
            .bodies
            .len()
            .div_ceil(threads)
            .max(MIN_BODIES_PER_THREAD);
        std::thread::scope(|scope| {
            for part in self.bodies.chunks_mut(chunk) {
                scope.spawn(move || part.iter_mut().for_each(step));
            }
        });
        self.finish_frame();
        true
    }
}

/// The model with L and the body scaled by `params`.
pub fn scaled(model: &Model, params: Params) -> (Coefficients<f64>, RigidBody<f64>) {
    let mut c = model.coefficients.clone();
    let _ = c.set_reference_length(c.reference_length() * params.size);
    (c, scaled_body(model, params))
}

/// The model's body (or [`crate::models::PLATE_BODY`] when it records
/// none) with mass and inertia scaled by `params`.
pub fn scaled_body(model: &Model, params: Params) -> RigidBody<f64> {
    let props = model.coefficients.body.unwrap_or(crate::models::PLATE_BODY);
    let inertia = omniad_core::math::symmetric_from_six(props.inertia) * params.mass_scale;
    RigidBody::new(props.mass * params.mass_scale, inertia)
        .or_else(|_| RigidBody::new(props.mass, Matrix3::identity() * 1e-6))
        .unwrap_or(RigidBody {
            mass: 1.0,
            inertia: Matrix3::identity(),
            inverse_inertia: Matrix3::identity(),
        })
}
