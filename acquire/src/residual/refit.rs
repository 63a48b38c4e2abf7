//! Refit around the effect (issue 15, item 4). In a model-based
//! reconstruction every effect the model lacks changes the states the
//! forces are reconstructed from, not only the forces: the filter's
//! process model (eqs. 1-2 with the model's wrench) explains the missing
//! force by the states and its bias wrench, which pulls the reconstructed
//! forces toward the model without it. A steady wind (the air velocity is
//! `Rᵀ(v - w)`, eqs. 5-6), added mass (its `-M_a dU/dt` belongs on the mass
//! side of eq. 1, `omniad_core::rigid_body::state_rate_with_added_mass`)
//! and every other named effect the core evaluates (buoyancy, rotational
//! lift, propeller thrust, linear drag: `omniad_core::effect`) are
//! therefore put into the process model once the first round selects
//! them (`pipeline::process_effects`: `FilterConfig::wind`,
//! `FitConfig::effects`); each round reconstructs and fits every take
//! again and runs the selection on the new states:
//! * the wind is a Gauss-Newton iteration: the wind candidate of a round
//!   is linearised about the round's wind and its estimate is added to it;
//!   a wind carried into a round stays when the round finds no significant
//!   change (the increment kept by the selection, or still moving by its
//!   own jackknife uncertainty and helping, linearised or judged exactly
//!   on the round's frames, `proposal::still_moving`, [`wind_step`]);
//! * a named effect is estimated whole on each round's states (the frames'
//!   air wrench holds all of it) and must be selected again: a round that
//!   does not keep every effect it held is not a confirmation. On the
//!   first states an added mass that predicts held-out takes
//!   significantly better ([`significant`]) but was not kept (not
//!   positive semi-definite) is tried in the process model projected onto
//!   PSD tensors ([`omniad_core::math::nearest_psd`]) when no named
//!   effect was kept, and carried on (tentatively, re-projected each
//!   round) while the rounds that hold it still find it significant: it
//!   is kept only when the refitted states confirm it (selected,
//!   plausible); where its coupling alone (added mass without the
//!   acceleration reaction, a stateless fluid model's air) predicts the
//!   held-out force better, the coupling is the reading tried, and a
//!   round that moves from one reading of M_a to the other (or drops a
//!   coupling's rotational lift) has kept the term
//!   ([`crate::residual::candidates::Candidate::excludes`]);
//! * where the first states cannot read M_a (added mass significant with
//!   nothing positive to try, or the coupling about to start the
//!   refits), the markers' innovation likelihood of refinements holding
//!   multiples of the object's potential-flow added mass picks the start
//!   ([`likelihood_probe`]): the likelihood scores predictions of the raw
//!   markers, so it does not lean toward the model the states were
//!   reconstructed with;
//! * a round is judged take by take ([`takes`]): a take whose held-out
//!   error jumps while the others settle, or whose markers the round's
//!   reconstruction misses by more than their noise beyond its first-round
//!   fit ([`markers`]; its reconstruction broke in that round), is named
//!   and left out of that round's selection, proposal and comparison.
//!
//! Rounds stop when the state effects are the same as the round's own,
//! the wind and each effect change by less than [`state::WIND_TOLERANCE`]
//! and [`state::EFFECT_TOLERANCE`] and the wind no longer moves
//! significantly, after at most [`MAX_REFITS`] refits; a round the rounds
//! converge on that predicts held-out takes clearly worse than the
//! confirmed round before it leaves that round standing
//! ([`worse_than_before`]).
//! When no refit confirms the effects, the first round's result stands.
//! Generic blocks (spin, gravity coupling) stay out of the process model:
//! they are the last resort, not physics to predict with.

mod base_states;
mod likelihood_probe;
mod markers;
mod proposal;
mod report;
mod state;
mod takes;
mod truth_model;
mod wind_search;
mod wind_step;

pub(crate) use base_states::base_on;
pub use likelihood_probe::AddedMassProbe;
use proposal::{in_doubt, proposal, tentative, wind_moved};
pub(crate) use report::describe;
use report::summary;
pub use report::{JumpedTake, Refit, RefitRound};
pub(crate) use truth_model::truth_on;
use wind_search::FirstStates;
pub use wind_search::WindSearch;

use crate::error::{Error, Result};
use crate::fit::context::FitContext;
use crate::input::recording::RecordingSet;
use crate::pipeline::{fit, FitConfig, FitOutcome};
use crate::reconstruct::forces::Sample;
use crate::reconstruct::run::Progress;
use crate::residual::candidates::{Candidate, ColumnContext, ALL};
use crate::residual::extend::{extend, Extended};
use crate::residual::null;
use crate::residual::problems::{self, Problems};
use crate::residual::select::{self, Selection, MIN_GAIN};
use nalgebra::Vector3;
use omniad_core::effect::EffectKind;
use omniad_core::Coefficients;
use serde::Serialize;
use state::{accelerate, steps, StateEffects, Steps};
use std::cell::RefCell;
use std::collections::BTreeMap;

/// Most refits (rounds after the first).
pub const MAX_REFITS: usize = 5;

/// One round: the fit with the state effects in the process model, the
/// selection on its states and the extended model.
pub(crate) struct Round {
    /// The process model's state effects.
    pub effects: StateEffects,
    /// The refinement's outcome (its model carries the round's named
    /// effects).
    pub outcome: FitOutcome,
    /// The joint problems on its frames.
    pub p: Problems,
    /// The selection.
    pub sel: Selection,
    /// The selected design fitted on all takes (no process-model effect).
    pub ext: Extended,
    /// The null calibration the selection used (the first round's).
    pub null: Option<NullCalibration>,
    /// The carried wind's significant increment (or a halving of it) that
    /// the linearised judgement rejected and the exact one accepts
    /// ([`wind_step`]); `None` otherwise.
    pub judged_step: Option<Vector3<f64>>,
}

impl Round {
    /// The round's selection without the wind: the effects a wind blows
    /// beside (the wind search and the exact wind step judge the wind on
    /// top of them).
    pub(super) fn selected_besides_wind(&self) -> Vec<Candidate> {
        self.sel
            .selected
            .iter()
            .copied()
            .filter(|c| *c != Candidate::Wind)
            .collect()
    }

    /// The round's frames of the takes its selection scored (a take left
    /// out of the round, [`takes::jumps`], is not among them).
    pub(super) fn selection_samples(&self) -> Vec<Sample> {
        let takes = &self.p.force.take_ids;
        self.outcome
            .samples
            .iter()
            .filter(|s| takes.contains(&s.take))
            .copied()
            .collect()
    }

    /// The model the round's candidates are fitted against: its
    /// coefficients alone, or `given`.
    pub(crate) fn candidates_model(&self, given: Option<&Coefficients<f64>>) -> Coefficients<f64> {
        given.cloned().unwrap_or_else(|| bare(&self.outcome.model))
    }
}

/// The fit of `set` with `effects` in the process model, the model the
/// candidates are fitted against (the coefficients alone, or `given`) and
/// the joint problems on its states.
fn prepare(
    set: &RecordingSet,
    cfg: &FitConfig,
    effects: &StateEffects,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Result<(FitOutcome, Coefficients<f64>, Problems)> {
    let outcome = fit(set, &round_config(cfg, effects), progress)?;
    let (model, p) = problems_of(set, &outcome, given, &[], progress)?;
    Ok((outcome, model, p))
}

/// The refinement's settings of a round with `effects` in the process
/// model (no generic blocks: they are the selection's to try).
fn round_config(cfg: &FitConfig, effects: &StateEffects) -> FitConfig {
    let mut base_cfg = cfg.clone();
    base_cfg.lsq.extensions = false;
    base_cfg.filter.wind = effects.wind.unwrap_or_else(Vector3::zeros);
    base_cfg.effects = effects.effects.clone();
    base_cfg
}

/// The model the candidates are fitted against and the joint problems on
/// the states of `outcome`, without the frames of the takes in `skip`.
fn problems_of(
    set: &RecordingSet,
    outcome: &FitOutcome,
    given: Option<&Coefficients<f64>>,
    skip: &[usize],
    progress: &dyn Progress,
) -> Result<(Coefficients<f64>, Problems)> {
    // The coefficients alone: the frames' air wrench holds the process
    // model's effects, which the selection estimates again.
    // A given baseline is held as it is (`fixed::hold`).
    let model = match given {
        Some(g) => g.clone(),
        None => bare(&outcome.model),
    };
    progress.stage("residual: normal equations", 1);
    let kept: Vec<_> = outcome
        .samples
        .iter()
        .filter(|s| !skip.contains(&s.take))
        .copied()
        .collect();
    let p = problems_on(set, outcome, &kept, &model)?;
    let p = match given {
        Some(g) => super::fixed::hold(p, g)?,
        None => p,
    };
    progress.tick();
    Ok((model, p))
}

/// A fitted model without its effects.
pub(crate) fn bare(model: &Coefficients<f64>) -> Coefficients<f64> {
    let mut m = model.clone();
    EffectKind::ALL.iter().for_each(|k| m.remove_effect(*k));
    m
}

/// The joint problems on `samples` (frames of `outcome`'s states), with
/// `outcome`'s smoothing and `model` for the wind's linearisation.
fn problems_on(
    set: &RecordingSet,
    outcome: &FitOutcome,
    samples: &[Sample],
    model: &Coefficients<f64>,
) -> Result<Problems> {
    let smoothing = outcome
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .and_then(|r| r.smoothing)
        .ok_or_else(|| Error::Data("the base fit chose no smoothing".into()))?;
    let ctx = FitContext::of_set(set);
    let cols = ColumnContext {
        air_density: set.world.air_density,
        reference_length: set.object.reference_length,
        model,
    };
    Ok(problems::build(
        set.object.mass,
        samples,
        &outcome.reconstruction,
        &ctx,
        &cols,
        (
            usize::from(model.degree()),
            usize::from(model.torque_degree()),
        ),
        smoothing,
    ))
}

/// The step-0 gain of added mass when the first round proposes it
/// (selected, or tentative in `proposal`); 0 when it does not.
fn rival(first: &Round, proposed: &StateEffects) -> f64 {
    let am = Candidate::Named(EffectKind::AddedMass);
    let proposes =
        first.sel.selected.contains(&am) || proposed.effect(EffectKind::AddedMass).is_some();
    let step0 = first
        .sel
        .tried
        .iter()
        .find(|t| t.step == 0 && t.candidate == am);
    step0.filter(|_| proposes).map_or(0.0, |t| t.gain)
}

/// The wind search on the first round's states ([`wind_search`]) when
/// the base model is fitted (not given); a wind the round kept (its
/// linear step) is one of its starts.
fn search_wind(
    set: &RecordingSet,
    cfg: &FitConfig,
    (first, proposed): (&Round, &StateEffects),
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Option<WindSearch> {
    if given.is_some() {
        return None;
    }
    let kept = first.sel.selected.contains(&Candidate::Wind);
    let selection = first.selected_besides_wind();
    let (rho, l) = (set.world.air_density, set.object.reference_length);
    let model = RefCell::new(bare(&first.outcome.model));
    // One bar for the search, a tick per wind judged (its length the most
    // it can judge; the search usually stops well before).
    progress.stage("residual: wind search", wind_search::MAX_JUDGED);
    let build = |samples: &[Sample]| -> Option<Problems> {
        // C_F refitted on these frames, then the problems linearised about it.
        let m = model.borrow().clone();
        let p = problems_on(set, &first.outcome, samples, &m).ok()?;
        let refitted = extend(&p, &m, &[], (cfg.lsq.damping_floor, rho, l))
            .ok()?
            .model;
        let p = problems_on(set, &first.outcome, samples, &refitted).ok()?;
        *model.borrow_mut() = refitted;
        progress.tick();
        Some(p)
    };
    let at = ALL.iter().position(|c| *c == Candidate::Wind).unwrap_or(0);
    let null_gain = NullCalibration::in_order(first.null.as_ref())
        .get(at)
        .copied()
        .unwrap_or(0.0);
    let states = FirstStates {
        samples: &first.outcome.samples,
        reconstruction: &first.outcome.reconstruction,
        baseline: &first.sel.baseline,
        linear: proposed.wind.filter(|_| kept),
        selection: &selection,
        rival: rival(first, proposed),
        null_gain,
        up: -set
            .world
            .gravity
            .try_normalize(f64::EPSILON)
            .unwrap_or_else(|| -Vector3::z()),
    };
    wind_search::search(&states, &build)
}

/// Round `r` with its carried wind's increment judged exactly
/// ([`wind_step`]) when it is significant but its linearised judgement
/// rejected it, the selection did not keep it and the base model is
/// fitted (not given).
fn judge_wind_step(
    set: &RecordingSet,
    r: Round,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Round {
    let rejected = proposal::significant_increment(&r.sel.tried).filter(|(_, helps)| !helps);
    let Some((dw, _)) = rejected else {
        return r;
    };
    if given.is_some() || r.effects.wind.is_none() || r.sel.selected.contains(&Candidate::Wind) {
        return r;
    }
    progress.stage(
        "residual: the wind's step judged exactly",
        2 + wind_search::HALVINGS,
    );
    let model = bare(&r.outcome.model);
    let build = |samples: &[Sample]| -> Option<Problems> {
        progress.tick();
        problems_on(set, &r.outcome, samples, &model).ok()
    };
    let judged_step = wind_step::judge(&r, dw, &build);
    Round { judged_step, ..r }
}

/// The null calibration ([`super::null`]) of the first round: the set
/// re-simulated [`null::DRAWS`] times with the round's model from its
/// states (each with its own noise draw), reconstructed and fitted the
/// same way, and each candidate's step-0 gain there. `None` (no
/// calibration: every null bound 0) when fewer than two replicas can be
/// made and analysed, e.g. too few takes survive.
fn calibrate(
    set: &RecordingSet,
    cfg: &FitConfig,
    outcome: &FitOutcome,
    model: &Coefficients<f64>,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Option<NullCalibration> {
    let mut draws = Vec::new();
    for draw in 0..null::DRAWS {
        progress.stage("residual: null replica (the set without effects)", 1);
        let Some(replica) = null::replica(set, &outcome.reconstruction, model, draw) else {
            continue;
        };
        let Ok((_, _, p)) = prepare(&replica, cfg, &StateEffects::default(), given, progress)
        else {
            continue;
        };
        draws.extend(select::null_gains(&p));
    }
    if draws.len() < 2 {
        return None;
    }
    let n = draws.len() as f64;
    let gains = ALL.iter().enumerate().map(|(i, c)| {
        let g: Vec<f64> = draws
            .iter()
            .map(|d| d.1.get(i).copied().unwrap_or(0.0))
            .collect();
        (
            c.name(),
            NullGains {
                bound: null::bound(&g),
                draws: g,
            },
        )
    });
    Some(NullCalibration {
        heldout_force_rms: draws.iter().map(|d| d.0).sum::<f64>() / n,
        gains: gains.collect(),
    })
}

/// One candidate's gains on the null replicas.
#[derive(Clone, Debug, Serialize)]
pub struct NullGains {
    /// Its held-out force gain on each replica (step 0).
    pub draws: Vec<f64>,
    /// Their mean plus [`null::Z`] standard deviations ([`null::bound`]).
    pub bound: f64,
}

/// What the null replicas gave ([`super::null`]).
#[derive(Clone, Debug, Serialize)]
pub struct NullCalibration {
    /// The replicas' base model's held-out force RMS (mean), N.
    pub heldout_force_rms: f64,
    /// Each candidate's gains on the replicas and their bound.
    pub gains: BTreeMap<&'static str, NullGains>,
}

impl NullCalibration {
    /// The null bounds in the order of [`ALL`] (0 when absent).
    fn in_order(c: Option<&Self>) -> Vec<f64> {
        ALL.iter()
            .map(|a| {
                c.and_then(|c| c.gains.get(a.name()))
                    .map_or(0.0, |g| g.bound)
            })
            .collect()
    }
}

/// Runs one round with `effects` in the process model; `null` is the first
/// round's calibration (`None` in the first round: it is made from its
/// states, and returned in the round).
pub(crate) fn round(
    set: &RecordingSet,
    cfg: &FitConfig,
    effects: StateEffects,
    given: Option<&Coefficients<f64>>,
    null: Option<&Option<NullCalibration>>,
    progress: &dyn Progress,
) -> Result<Round> {
    let outcome = fit(set, &round_config(cfg, &effects), progress)?;
    round_on(set, cfg, (effects, outcome), given, null, progress)
}

/// [`round`] on the refinement `outcome` already made with `effects` in
/// the process model (with [`round_config`]'s settings).
fn round_on(
    set: &RecordingSet,
    cfg: &FitConfig,
    (effects, outcome): (StateEffects, FitOutcome),
    given: Option<&Coefficients<f64>>,
    null: Option<&Option<NullCalibration>>,
    progress: &dyn Progress,
) -> Result<Round> {
    let (model, p) = problems_of(set, &outcome, given, &[], progress)?;
    let null = match null {
        Some(n) => n.clone(),
        None => calibrate(set, cfg, &outcome, &model, given, progress),
    };
    let (sel, ext) = select_on(set, cfg, &p, &model, null.as_ref(), progress)?;
    Ok(Round {
        effects,
        outcome,
        p,
        sel,
        ext,
        null,
        judged_step: None,
    })
}

/// The selection on `p` and its extended model.
fn select_on(
    set: &RecordingSet,
    cfg: &FitConfig,
    p: &Problems,
    model: &Coefficients<f64>,
    null: Option<&NullCalibration>,
    progress: &dyn Progress,
) -> Result<(Selection, Extended)> {
    let (rho, l) = (set.world.air_density, set.object.reference_length);
    let gains = NullCalibration::in_order(null);
    let sel = select::select(p, rho, l, &gains, progress).ok_or_else(|| {
        Error::Data(format!(
            "the residual analysis needs at least {} takes with usable frames",
            crate::fit::select::MIN_TAKES
        ))
    })?;
    let ext = extend(p, model, &sel.selected, (cfg.lsq.damping_floor, rho, l))?;
    Ok((sel, ext))
}

/// Round `r` with the takes in `skip` left out (their reconstruction broke
/// in it, [`takes::jumps`]): the same states, the selection run again on
/// the other takes. `r` as it is when too few takes would be left.
fn without(
    set: &RecordingSet,
    cfg: &FitConfig,
    r: Round,
    skip: &[usize],
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Round {
    let again = problems_of(set, &r.outcome, given, skip, progress).and_then(|(m, p)| {
        let (sel, ext) = select_on(set, cfg, &p, &m, r.null.as_ref(), progress)?;
        Ok((p, sel, ext))
    });
    match again {
        Ok((p, sel, ext)) => Round { p, sel, ext, ..r },
        Err(_) => r,
    }
}

/// Each take of round `r` (index in the set) with its selection's
/// weighted held-out force error (the round's own model on its states:
/// the base model's error moves take by take as much as the state effects
/// do, the round's selection's should settle).
fn per_take(r: &Round) -> Vec<(usize, f64)> {
    r.p.force
        .take_ids
        .iter()
        .copied()
        .zip(r.sel.after.per_take.iter().copied())
        .collect()
}

/// The rounds' result: the first round, the final one (`None`: the first
/// stands), the final wind, and the report.
pub(crate) struct Rounds {
    pub first: Round,
    pub last: Option<Round>,
    pub wind: Option<Vector3<f64>>,
    pub refit: Refit,
}

/// Runs the first round and the refits it calls for.
pub(crate) fn run(
    set: &RecordingSet,
    cfg: &FitConfig,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Result<Rounds> {
    let first = round(set, cfg, StateEffects::default(), given, None, progress)?;
    let mut trial = proposal(&first, true);
    // A wind the linear candidate could not reach (or reached only
    // roughly) replaces what the first round kept as the refit's start:
    // the rounds select the effects again on states reconstructed in it
    // ([`wind_search`]).
    let searched = search_wind(set, cfg, (&first, &trial), given, progress);
    if let Some(s) = searched.as_ref().filter(|s| s.accepted && s.moved()) {
        trial = StateEffects {
            wind: Some(Vector3::from(s.wind)),
            effects: Vec::new(),
        };
    }
    // An added mass the first states hide, or read as its coupling: the
    // markers' likelihood judges ([`likelihood_probe`]).
    let doubt = in_doubt(&first, &trial).filter(|_| given.is_none());
    let probed = doubt
        .as_ref()
        .and_then(|d| likelihood_probe::probe(set, cfg, &first, d, progress));
    let (probed, mut rival_outcome) = match probed {
        Some(p) => (Some(p.report), p.rival_outcome),
        None => (None, None),
    };
    if let (Some(e), Some(d)) = (probed.as_ref().and_then(AddedMassProbe::effect), doubt) {
        trial = StateEffects {
            wind: None,
            effects: d.others.into_iter().chain([e]).collect(),
        };
    }
    let as_array = |w: Option<Vector3<f64>>| w.map(|w| [w.x, w.y, w.z]);
    let mut refit = Refit {
        wind_before_refilter: as_array(trial.wind),
        wind_search: searched,
        added_mass_probe: probed,
        rounds: vec![summary(&first)],
        ..Refit::default()
    };
    let mut last: Option<(Round, Option<Vector3<f64>>)> = None;
    let mut previous: Option<Steps> = None;
    let mut before = per_take(&first);
    let pose_noise = cfg.filter.pose_position_noise;
    let mut reference = markers::per_take(set, &first.outcome.reconstruction, pose_noise);
    let names: Vec<&str> = set.takes.iter().map(|t| t.name.as_str()).collect();
    while !trial.is_empty() && refit.refits < MAX_REFITS {
        // The probe refined the rival, which is then `trial`, with this
        // round's settings: its refinement is this round's.
        let outcome = match rival_outcome.take() {
            Some(o) => o,
            None => fit(set, &round_config(cfg, &trial), progress)?,
        };
        let r = round_on(
            set,
            cfg,
            (trial.clone(), outcome),
            given,
            Some(&first.null),
            progress,
        )?;
        refit.refits += 1;
        let now = per_take(&r);
        let now_fit = markers::per_take(set, &r.outcome.reconstruction, pose_noise);
        let (skip, jumped) = takes::judge(&names, (&mut before, &now), (&mut reference, &now_fit));
        let r = if skip.is_empty() {
            r
        } else {
            without(set, cfg, r, &skip, given, progress)
        };
        let r = judge_wind_step(set, r, given, progress);
        refit.rounds.push(RefitRound {
            jumped_takes: jumped,
            ..summary(&r)
        });
        let next = proposal(&r, false);
        // An effect the refitted states neither select again nor (added
        // mass, [`proposal`]) still find significant is not confirmed:
        // the last confirmed round (or the first) stands.
        if !trial.kinds_within(&next) {
            refit.converged = false;
            break;
        }
        let confirmed = tentative(&r).is_empty();
        refit.converged = confirmed && next.close_to(&trial) && !wind_moved(&r);
        if refit.converged && worse_than_before(&r, last.as_ref().map(|l| &l.0)) {
            refit.kept_previous_round = true;
            break;
        }
        if confirmed {
            last = Some((r, next.wind));
        } else if next.close_to(&trial) {
            // Settled without being kept: it will not be confirmed.
            break;
        }
        if refit.converged {
            break;
        }
        let step = steps(&trial, &next);
        trial = accelerate(&trial, &next, &step, previous.as_ref());
        previous = Some(step);
    }
    refit.confirmed = last.is_some();
    let last = last.filter(|(r, _)| earns_its_place(&first, r));
    refit.no_gain = refit.confirmed && last.is_none();
    let (last, wind) = match last {
        Some((r, w)) => (Some(r), w),
        None => (None, first.ext.wind),
    };
    refit.wind_after_refilter = as_array(wind).filter(|_| last.is_some());
    Ok(Rounds {
        first,
        last,
        wind,
        refit,
    })
}

/// Whether round `r`, on which the rounds converged, predicts held-out
/// forces more than [`MIN_GAIN`] worse (RMS, N) than the confirmed round
/// before it (`previous`).
///
/// Why: converged, the round holds the same state effects as the round
/// before within the tolerances, so the two are readings of one fixed
/// point, and the one whose selection predicts held-out takes better is
/// the better reconstruction of it. Measured on MuJoCo's box in a (0.7,
/// -0.6, 0) m/s wind (seed 3): the third refit moved the wind by 0.05 m/s
/// and yet every take's held-out error rose 2-6 times (the refinement's
/// first, model-free fit residual 0.22 against 0.13 the round before),
/// and reporting it made the held-out force 1.27 times the baseline's
/// instead of 0.37.
fn worse_than_before(r: &Round, previous: Option<&Round>) -> bool {
    previous.is_some_and(|p| (1.0 - MIN_GAIN) * r.sel.after.force_rms > p.sel.after.force_rms)
}

/// Whether a confirmed refit replaces the first round's result.
///
/// Why: a wind or an added mass changes the kinematics the states are
/// reconstructed from, so its first-round estimate is biased (measured:
/// half of a 1 m/s wind) and the refit is needed whatever it gains. A force
/// effect (buoyancy, rotational lift, ...) enters only the model-based
/// smoothing, and holding it there feeds back on its own estimate: on the
/// shared `plate-buoyancy` the rounds moved V_b from -2 % to +10 % of the
/// truth while the held-out force stayed within 2 %. So a refit of force
/// effects must earn its place by the selection's own criterion: its
/// held-out force RMS at least [`MIN_GAIN`] below the first round's.
fn earns_its_place(first: &Round, last: &Round) -> bool {
    let moves_states =
        last.effects.wind.is_some() || last.effects.effect(EffectKind::AddedMass).is_some();
    moves_states || last.sel.after.force_rms <= (1.0 - MIN_GAIN) * first.sel.after.force_rms
}

/// The final selection's names and parameters: the last round's, with a
/// wind carried in its process model (and not changed significantly by
/// it) listed where the first round had it, at its full value.
pub(crate) fn selection(
    rounds: &Rounds,
    last: &Round,
) -> (Vec<String>, Vec<(Candidate, Vec<f64>)>) {
    let mut params = last.ext.params.clone();
    if let Some(w) = rounds.wind {
        let v = vec![w.x, w.y, w.z];
        match params.iter_mut().find(|(c, _)| *c == Candidate::Wind) {
            Some(slot) => slot.1 = v,
            None => {
                let at = rounds
                    .first
                    .sel
                    .selected
                    .iter()
                    .position(|c| *c == Candidate::Wind)
                    .unwrap_or(0)
                    .min(params.len());
                params.insert(at, (Candidate::Wind, v));
            }
        }
    }
    let names = params.iter().map(|(c, _)| c.name().to_owned()).collect();
    (names, params)
}
