//! `omniad residual` (issue 15): find the base model's residual on
//! held-out takes, name the effect it points to, add it, and report the
//! error before and after.
//!
//! 1. The base model (no extensions) is fitted by the refinement
//!    ([`crate::pipeline::fit`]).
//! 2. Every candidate ([`candidates`]) is fitted jointly with alpha in one
//!    force problem and one torque problem ([`problems`],
//!    [`crate::fit::joint`]), scored leave-one-take-out.
//! 3. Greedy forward selection with a gain threshold, a sign test across
//!    held-out takes, plausibility and parsimony ([`select`]); clean air
//!    gets nothing.
//! 4. The base and the extended model ([`extend`]) are re-simulated
//!    against the reconstruction, each take with the models fitted without
//!    it ([`resimulate`]); the residual is diagnosed
//!    ([`diagnose`]) and described in words ([`words`]).
//!
//! 5. A wind or a named effect found changes the states themselves (the
//!    reconstruction is model-based): it is put into the reconstruction's
//!    process model and everything above runs again on the new states
//!    until the selection settles ([`refit`]).

pub mod candidates;
pub mod diagnose;
pub mod extend;
pub mod fixed;
pub mod frames;
pub mod identify;
pub(crate) mod null;
pub(crate) mod output_error;
pub mod plots;
pub(crate) mod problems;
pub mod refit;
pub mod resimulate;
pub mod select;
pub mod words;

use crate::error::Result;
use crate::input::recording::RecordingSet;
use crate::pipeline::FitConfig;
use crate::reconstruct::run::Progress;
use nalgebra::Vector3;
use omniad_core::Coefficients;
pub use resimulate::{Resimulation, TakeResimulation};
use serde::Serialize;
use std::path::Path;

/// Held-out RMS errors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HeldOut {
    /// Force, N.
    pub heldout_force_rms: f64,
    /// Torque, N m.
    pub heldout_torque_rms: f64,
}

/// One candidate in the report.
#[derive(Clone, Debug, Serialize)]
pub struct CandidateReport {
    /// Name.
    pub effect: String,
    /// Selection step it was tried at (0 first).
    pub step: usize,
    /// Held-out force RMS with it, N.
    pub heldout_force_rms: f64,
    /// Held-out torque RMS with it, N m.
    pub heldout_torque_rms: f64,
    /// Relative gain of the weighted held-out force error.
    pub gain: f64,
    /// Relative gain of the held-out squared torque error.
    pub torque_gain: f64,
    /// Relative gain of force and torque together, each in units of its
    /// baseline (what the selection ranks by, [`select`]).
    pub score_gain: f64,
    /// Held-out takes predicted better.
    pub takes_better: usize,
    /// Held-out takes.
    pub takes: usize,
    /// Parameters (the library's order and units; wind: world m/s).
    pub params: Vec<f64>,
    /// Jackknife standard errors over the held-out folds.
    pub uncertainty: Vec<f64>,
    /// Why it was not kept.
    pub rejected: Option<String>,
    /// The fraction of the measured force's weighted square its design's
    /// effect columns leave unexplained without C_F (at most
    /// [`identify::COPY_FRACTION`]: not identifiable; absent with a given
    /// model).
    pub unexplained_without_cf: Option<f64>,
    /// The share of its fitted force's weighted square that the base
    /// model's C_F (with the effects kept before it) cannot take over
    /// ([`identify::beyond_cf`]): what its held-out gain can come from;
    /// absent with a given model.
    pub beyond_cf: Option<f64>,
    /// The bound of its gains on the set re-simulated without effects
    /// ([`null`]): it is kept only with a gain at least
    /// [`select::MIN_GAIN`] above this (or above 0 when it is negative).
    pub null_gain: f64,
}

/// C_F relative error against `truth/` (synthetic sets).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TruthError {
    /// Base model.
    pub before: f64,
    /// Extended model.
    pub after: f64,
    /// Directions compared.
    pub directions: usize,
}

/// The analysis.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The base model's held-out errors (a given model, `--coeffs`: its
    /// residual on every take, nothing of it being fitted), on the frames
    /// `after` is scored on: the last round's states, back in still air
    /// when they hold a wind ([`refit::base_on`]).
    pub baseline: HeldOut,
    /// The base model's held-out errors on the first round's states
    /// (reconstructed without any effect): the residual the diagnosis,
    /// the figures and the candidates' first step read. The same as
    /// `baseline` when no refit round was kept.
    pub first_round_baseline: HeldOut,
    /// Where the base model comes from: `fitted` (leave-one-take-out) or
    /// `given` (`--coeffs`, held fixed; candidates' `params` are then
    /// increments on what it stores).
    pub baseline_model: &'static str,
    /// The states `baseline` is scored on: `final_round` (those of
    /// `after`), or `first_round` when the base model could not be scored
    /// on the final round's frames (its problems in still air could not
    /// be built); the words then say so.
    pub baseline_frames: &'static str,
    /// Every candidate as tried.
    pub candidates: Vec<CandidateReport>,
    /// Kept effects, strongest (first chosen) first.
    pub selected: Vec<String>,
    /// Their parameters in the extended model, in the order of `selected`
    /// (a coupling's split: its M_a and the rotational lift it holds,
    /// `candidates::CouplingSplit`; the wind in world m/s).
    pub selected_params: Vec<Vec<f64>>,
    /// The extended model's held-out errors.
    pub after: HeldOut,
    /// Re-simulation of the takes, each held out (the base and the
    /// extended model fitted without it on the frames `baseline` and
    /// `after` are scored on, each flown from the same round's states).
    pub resimulation: Option<Resimulation>,
    /// The reconstructed force's noise as the markers alone predict it, N:
    /// `sqrt(mean tr Σ_F)` over the force frames, `Σ_F` the markers-only
    /// (model-free) smoother's covariance of the reconstructed force (eqs.
    /// 9-10). A conservative reference, not a floor: the refinement's
    /// states use the model as well and are more precise (shared
    /// `plate-buoyancy`: 0.23 N here, 0.044 N held-out residual after).
    pub markers_only_force_noise_rms: f64,
    /// C_F error against the truth, when the set has `truth/`.
    pub cf_error_vs_truth: Option<TruthError>,
    /// The generating model's errors on the frames `after` is scored on,
    /// when the set has `truth/model.omni` (`omniad synth` writes it): the
    /// exactly right model, held as it is in the set's true wind
    /// ([`refit::truth_on`]). `truth_model / baseline` is the ratio the
    /// exactly right model gets on these frames; not a bound, since the
    /// states lean toward the fitted model they were reconstructed with
    /// (BENCHMARKS.md, stop 31).
    pub truth_model: Option<HeldOut>,
    /// The selected wind (world frame, m/s).
    pub wind: Option<[f64; 3]>,
    /// The residual's diagnosis.
    pub diagnosis: diagnose::Diagnosis,
    /// The report in words.
    pub words: Vec<String>,
    /// Frames and takes analysed.
    pub frames: usize,
    /// Takes analysed.
    pub takes: usize,
    /// Takes left out: their first reconstruction was implausible
    /// (`reconstruct::first`).
    pub left_out_takes: Vec<crate::reconstruct::first::LeftOut>,
    /// The refit around the wind and named effects found ([`refit`]).
    pub refit: refit::Refit,
    /// The null calibration ([`null`]): the candidates' gains on the set
    /// re-simulated with the base model, without any effect; absent when
    /// the replicas could not be analysed (then every null bound is 0).
    pub null_calibration: Option<refit::NullCalibration>,
}

/// The analysis and the models.
pub struct Analysis {
    /// The report.
    pub report: Report,
    /// The base model.
    pub base: Coefficients<f64>,
    /// The extended model.
    pub extended: Coefficients<f64>,
    /// Per frame, the base model's held-out force residual (first round)
    /// and the extended model's (last round), body frame
    /// ([`frames`]).
    pub frames: Vec<frames::FrameResidual>,
}

/// For each of `takes` takes, `design` fitted on problems `p` without it
/// (`extend::extend_without`, over `model`: a round's bare model or the
/// given one): the models its held-out re-simulation flies. `None` where
/// the model cannot be built.
fn held_out_models(
    takes: usize,
    p: &problems::Problems,
    model: &Coefficients<f64>,
    design: &[candidates::Candidate],
    consts: (f64, f64, f64),
) -> Vec<Option<Coefficients<f64>>> {
    (0..takes)
        .map(|t| extend::extend_without(p, model, design, consts, t).ok())
        .map(|e| e.map(|e| e.model))
        .collect()
}

/// Runs the analysis of the set in `dir`: the first round on states
/// reconstructed without any effect, then the refits around the wind and
/// the named effects it finds ([`refit`]). `baseline` is the base model
/// on the final round's frames ([`refit::base_on`]; the first round's is
/// `first_round_baseline`); `candidates`, `selected` and `after` are the final round's (the
/// first round's when no refit confirmed an effect, or a refit of force
/// effects only gained too little, `refit::earns_its_place`). With `given` (checked
/// by [`fixed::check`]) that model is the baseline of every round instead
/// of the fitted one.
pub fn analyse(
    dir: &Path,
    set: &RecordingSet,
    cfg: &FitConfig,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Result<Analysis> {
    let rounds = refit::run(set, cfg, given, progress)?;
    let first = &rounds.first;
    let last = rounds.last.as_ref().unwrap_or(first);
    let (selected, params) = refit::selection(&rounds, last);
    let diagnosis = diagnose::diagnose(&first.p, &first.sel.baseline.residuals);
    let consts = (
        cfg.lsq.damping_floor,
        set.world.air_density,
        set.object.reference_length,
    );
    // Before and after on the same frames: the base model scored, fitted
    // for the re-simulation and flown on the round `after` comes from.
    let same = refit::base_on(set, last, given);
    let (before_round, base_p, base) = match &same {
        Some(b) => (last, b.problems(last), &b.scored),
        None => (first, &first.p, &first.sel.baseline),
    };
    let n = set.takes.len();
    let base_models = held_out_models(
        n,
        base_p,
        &before_round.candidates_model(given),
        &[],
        consts,
    );
    let extended_models = held_out_models(
        n,
        &last.p,
        &last.candidates_model(given),
        &last.sel.selected,
        consts,
    );
    let resimulation = resimulate::compare(
        set,
        &resimulate::Run {
            reconstruction: &before_round.outcome.reconstruction,
            models: &base_models,
            wind: Vector3::zeros(),
        },
        &resimulate::Run {
            reconstruction: &last.outcome.reconstruction,
            models: &extended_models,
            wind: rounds.wind.unwrap_or_else(Vector3::zeros),
        },
    );
    // "Before" is the base model: the given one when there is one (it
    // is every round's baseline), not the first round's own fit.
    let cf_error_vs_truth = truth_error(
        dir,
        given.unwrap_or(&first.outcome.model),
        &last.ext.model,
        &last.outcome.samples,
    );
    let candidates: Vec<CandidateReport> = last
        .sel
        .tried
        .iter()
        .map(|t| CandidateReport {
            effect: t.candidate.name().to_owned(),
            step: t.step,
            heldout_force_rms: t.force_rms,
            heldout_torque_rms: t.torque_rms,
            gain: t.gain,
            torque_gain: t.torque_gain,
            score_gain: t.score_gain,
            takes_better: t.takes_better.0,
            takes: t.takes_better.1,
            params: t.params.clone(),
            uncertainty: t.uncertainty.clone(),
            rejected: t.rejected.clone(),
            unexplained_without_cf: t.unexplained_without_cf,
            beyond_cf: t.beyond_cf,
            null_gain: t.null_gain,
        })
        .collect();
    let truth = refit::truth_on(dir, set, last);
    let mut report = Report {
        baseline: HeldOut {
            heldout_force_rms: base.force_rms,
            heldout_torque_rms: base.torque_rms,
        },
        first_round_baseline: HeldOut {
            heldout_force_rms: first.sel.baseline.force_rms,
            heldout_torque_rms: first.sel.baseline.torque_rms,
        },
        baseline_model: if given.is_some() { "given" } else { "fitted" },
        baseline_frames: if same.is_some() {
            "final_round"
        } else {
            "first_round"
        },
        candidates,
        selected_params: params.iter().map(|(_, v)| v.clone()).collect(),
        selected,
        after: HeldOut {
            heldout_force_rms: last.sel.after.force_rms,
            heldout_torque_rms: last.sel.after.torque_rms,
        },
        resimulation,
        markers_only_force_noise_rms: markers_only_noise(&first.p.force_samples),
        cf_error_vs_truth,
        truth_model: truth.as_ref().ok().copied().flatten(),
        wind: rounds.wind.map(|w| [w.x, w.y, w.z]),
        diagnosis,
        words: Vec::new(),
        frames: last.p.force.frames.len(),
        takes: last.p.force.takes.len(),
        left_out_takes: last.outcome.left_out.clone(),
        refit: rounds.refit.clone(),
        null_calibration: first.null.clone(),
    };
    report.words = words::describe(&report, &params);
    report.words.extend(refit::describe(&report.refit));
    if same.is_none() {
        report.words.push(
            "The base model could not be scored on the final round's frames (back in still air): `baseline` is its score on the first round's states, so before and after are not on the same frames.".into(),
        );
    }
    if let Err(why) = truth {
        report
            .words
            .push(format!("The truth's model could not be scored: {why}."));
    }
    let mut table = frames::rows("base", base_p, &base.residuals);
    table.extend(frames::rows(
        "first_round",
        &first.p,
        &first.sel.baseline.residuals,
    ));
    table.extend(frames::rows("extended", &last.p, &last.sel.after.residuals));
    Ok(Analysis {
        report,
        base: first.outcome.model.clone(),
        extended: last.ext.model.clone(),
        frames: table,
    })
}

/// `sqrt(mean tr Σ_F)` of `samples`, N (see
/// [`Report::markers_only_force_noise_rms`]).
fn markers_only_noise(samples: &[crate::reconstruct::forces::Sample]) -> f64 {
    let n = samples.len().max(1) as f64;
    (samples.iter().map(|s| s.force_cov.trace()).sum::<f64>() / n).sqrt()
}

/// C_F error of both models against `dir/truth/coefficients.csv`, over
/// the directions the frames cover (as `omniad lab accept`: 20 frames
/// within 15°).
fn truth_error(
    dir: &Path,
    base: &Coefficients<f64>,
    extended: &Coefficients<f64>,
    samples: &[crate::reconstruct::forces::Sample],
) -> Option<TruthError> {
    use crate::synth::truth::{fitted_directions, force_error, read_coefficients};
    let path = dir.join("truth").join("coefficients.csv");
    if !path.exists() {
        return None;
    }
    let truth = read_coefficients(&path).ok()?;
    let dirs = fitted_directions(samples);
    let angle = 15f64.to_radians();
    let (before, directions) = force_error(base, &truth, &dirs, 20, angle);
    let (after, _) = force_error(extended, &truth, &dirs, 20, angle);
    Some(TruthError {
        before,
        after,
        directions,
    })
}
