//! How strong a synthetic set's wind and added mass are (issue 15's
//! "realistic strength": the effect's force 15-50 % of the aerodynamic
//! force): RMS over the frames of the TRUE states of the effect's force and
//! of the aerodynamic force of eqs. (5)-(6), body frame, N.
//! `omniad lab effect-strength SET --object OBJECT` (the object the set was
//! made with: its generating model gives the aerodynamic force).
//! * added mass (`truth/model.toml` `[parameters] added_mass`): the
//!   effect's force `-M_a dU/dt - Ω × (M_a U)` (Lamb §126) with `U` and
//!   `dU/dt` from the true states (eq. 9's central differences);
//! * wind (`truth/model.toml` `wind`, world m/s): the aerodynamic force at
//!   the air velocity `Rᵀ(v - w)` minus at the ground velocity `Rᵀv`.
//!
//! The aerodynamic force is the generating model's at the air velocity.

use super::{say, LabResult};
use crate::input::recording::RecordingSet;
use crate::reconstruct::forces::{ForceStats, Sample};
use crate::reconstruct::run::samples_in_wind;
use crate::synth::truth::true_trajectories;
use nalgebra::Vector3;
use omniad_core::effect::{Effect, EffectInputs, EffectKind};
use omniad_core::Coefficients;
use std::io::Write;
use std::path::Path;

/// RMS forces over the frames, N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strength {
    /// The aerodynamic force of eqs. (5)-(6).
    pub aero: f64,
    /// The wind's change of it.
    pub wind: f64,
    /// The added mass's force.
    pub added_mass: f64,
}

/// The strengths on frames `s` (velocities relative to the air moving
/// with `wind`) of a set whose air follows `model` (eqs. 5-6) in `wind`
/// with added mass `m_a` (xx, yy, zz, xy, xz, yz; kg).
pub fn strength(
    s: &[Sample],
    model: &Coefficients<f64>,
    (wind, m_a): (&Vector3<f64>, Option<&[f64]>),
    (rho, l): (f64, f64),
    attitude: &dyn Fn(&Sample) -> nalgebra::UnitQuaternion<f64>,
) -> Strength {
    let am = m_a.and_then(|p| Effect::new(EffectKind::AddedMass, p));
    let (mut a, mut w, mut m) = (0.0, 0.0, 0.0);
    for f in s {
        let aero = model.wrench(&f.velocity, &f.angular_velocity, rho).force;
        let ground = f.velocity + attitude(f).inverse_transform_vector(wind);
        let still = model.wrench(&ground, &f.angular_velocity, rho).force;
        a += aero.norm_squared();
        w += (aero - still).norm_squared();
        if let Some(e) = &am {
            let x = EffectInputs {
                velocity: f.velocity,
                angular_velocity: f.angular_velocity,
                gravity: f.gravity_body,
                velocity_rate: f.velocity_rate,
                air_density: rho,
                reference_length: l,
            };
            m += e.wrench(&x).force.norm_squared();
        }
    }
    let n = s.len().max(1) as f64;
    Strength {
        aero: (a / n).sqrt(),
        wind: (w / n).sqrt(),
        added_mass: (m / n).sqrt(),
    }
}

/// The wind and added-mass parameters of `truth/model.toml`.
fn truth_effects(dir: &Path) -> Result<(Vector3<f64>, Option<Vec<f64>>), String> {
    let path = dir.join("truth").join("model.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: toml::Value = text
        .parse()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let numbers = |x: Option<&toml::Value>| -> Option<Vec<f64>> {
        x?.as_array()?
            .iter()
            .map(|n| n.as_float().or_else(|| n.as_integer().map(|i| i as f64)))
            .collect()
    };
    let w = numbers(v.get("wind")).unwrap_or_default();
    let wind = Vector3::new(
        w.first().copied().unwrap_or(0.0),
        w.get(1).copied().unwrap_or(0.0),
        w.get(2).copied().unwrap_or(0.0),
    );
    let am = numbers(v.get("parameters").and_then(|p| p.get("added_mass")));
    Ok((wind, am))
}

/// Prints the strengths of the synthetic set in `dir`, made with `object`.
pub fn run(dir: &Path, object: crate::synth::SynthObject, out: &mut dyn Write) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let spec = crate::synth::ObjectSpec::of(object);
    let model = crate::synth::truth_model(&spec, 8)?;
    let (wind, am) = truth_effects(dir)?;
    let states = true_trajectories(dir, &set)?;
    let frames = samples_in_wind(&set, &states, &wind, &mut ForceStats::default());
    let attitude = |f: &Sample| {
        states
            .get(f.take)
            .and_then(|t| t.states.get(f.index))
            .map_or_else(nalgebra::UnitQuaternion::identity, |x| x.orientation)
    };
    let (rho, l) = (set.world.air_density, set.object.reference_length);
    let s = strength(&frames, &model, (&wind, am.as_deref()), (rho, l), &attitude);
    say!(out, "frames {} (true states)", frames.len());
    say!(out, "aerodynamic force RMS {:.4} N", s.aero);
    say!(
        out,
        "wind [{:.2}, {:.2}, {:.2}] m/s: force RMS {:.4} N = {:.1} % of the aerodynamic",
        wind.x,
        wind.y,
        wind.z,
        s.wind,
        100.0 * s.wind / s.aero
    );
    say!(
        out,
        "added mass: force RMS {:.4} N = {:.1} % of the aerodynamic",
        s.added_mass,
        100.0 * s.added_mass / s.aero
    );
    Ok(())
}
