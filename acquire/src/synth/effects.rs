//! The effects a synthetic set's air may carry beyond the OmniAD model,
//! `--effect NAME[=SCALE]`, each one of the core's named effects
//! ([`omniad_core::effect`], whose `Effect::wrench` computes the force:
//! the physics has one owner). SCALE in physical terms (object of extents
//! `s`, reference length L, air density ρ):
//!
//! | name | parameters at SCALE |
//! |---|---|
//! | `buoyancy` | `V_b = SCALE · s_x s_y s_z` (1: the bounding box displaces air) |
//! | `added_mass` | `M_a = SCALE ·` the inscribed ellipsoid's potential-flow tensor ([`crate::synth::added_mass`], Lamb §114) |
//! | `added_mass_coupling` | the same M_a, its velocity terms only (no acceleration reaction: the air of a stateless fluid model such as MuJoCo's) |
//! | `rotational_lift` | `c = SCALE` (force `ρL³ c Ω × V`) |
//! | `magnus` | alias: `rotational_lift` with `c = SCALE / 2` (the old `½ρL³ SCALE Ω × V`) |
//! | `linear_drag` | `k = SCALE · 3π` (Stokes' sphere of diameter L; force `-k μ L V`) |
//! | `propeller_thrust` | `K = SCALE · Z Zᵀ` (Z the pole: thrust along the pole from spin about it, force `½ρL⁴ |Ω| K Ω`) |

use crate::error::{Error, Result};
use crate::synth::ObjectSpec;
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::reference::ellipsoid::added_mass;

/// One `--effect NAME[=SCALE]` as given.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectSpec {
    /// The name as given (`magnus` stays `magnus`).
    pub name: String,
    /// The effect.
    pub kind: EffectKind,
    /// SCALE (1 when not given).
    pub scale: f64,
}

/// The names `--effect` accepts.
pub const NAMES: [&str; 7] = [
    "added_mass",
    "added_mass_coupling",
    "rotational_lift",
    "magnus",
    "propeller_thrust",
    "buoyancy",
    "linear_drag",
];

impl EffectSpec {
    /// Parses `NAME[=SCALE]`.
    pub fn parse(s: &str) -> Result<Self> {
        let (name, scale) = match s.split_once('=') {
            Some((n, v)) => (
                n,
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| Error::Data(format!("effect `{s}`: SCALE must be a number")))?,
            ),
            None => (s, 1.0),
        };
        let kind = match name {
            "magnus" => Some(EffectKind::RotationalLift),
            n => EffectKind::from_name(n),
        }
        .ok_or_else(|| {
            Error::Data(format!(
                "unknown effect `{name}` (known: {})",
                NAMES.join(", ")
            ))
        })?;
        Ok(Self {
            name: name.to_owned(),
            kind,
            scale,
        })
    }

    /// The effect's parameters for `spec` in air of density `rho` (see the
    /// module's table).
    pub fn effect(&self, spec: &ObjectSpec, rho: f64) -> Result<Effect<f64>> {
        let s = self.scale;
        let params: Vec<f64> = match self.kind {
            EffectKind::Buoyancy => vec![s * spec.size.x * spec.size.y * spec.size.z],
            EffectKind::RotationalLift if self.name == "magnus" => vec![s * 0.5],
            EffectKind::RotationalLift => vec![s],
            EffectKind::LinearDrag => vec![s * 3.0 * std::f64::consts::PI],
            EffectKind::AddedMass | EffectKind::AddedMassCoupling => {
                // The ellipsoid inscribed in the bounding box (Lamb §114,
                // the core's reference model): diagonal in the body frame.
                let half = [spec.size.x, spec.size.y, spec.size.z].map(|e| 0.5 * e);
                let [mx, my, mz] = added_mass(half, rho);
                vec![s * mx, s * my, s * mz, 0.0, 0.0, 0.0]
            }
            EffectKind::PropellerThrust => {
                let z = spec.pole.normalize();
                let k = z * z.transpose() * s;
                (0..9).map(|i| k[(i / 3, i % 3)]).collect()
            }
        };
        Effect::new(self.kind, &params)
            .ok_or_else(|| Error::Data(format!("effect `{}`: bad parameters", self.name)))
    }
}
