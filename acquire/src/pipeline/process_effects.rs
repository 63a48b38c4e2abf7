//! Effects that change the states, put into the refinement's process model
//! (issue 15, "refit around the effect"). The residual analysis
//! (`residual::refit`) finds them on a first fit and fits again with them:
//! * the object's named effects (`omniad_core::effect`: buoyancy, rotational
//!   lift, propeller thrust, linear drag, added mass) are carried by the
//!   base model the refinement starts from, so the filter's RK4 step
//!   predicts with them (`rigid_body::AirForces` evaluates every stored
//!   effect; added mass on the mass side,
//!   `rigid_body::state_rate_with_added_mass`, solving
//!   `(M I + M_a) dU/dt = ...`), and the coefficient fit sees the frames'
//!   air wrench net of the effects' (eqs. 9-10 give the whole air wrench,
//!   the effects' included: alpha, beta and D must not take it twice). In
//!   a model-based reconstruction any force the process model lacks is
//!   explained by the states and the bias wrench instead, which pulls the
//!   reconstructed forces toward the model without it;
//! * the wind is the recording's: it sits in the filter's settings
//!   (`FilterConfig::wind`), and the frames' velocities are relative to
//!   the air (`run::samples_in_wind`).

use crate::error::{Error, Result};
use crate::reconstruct::forces::Sample;
use omniad_core::effect::Effect;
use omniad_core::Coefficients;
use std::borrow::Cow;

/// `base` with `effects` stored (one per kind; each checked by the core).
pub(super) fn with_effects(
    mut base: Coefficients<f64>,
    effects: &[Effect<f64>],
) -> Result<Coefficients<f64>> {
    for e in effects {
        base.set_effect(*e).map_err(|err| {
            Error::Data(format!("cannot add the effect {}: {err}", e.kind.name()))
        })?;
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
