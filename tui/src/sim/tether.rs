//! A tethered kite flying in gusts: the kite view's design as one rigid
//! body (`omniad_core::kite` air wrench of all its panels) on an elastic
//! line to an anchor at the origin, in a wind with deterministic gusts.

use crate::kite::design::{rotation, Analysis, Assembly, Design};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::integrate::rk4_step;
use omniad_core::kite::statics::air_wrench;
use omniad_core::kite::Primitive;
use omniad_core::rigid_body::Forces;
use omniad_core::{Coefficients, Environment, RigidBody, State, Wrench};
use std::collections::VecDeque;

/// Physics step, s (small: the quadratic damping of eq. 6 on a light
/// kite is stiff).
const DT: f64 = 1.0 / 1920.0;
/// Steps per displayed frame (1/30 s).
const STEPS: usize = 64;
/// Line stiffness, N/m, and damping, N s/m.
const STIFFNESS: f64 = 40.0;
const DAMPING: f64 = 1.0;
/// Trail length, frames.
const TRAIL: usize = 90;

/// The tethered kite's state.
#[derive(Clone, Debug)]
pub struct Tethered {
    /// Kite state (world, z up; the anchor is the origin).
    pub state: State<f64>,
    /// Simulated time, s.
    pub time: f64,
    /// Mean wind along +x, m/s.
    pub wind: f64,
    /// Gust amplitude as a fraction of the mean wind.
    pub gust: f64,
    /// Line length, m.
    pub length: f64,
    /// Times the kite hit the ground and was relaunched.
    pub crashes: u32,
    /// Recent positions.
    pub trail: VecDeque<Vector3<f64>>,
    assembly: Assembly,
    attachment: Vector3<f64>,
    orientation: UnitQuaternion<f64>,
    air_density: f64,
}

/// The wind at time `t`: mean `u` along x with gusts of relative size `g`.
pub fn gusty_wind(u: f64, g: f64, t: f64) -> Vector3<f64> {
    let along =
        1.0 + g * (0.6 * (0.9 * t).sin() + 0.3 * (2.7 * t + 1.0).sin() + 0.1 * (6.1 * t).sin());
    Vector3::new(u * along, u * g * 0.4 * (0.5 * t + 2.0).sin(), 0.0)
}

struct KiteForces<'a> {
    prims: &'a [Primitive<'a, f64>],
    rho: f64,
    wind: (f64, f64),
    attachment: Vector3<f64>,
    length: f64,
}

impl Forces<f64> for KiteForces<'_> {
    fn wrench(&self, t: f64, s: &State<f64>) -> Wrench<f64> {
        let w = gusty_wind(self.wind.0, self.wind.1, t);
        let v = s.orientation.inverse_transform_vector(&(s.velocity - w));
        let mut out = air_wrench(self.prims, &v, &s.angular_velocity, self.rho);
        let d = s.position + s.orientation * self.attachment;
        let dist = d.norm();
        if dist > self.length {
            let u = d / dist;
            let va = s.velocity + s.orientation * s.angular_velocity.cross(&self.attachment);
            let pull = (STIFFNESS * (dist - self.length) + DAMPING * va.dot(&u)).max(0.0);
            let f = s.orientation.inverse_transform_vector(&(-u * pull));
            out.force += f;
            out.torque += self.attachment.cross(&f);
        }
        out
    }
}

impl Tethered {
    /// The kite of `design` (analysed as `analysis`) on a `length` m line.
    pub fn new(
        design: &Design,
        analysis: &Analysis,
        plate: &Coefficients<f64>,
        length: f64,
    ) -> Self {
        let orientation = UnitQuaternion::from_matrix(&rotation(&design.orientation));
        let mut s = Self {
            state: State::at_rest(Vector3::zeros()),
            time: 0.0,
            wind: design.wind_speed,
            gust: 0.3,
            length,
            crashes: 0,
            trail: VecDeque::new(),
            assembly: Assembly::new(design, plate),
            attachment: analysis.attachment,
            orientation,
            air_density: design.air_density,
        };
        s.launch(analysis);
        s
    }

    fn launch_at(&mut self, dir: Vector3<f64>) {
        let p = dir * self.length - self.orientation * self.attachment;
        self.state = State {
            orientation: self.orientation,
            ..State::at_rest(p)
        };
        self.trail.clear();
    }

    fn launch(&mut self, analysis: &Analysis) {
        let n = analysis.tension.norm();
        let dir = if n > 0.0 {
            -analysis.tension / n
        } else {
            Vector3::new(1.0, 0.0, 1.0).normalize()
        };
        self.launch_at(dir);
    }

    /// Advances one displayed frame.
    pub fn step_frame(&mut self) {
        let prims = self.assembly.primitives();
        let body = RigidBody::new(self.assembly.mass, self.assembly.inertia);
        let Ok(body) = body else { return };
        let forces = KiteForces {
            prims: &prims,
            rho: self.air_density,
            wind: (self.wind, self.gust),
            attachment: self.attachment,
            length: self.length,
        };
        let env = Environment {
            air_density: self.air_density,
            ..Environment::standard()
        };
        for _ in 0..STEPS {
            self.state = rk4_step(&body, &env, &forces, self.time, DT, &self.state);
            self.time += DT;
        }
        if self.state.position.z < 0.0 || !self.state.is_finite() {
            self.crashes += 1;
            self.launch_at(Vector3::new(1.0, 0.0, 1.0).normalize());
        }
        self.trail.push_back(self.state.position);
        while self.trail.len() > TRAIL {
            self.trail.pop_front();
        }
    }
}
