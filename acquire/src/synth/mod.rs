//! `omniad synth`: recording sets generated from a known coefficient model
//! (the plate or open box of the shared sets, made by projecting the
//! [`omniad_core::reference::panel`] model onto SH with
//! [`omniad_core::projection`]), simulated
//! with the core RK4, filmed by the shared sets' camera, with `truth/`.
//!
//! Effects outside the OmniAD model can be added to the physics, each one
//! of the core's named effects ([`effects`] says what each SCALE means),
//! and a steady wind (the air moves at `w`: the physics sees `v - w`, the
//! markers the body's own motion).

pub mod effects;
pub mod start;
pub mod strength;
pub mod taira;
pub mod truth;
pub mod write;

use crate::error::{Error, Result};
use nalgebra::{Matrix3, Vector3};
use omniad_core::effect::EffectInputs;
use omniad_core::reference::panel::PanelModel;
use omniad_core::rigid_body::{AirForces, Forces};
use omniad_core::{Coefficients, Environment, RigidBody, State, Wrench};

/// The objects `synth` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SynthObject {
    /// Foam plate 30 x 50 x 2 cm, 48 g.
    Plate,
    /// Box-kite cell 30 x 40 x 20 cm open along y, 40 g.
    Box,
    /// The plate's size and mass with the measured lift and drag of
    /// [`taira`] (the paper's Fig. 13 validation).
    TairaPlate,
}

pub use effects::EffectSpec as Effect;
pub use start::{random_start, ThrowSpeed};

/// Settings of a synthetic set.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthConfig {
    /// Object.
    pub object: SynthObject,
    /// Effects added to the physics.
    pub effects: Vec<Effect>,
    /// Steady wind, world frame, m/s.
    pub wind: Vector3<f64>,
    /// Tracking noise, 1 sigma, px.
    pub noise: f64,
    /// Seed.
    pub seed: u64,
    /// Number of drops (from about 6 m) and spinning throws (from 1 m).
    pub takes: (usize, usize),
    /// Release speed of the spinning throws ([`ThrowSpeed`]); `None`
    /// keeps the default throw (3-4 m/s straight up, ±0.5 m/s sideways).
    pub throw_speed: Option<ThrowSpeed>,
    /// Probability that a visible marker's row is missing.
    pub dropout: f64,
    /// Probability that a row is an outlier (a tracker jump of 20-60 px).
    pub outliers: f64,
    /// SH degree of the generating model.
    pub degree: u8,
}

impl Default for SynthConfig {
    fn default() -> Self {
        Self {
            object: SynthObject::Plate,
            effects: Vec::new(),
            wind: Vector3::zeros(),
            noise: 0.7,
            seed: 1,
            takes: (8, 5),
            throw_speed: None,
            dropout: 0.02,
            outliers: 0.0,
            degree: 8,
        }
    }
}

/// Geometry and mass of a synthetic object.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSpec {
    /// Name.
    pub name: &'static str,
    /// kg.
    pub mass: f64,
    /// Extents (x, y, z), m.
    pub size: Vector3<f64>,
    /// Pole.
    pub pole: Vector3<f64>,
    /// Faces carrying markers (outward body normals); each has 4 corner markers.
    pub faces: Vec<Vector3<f64>>,
}

impl ObjectSpec {
    /// The spec of an object.
    pub fn of(o: SynthObject) -> Self {
        match o {
            SynthObject::Plate => Self {
                name: "plate",
                mass: 0.048,
                size: Vector3::new(0.3, 0.5, 0.02),
                pole: Vector3::z(),
                faces: vec![Vector3::z(), -Vector3::z()],
            },
            SynthObject::TairaPlate => Self {
                name: taira::NAME,
                ..Self::of(SynthObject::Plate)
            },
            SynthObject::Box => Self {
                name: "openbox",
                mass: 0.04,
                size: Vector3::new(0.3, 0.4, 0.2),
                pole: Vector3::y(),
                faces: vec![Vector3::x(), -Vector3::x(), Vector3::z(), -Vector3::z()],
            },
        }
    }

    /// Reference length L: the bounding-box diagonal, m.
    pub fn reference_length(&self) -> f64 {
        self.size.norm()
    }

    /// Inertia of a uniform solid box of the extents, kg m².
    pub fn inertia(&self) -> Matrix3<f64> {
        let s = self.size.component_mul(&self.size) * (self.mass / 12.0);
        Matrix3::from_diagonal(&Vector3::new(s.y + s.z, s.x + s.z, s.x + s.y))
    }

    /// Markers: 4 per face, inset 10 % from the corners; face index of each.
    pub fn markers(&self) -> Vec<(Vector3<f64>, usize)> {
        let h = self.size * 0.5;
        let mut out = Vec::new();
        for (fi, n) in self.faces.iter().enumerate() {
            let axis = n.iamax();
            let others: Vec<usize> = (0..3).filter(|&a| a != axis).collect();
            for (su, sv) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
                let mut p = n.component_mul(&h);
                if let [a, b] = others[..] {
                    p[a] = su * 0.9 * h[a];
                    p[b] = sv * 0.9 * h[b];
                }
                out.push((p, fi));
            }
        }
        out
    }

    /// Panel model of the object.
    pub fn panels(&self) -> PanelModel {
        match self.faces.len() {
            2 => PanelModel::plate(self.size.x, self.size.y),
            _ => PanelModel::open_box(self.size.x, self.size.y, self.size.z),
        }
    }
}

/// The generating coefficient model: the panel model projected onto SH.
pub fn truth_model(spec: &ObjectSpec, degree: u8) -> Result<Coefficients<f64>> {
    if spec.name == taira::NAME {
        return taira::truth_model(spec, degree);
    }
    let panels = spec.panels();
    let l = spec.reference_length();
    let rho = 1.0;
    let mut m = omniad_core::projection::project(degree, spec.pole, l, |e| {
        let (f, t) = panels.translation_wrench(e, rho);
        (f / (0.5 * rho * l * l), t / (0.5 * rho * l * l * l))
    })
    .map_err(|e| Error::Data(format!("projection: {e}")))?;
    m.set_damping(&panels.damping_tensor(l))
        .map_err(|e| Error::Data(format!("damping: {e}")))?;
    Ok(m)
}

/// The physics of a synthetic set: the OmniAD model plus named effects,
/// each evaluated by the core ([`omniad_core::effect::Effect::wrench`];
/// added mass with `dV/dt = 0` there, its `-M_a dV/dt` carried by the
/// equations of motion through [`Forces::added_mass`]).
pub struct SynthForces<'a> {
    /// Model and environment (wind included).
    pub air: AirForces<'a, f64>,
    /// The effects with their parameters.
    pub effects: &'a [omniad_core::effect::Effect<f64>],
}

impl SynthForces<'_> {
    /// What the effects act on in state `s` (body frame) of this air, with
    /// `velocity_rate` the body-frame `dV/dt`, m/s².
    pub fn effect_inputs(&self, s: &State<f64>, velocity_rate: Vector3<f64>) -> EffectInputs<f64> {
        let env = &self.air.environment;
        EffectInputs {
            velocity: s.air_velocity_body(&env.wind),
            angular_velocity: s.angular_velocity,
            gravity: s.orientation.inverse_transform_vector(&env.gravity),
            velocity_rate,
            air_density: env.air_density,
            reference_length: self.air.model.reference_length(),
        }
    }
}

impl Forces<f64> for SynthForces<'_> {
    fn wrench(&self, t: f64, s: &State<f64>) -> Wrench<f64> {
        let mut w = self.air.wrench(t, s);
        // Added mass's -M_a dU/dt is on the mass side (`added_mass`).
        let inputs = self.effect_inputs(s, Vector3::zeros());
        for e in self.effects {
            let f = e.wrench(&inputs);
            w.force += f.force;
            w.torque += f.torque;
        }
        w
    }

    fn added_mass(&self) -> Option<Matrix3<f64>> {
        self.effects.iter().find_map(|e| e.added_mass())
    }
}

/// Simulates one take at `substeps` RK4 steps per frame; stops below 0.3 m
/// (after at least 10 frames) or after `max_frames`.
pub fn simulate(
    body: &RigidBody<f64>,
    env: &Environment<f64>,
    forces: &SynthForces<'_>,
    start: State<f64>,
    fps: f64,
    max_frames: usize,
) -> Vec<State<f64>> {
    let substeps = 10;
    let dt = 1.0 / (fps * substeps as f64);
    let mut s = start;
    let mut out = vec![s];
    for k in 1..max_frames {
        for i in 0..substeps {
            s = omniad_core::integrate::rk4_step(
                body,
                env,
                forces,
                (k * substeps + i) as f64 * dt,
                dt,
                &s,
            );
        }
        if !s.is_finite() || (s.position.z < 0.3 && k >= 10) {
            break;
        }
        out.push(s);
    }
    out
}
