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
//!   change;
//! * a named effect is estimated whole on each round's states (the frames'
//!   air wrench holds all of it) and must be selected again: a round that
//!   does not keep every effect it held is not a confirmation. On the
//!   first states an added mass that predicts held-out takes
//!   significantly better ([`significant`]) but was not kept (not
//!   positive semi-definite) is tried in the process model projected onto
//!   PSD tensors ([`omniad_core::math::nearest_psd`]) when no named
//!   effect was kept: it is kept only when the refitted states confirm it
//!   (selected, plausible).
//!
//! Rounds stop when the state effects are the same as the round's own and
//! the wind and each effect change by less than [`state::WIND_TOLERANCE`]
//! and [`state::EFFECT_TOLERANCE`], after at most [`MAX_REFITS`] refits.
//! When no refit confirms the effects, the first round's result stands.
//! Generic blocks (spin, gravity coupling) stay out of the process model:
//! they are the last resort, not physics to predict with.

mod state;

use crate::error::{Error, Result};
use crate::fit::context::FitContext;
use crate::input::recording::RecordingSet;
use crate::pipeline::{fit, FitConfig, FitOutcome};
use crate::reconstruct::run::Progress;
use crate::residual::candidates::{Candidate, ColumnContext, ALL};
use crate::residual::extend::{extend, Extended};
use crate::residual::null;
use crate::residual::problems::{self, Problems};
use crate::residual::select::{self, gain_bar, sign_threshold, Selection, MIN_GAIN};
use nalgebra::Vector3;
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::Coefficients;
use serde::Serialize;
use state::{accelerate, added_mass_effect, psd, steps, StateEffects, Steps};
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
    let mut base_cfg = cfg.clone();
    base_cfg.lsq.extensions = false;
    base_cfg.filter.wind = effects.wind.unwrap_or_else(Vector3::zeros);
    base_cfg.effects = effects.effects.clone();
    let outcome = fit(set, &base_cfg, progress)?;
    let smoothing = outcome
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .and_then(|r| r.smoothing)
        .ok_or_else(|| Error::Data("the base fit chose no smoothing".into()))?;
    // The coefficients alone: the frames' air wrench holds the process
    // model's effects, which the selection estimates again.
    // A given baseline is held as it is (`fixed::hold`).
    let model = match given {
        Some(g) => g.clone(),
        None => {
            let mut m = outcome.model.clone();
            EffectKind::ALL.iter().for_each(|k| m.remove_effect(*k));
            m
        }
    };
    let ctx = FitContext::of_set(set);
    let cols = ColumnContext {
        air_density: set.world.air_density,
        reference_length: set.object.reference_length,
        model: &model,
    };
    progress.stage("residual: normal equations", 1);
    let p = problems::build(
        &outcome.samples,
        &outcome.reconstruction,
        &ctx,
        &cols,
        usize::from(given.map_or(cfg.degree, |g| g.degree())),
        smoothing,
    );
    let p = match given {
        Some(g) => super::fixed::hold(p, g)?,
        None => p,
    };
    progress.tick();
    Ok((outcome, model, p))
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
    let (outcome, model, p) = prepare(set, cfg, &effects, given, progress)?;
    let null = match null {
        Some(n) => n.clone(),
        None => calibrate(set, cfg, &outcome, &model, given, progress),
    };
    let (rho, l) = (set.world.air_density, set.object.reference_length);
    let gains = NullCalibration::in_order(null.as_ref());
    let sel = select::select(&p, rho, l, &gains, progress).ok_or_else(|| {
        Error::Data(format!(
            "the residual analysis needs at least {} takes with usable frames",
            crate::fit::select::MIN_TAKES
        ))
    })?;
    let ext = extend(&p, &model, &sel.selected, cfg.lsq.damping_floor)?;
    Ok(Round {
        effects,
        outcome,
        p,
        sel,
        ext,
        null,
    })
}

/// Whether a tried candidate predicts held-out takes significantly better
/// (gain at least [`MIN_GAIN`] above its null gain, sign test passed),
/// plausible or not.
fn significant(t: &select::Tried) -> bool {
    t.gain >= gain_bar(t.null_gain) && t.takes_better.0 >= sign_threshold(t.takes_better.1)
}

/// The state effects round `r` points to: its wind (added to the wind it
/// carried) and its selected named effects, in selection order.
fn proposal(r: &Round, first: bool) -> StateEffects {
    let param = |c: Candidate| r.ext.params.iter().find(|(d, _)| *d == c).map(|x| &x.1);
    let wind = match (param(Candidate::Wind), r.effects.wind) {
        (Some(v), carried) => {
            let dw = Vector3::new(v[0], v[1], v[2]);
            Some(carried.unwrap_or_else(Vector3::zeros) + dw)
        }
        (None, carried) => carried,
    };
    let mut effects: Vec<Effect<f64>> = r
        .sel
        .selected
        .iter()
        .enumerate()
        .filter_map(|(step, c)| match *c {
            // Added mass as estimated when it was kept (with alpha and the
            // effects kept before it): later effects fitted jointly with
            // it can share its columns (buoyancy's Rᵀg and a drop's dU/dt
            // are nearly parallel).
            Candidate::Named(EffectKind::AddedMass) => r
                .sel
                .tried
                .iter()
                .find(|t| t.candidate == *c && t.step == step)
                .and_then(|t| psd(&t.params))
                .and_then(|m| added_mass_effect(&m)),
            // The others as the extended model's joint fit has them.
            Candidate::Named(kind) => param(*c).and_then(|v| Effect::new(kind, v)),
            _ => None,
        })
        .collect();
    // A significant added mass that was not kept is tried only when no
    // named effect explains the first states (generic blocks or nothing
    // were kept): next to one that does, it is a rival explanation
    // (isotropic added mass copies buoyancy, `identify.rs`), not a
    // missing piece, and a refit holding both confirms neither.
    let am = Candidate::Named(EffectKind::AddedMass);
    if first && effects.is_empty() {
        let implausible = r
            .sel
            .tried
            .iter()
            .find(|t| t.step == 0 && t.candidate == am && significant(t))
            .and_then(|t| psd(&t.params))
            .and_then(|m| added_mass_effect(&m));
        effects.extend(implausible);
    }
    StateEffects { wind, effects }
}

/// One round in the report.
#[derive(Clone, Debug, Serialize)]
pub struct RefitRound {
    /// The process model's wind (world, m/s), if any.
    pub wind: Option<[f64; 3]>,
    /// The process model's named effects and their parameters (the
    /// library's order and units; added mass xx, yy, zz, xy, xz, yz, kg).
    pub effects: BTreeMap<&'static str, Vec<f64>>,
    /// The round's selection.
    pub selected: Vec<String>,
    /// Held-out force RMS of its base model and of its selection, N.
    pub heldout_force_rms: [f64; 2],
}

/// What the refit did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Refit {
    /// Refits run (rounds after the first).
    pub refits: usize,
    /// The last round's state effects agreed with what it found (within
    /// the tolerances); false when the cap stopped the rounds or no refit
    /// confirmed the effect.
    pub converged: bool,
    /// Whether a refit's states confirmed the effects (otherwise the first
    /// round's result is reported).
    pub confirmed: bool,
    /// The refits held force effects only (no wind, no added mass),
    /// confirmed them, but predicted held-out takes less than [`MIN_GAIN`]
    /// better than the first round: the first round's result stands.
    pub no_gain: bool,
    /// The wind found on the states reconstructed without it (world, m/s).
    pub wind_before_refilter: Option<[f64; 3]>,
    /// The wind after the refits.
    pub wind_after_refilter: Option<[f64; 3]>,
    /// Every round, the first (no state effect) first.
    pub rounds: Vec<RefitRound>,
}

fn summary(r: &Round) -> RefitRound {
    RefitRound {
        wind: r.effects.wind.map(|w| [w.x, w.y, w.z]),
        effects: r
            .effects
            .effects
            .iter()
            .map(|e| (e.kind.name(), e.used_params().to_vec()))
            .collect(),
        selected: r.sel.selected.iter().map(|c| c.name().to_owned()).collect(),
        heldout_force_rms: [r.sel.baseline.force_rms, r.sel.after.force_rms],
    }
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
    let as_array = |w: Option<Vector3<f64>>| w.map(|w| [w.x, w.y, w.z]);
    let mut refit = Refit {
        wind_before_refilter: as_array(trial.wind),
        rounds: vec![summary(&first)],
        ..Refit::default()
    };
    let mut last: Option<(Round, Option<Vector3<f64>>)> = None;
    let mut previous: Option<Steps> = None;
    while !trial.is_empty() && refit.refits < MAX_REFITS {
        let r = round(set, cfg, trial.clone(), given, Some(&first.null), progress)?;
        refit.refits += 1;
        refit.rounds.push(summary(&r));
        let next = proposal(&r, false);
        // An effect the refitted states do not select again is not
        // confirmed: the last confirmed round (or the first) stands.
        if !trial.kinds_within(&next) {
            refit.converged = false;
            break;
        }
        refit.converged = next.close_to(&trial);
        last = Some((r, next.wind));
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

/// The refit in words.
pub(crate) fn describe(r: &Refit) -> Vec<String> {
    if r.rounds.len() < 2 {
        return Vec::new();
    }
    let what = r.rounds.get(1).map_or_else(String::new, |x| {
        let names = x
            .wind
            .iter()
            .map(|_| "wind")
            .chain(x.effects.keys().copied());
        names.collect::<Vec<_>>().join(", ")
    });
    let mut out = vec![format!(
        "Refit around the effect: every take was reconstructed and fitted again with the effects found ({what}) in the process model, {} time(s); {}.",
        r.refits,
        match (r.confirmed, r.converged) {
            _ if r.no_gain => format!(
                "the refitted states confirmed it but predicted held-out takes less than {:.0} % better, so the first result stands",
                MIN_GAIN * 100.0
            ),
            (false, _) => "the refitted states did not confirm it, so the first result stands".into(),
            (true, true) => "the selection and the parameters settled".into(),
            (true, false) => "the parameters had not settled at the cap".into(),
        }
    )];
    if let (Some(a), Some(b)) = (r.wind_before_refilter, r.wind_after_refilter) {
        out.push(format!(
            "Wind before the refilter [{:.3}, {:.3}, {:.3}] m/s, after [{:.3}, {:.3}, {:.3}] m/s.",
            a[0], a[1], a[2], b[0], b[1], b[2]
        ));
    }
    out
}
