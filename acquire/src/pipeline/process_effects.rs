//! Effects that change the states, put into the refinement's process model
//! (issue 15, "refit around the effect"). The residual analysis
//! (`residual::refit`) finds them on a first fit and fits again with them:
//! * added mass M_a (kg, body frame) is the object's: the base model the
//!   refinement starts from carries it as the core's named effect, so the
//!   filter's RK4 step solves `(M I + M_a) dU/dt = ...`
//!   (`rigid_body::state_rate_with_added_mass`), and the coefficient fit
//!   sees the frames' air wrench net of the effect's (eqs. 9-10 give the
//!   whole air wrench, `-M_a dU/dt - Ω × (M_a U)` and the Munk moment
//!   `-U × (M_a U)` included: alpha, beta and D must not take it twice);
//! * the wind is the recording's: it sits in the filter's settings
//!   (`FilterConfig::wind`), and the frames' velocities are relative to
//!   the air (`run::samples_in_wind`).

use crate::error::{Error, Result};
use crate::reconstruct::forces::Sample;
use nalgebra::Matrix3;
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::Coefficients;
use std::borrow::Cow;

/// `base` with the added mass `m` (symmetric, kg, body frame), if any.
pub(super) fn with_added_mass(
    mut base: Coefficients<f64>,
    m: Option<&Matrix3<f64>>,
) -> Result<Coefficients<f64>> {
    if let Some(m) = m {
        let six = omniad_core::math::six_from_symmetric(m);
        let e = Effect::new(EffectKind::AddedMass, &six)
            .ok_or_else(|| Error::Data("added mass: bad parameters".into()))?;
        base.set_effect(e)
            .map_err(|e| Error::Data(format!("cannot add the added mass: {e}")))?;
    }
    Ok(base)
}

/// The frames with the named effects of `model` taken off their air
/// wrench (borrowed unchanged when it has none).
pub(super) fn net_of_effects<'a>(
    frames: &'a [Sample],
    model: &Coefficients<f64>,
    air_density: f64,
) -> Cow<'a, [Sample]> {
    if model.effects().is_empty() {
        return Cow::Borrowed(frames);
    }
    let net = frames
        .iter()
        .map(|s| {
            let x = s.effect_inputs(air_density, model.reference_length());
            let mut out = *s;
            for e in model.effects() {
                let w = e.wrench(&x);
                out.force -= w.force;
                out.torque -= w.torque;
            }
            out
        })
        .collect();
    Cow::Owned(net)
}
