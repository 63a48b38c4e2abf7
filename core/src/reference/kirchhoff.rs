//! The Kirchhoff-tensor comparison model (Weißmann & Pinkall 2012; the
//! OmniAD paper's Fig. 12, orange): a rigid body in an ideal fluid feels
//! only its added mass (Kirchhoff's equations, Lamb *Hydrodynamics*
//! §124-126) — the force `-M_a dV/dt - Ω × (M_a V)` and the Munk moment
//! `-V × (M_a V)`, and no steady force at all (d'Alembert's paradox).
//!
//! The physics is the core's one owner of added mass,
//! [`EffectKind::AddedMass`] ([`Effect::wrench`] with `dV/dt` carried by
//! the equations of motion, [`crate::rigid_body::state_rate_with_added_mass`]);
//! this model only supplies `M_a` for a shape: the added mass of the solid
//! ellipsoid inscribed in its bounding box ([`super::ellipsoid`], Lamb
//! §114). For the paper's 30 x 50 x 2 cm plate at ρ = 1.2 kg/m³ that is
//! 20-22 g normal to the plate (the inscribed ellipsoid, a little under
//! the thin elliptic disc's 22.15 g; a thin
//! rectangular plate of the same sides has about 30 g, DNV-RP-C205
//! Table A-1, `C_A = 0.72` for b/a = 1.67) and under 1 g in plane.

use super::ellipsoid;
use super::shape::Shape;
use crate::aero::Wrench;
use crate::effect::{Effect, EffectInputs, EffectKind};
use crate::rigid_body::{Environment, Forces, State};
use nalgebra::{Matrix3, Vector3};

/// Added mass only (ideal fluid), for one shape in one environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kirchhoff {
    /// The added-mass effect, M_a in kg (body frame, diagonal).
    pub effect: Effect<f64>,
    /// ρ, wind and gravity.
    pub environment: Environment<f64>,
    /// L, m (the effect's inputs carry it; added mass does not use it).
    pub reference_length: f64,
}

impl Kirchhoff {
    /// The model of `shape` in `environment` (M_a scales with its ρ).
    pub fn new(shape: &Shape, environment: Environment<f64>) -> Self {
        let semi = [shape.size.x * 0.5, shape.size.y * 0.5, shape.size.z * 0.5];
        let [mx, my, mz] = ellipsoid::added_mass(semi, environment.air_density);
        let params = [mx, my, mz, 0.0, 0.0, 0.0];
        let effect = Effect::new(EffectKind::AddedMass, &params)
            .unwrap_or(Effect::unit(EffectKind::AddedMass, 6));
        Self {
            effect,
            environment,
            reference_length: shape.reference_length(),
        }
    }

    /// M_a, kg, body frame.
    pub fn tensor(&self) -> Matrix3<f64> {
        self.effect.added_mass().unwrap_or_else(Matrix3::zeros)
    }
}

impl Forces<f64> for Kirchhoff {
    /// `-Ω × (M_a V)` and the Munk moment; the `-M_a dV/dt` part is on the
    /// left of the equations of motion (see [`Forces::added_mass`]).
    fn wrench(&self, _t: f64, state: &State<f64>) -> Wrench<f64> {
        let env = &self.environment;
        self.effect.wrench(&EffectInputs {
            velocity: state.air_velocity_body(&env.wind),
            angular_velocity: state.angular_velocity,
            gravity: state.orientation.inverse_transform_vector(&env.gravity),
            velocity_rate: Vector3::zeros(),
            air_density: env.air_density,
            reference_length: self.reference_length,
        })
    }

    fn added_mass(&self) -> Option<Matrix3<f64>> {
        self.effect.added_mass()
    }
}
