//! How strong a synthetic set's effects are in physical terms (issue 15
//! item 8): per effect, `RMS|F_effect| / RMS|F_aero|` over every generated
//! frame of every take, `F_aero` the OmniAD model's force (eqs. 5, 7, body
//! frame, N) and `F_effect` the effect's force (the core's
//! [`omniad_core::effect::Effect::wrench`], body frame, N). The issue's
//! "realistic strength" is a fraction of 0.15-0.5.
//!
//! Wind (`--wind`, a property of the recording): its force is the model's
//! aerodynamic force at the air velocity `Rᵀ(v - w)` minus at the ground
//! velocity `Rᵀv` (eqs. 5, 7), reported as `wind`.
//!
//! Added mass: its force `-M_a dU/dt - Ω × (M_a U)` needs `dU/dt`, the rate
//! of the body-frame air velocity, taken here by central differences of
//! the frames (one-sided at the ends).

use crate::synth::SynthForces;
use nalgebra::Vector3;
use omniad_core::rigid_body::{AirForces, Forces};
use omniad_core::{Environment, State};

/// Sums of squared force magnitudes over frames.
#[derive(Clone, Debug, Default)]
pub struct Strength {
    /// Σ|F_aero|², N².
    aero: f64,
    /// Σ|F_effect|² per effect (the set's order), N².
    effects: Vec<f64>,
    /// Σ|F_aero(air velocity) - F_aero(ground velocity)|², N² (zero
    /// without wind).
    wind: f64,
}

impl Strength {
    /// Adds the frames `states` (at `fps`) of one take.
    pub fn add(&mut self, forces: &SynthForces<'_>, states: &[State<f64>], fps: f64) {
        self.effects.resize(forces.effects.len(), 0.0);
        let env = &forces.air.environment;
        let air = |s: &State<f64>| s.air_velocity_body(&env.wind);
        for (k, s) in states.iter().enumerate() {
            let aero = forces.air.wrench(k as f64 / fps, s).force;
            self.aero += aero.norm_squared();
            if env.wind != Vector3::zeros() {
                let still = AirForces {
                    model: forces.air.model,
                    environment: Environment {
                        wind: Vector3::zeros(),
                        ..*env
                    },
                };
                self.wind += (aero - still.wrench(k as f64 / fps, s).force).norm_squared();
            }
            let (a, b) = (k.saturating_sub(1), (k + 1).min(states.len() - 1));
            let rate = match (states.get(a), states.get(b)) {
                (Some(p), Some(n)) if b > a => (air(n) - air(p)) * (fps / (b - a) as f64),
                _ => Vector3::zeros(),
            };
            let inputs = forces.effect_inputs(s, rate);
            for (sum, e) in self.effects.iter_mut().zip(forces.effects) {
                *sum += e.wrench(&inputs).force.norm_squared();
            }
        }
    }

    /// `RMS|F_effect| / RMS|F_aero|` per effect (NaN without aerodynamic
    /// force).
    pub fn fractions(&self) -> Vec<f64> {
        self.effects.iter().map(|e| self.fraction(*e)).collect()
    }

    /// The wind's `RMS|F_wind| / RMS|F_aero|` (`None` without wind).
    pub fn wind_fraction(&self) -> Option<f64> {
        (self.wind > 0.0).then(|| self.fraction(self.wind))
    }

    fn fraction(&self, sum: f64) -> f64 {
        if self.aero > 0.0 {
            (sum / self.aero).sqrt()
        } else {
            f64::NAN
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::synth::write::generate;
    use crate::synth::{Effect, SynthConfig, SynthObject};

    /// The fraction a set of `effect` gets, as returned and as written.
    fn fraction(effect: &str) -> (f64, String) {
        let dir = tempfile::tempdir().expect("tempdir");
        let cfg = SynthConfig {
            object: SynthObject::Plate,
            effects: vec![Effect::parse(effect).expect("effect")],
            takes: (2, 1),
            ..SynthConfig::default()
        };
        let got = generate(dir.path(), &cfg).expect("synth");
        let toml = std::fs::read_to_string(dir.path().join("truth/model.toml")).expect("truth");
        (got.first().map_or(f64::NAN, |g| g.1), toml)
    }

    #[test]
    fn force_fraction_is_written_and_linear_in_a_weak_scale() {
        // Weak enough not to change the trajectories much: the effect's
        // force doubles, the aerodynamic force stays.
        let (one, toml) = fraction("linear_drag=50");
        let (two, _) = fraction("linear_drag=100");
        assert!(one > 0.005 && one < 0.1, "fraction {one}");
        assert!(
            toml.contains(&format!("[force_fraction]\nlinear_drag = {one:.4}")),
            "{toml}"
        );
        assert!((two / one - 2.0).abs() < 0.1, "{one} -> {two}");
    }
}
