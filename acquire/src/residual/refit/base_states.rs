//! The base model scored on the states the extended model is scored on:
//! the report's `baseline`, so that "before" and "after" are two models
//! on one set of held-out frames.
//!
//! Why: each round reconstructs the states with its own model in the
//! filter's process model, and a model-based reconstruction leans its
//! states toward that model. The first round's states lean toward the
//! base model (no effect), the last round's toward the extended one.
//! Scoring the base on the first round's states and the extended model
//! on the last round's changes the data between "before" and "after".
//! Measured on synthetic sets against their truth (BENCHMARKS.md, stop
//! 30): the ratio of the two models' errors against the true force is
//! followed about twice as closely when both are scored on the last
//! round's frames. The first round's number stays in the report
//! (`first_round_baseline`): it is the residual the diagnosis reads.
//!
//! A wind is the recording's, not a model's: the last round's frames are
//! in the air (`V - Rᵀw`); the base model, which knows no wind, is scored
//! on the same frames back in still air. The held-out re-simulation's
//! base models are fitted on the same problems and fly from the same
//! states (`residual::analyse`).

use super::wind_search::in_wind;
use super::{problems_on, Round};
use crate::input::recording::RecordingSet;
use crate::residual::fixed;
use crate::residual::problems::Problems;
use crate::residual::select::{score, Scored};
use nalgebra::Vector3;
use omniad_core::Coefficients;

/// The base model scored on a round's frames ([`base_on`]).
pub(crate) struct BaseOn {
    /// The problems it was scored on when the round holds a wind (its
    /// frames back in still air); `None`: the round's own problems.
    pub still_air: Option<Problems>,
    /// Its held-out scores.
    pub scored: Scored,
}

impl BaseOn {
    /// The problems the base model was scored on (`r`: the round given
    /// to [`base_on`]).
    pub fn problems<'a>(&'a self, r: &'a Round) -> &'a Problems {
        self.still_air.as_ref().unwrap_or(&r.p)
    }
}

/// The base model (the round's coefficients alone, or `given`), no effect
/// and no wind, scored on held-out takes of round `r`'s frames (the takes
/// its selection scored). `None` when the problems cannot be built.
pub(crate) fn base_on(
    set: &RecordingSet,
    r: &Round,
    given: Option<&Coefficients<f64>>,
) -> Option<BaseOn> {
    let Some(w) = r.effects.wind else {
        // The round's own baseline is exactly this (`select::select`
        // scores the empty design first).
        return Some(BaseOn {
            still_air: None,
            scored: r.sel.baseline.clone(),
        });
    };
    let model = r.candidates_model(given);
    let (p, scored) = scored_on(set, r, &-w, &model, given.is_some()).ok()?;
    Some(BaseOn {
        still_air: Some(p),
        scored,
    })
}

/// `model` with no effect beyond what it stores, scored on held-out takes
/// of round `r`'s frames (the takes its selection scored) seen in the
/// round's wind plus `shift` (world, m/s): held as it is when `hold`
/// (nothing fitted, so its error is its residual on every take), else its
/// coefficients fitted leave-one-take-out. With the problems it was scored
/// on; `Err` says why not (problems not built, non-finite errors, or not
/// every take of the round scored, which would not be the round's frames).
pub(super) fn scored_on(
    set: &RecordingSet,
    r: &Round,
    shift: &Vector3<f64>,
    model: &Coefficients<f64>,
    hold: bool,
) -> Result<(Problems, Scored), String> {
    let frames = in_wind(&r.selection_samples(), &r.outcome.reconstruction, shift);
    let p = problems_on(set, &r.outcome, &frames, model).map_err(|e| e.to_string())?;
    let p = if hold {
        fixed::hold(p, model).map_err(|e| e.to_string())?
    } else {
        p
    };
    let scored = score(&p, &[]).ok_or("its held-out errors are not finite")?;
    let (got, want) = (scored.per_take.len(), r.p.force.take_ids.len());
    if got != want {
        return Err(format!("{got} of the round's {want} takes scored"));
    }
    Ok((p, scored))
}
