//! Refit around the effect (issue 15, item 4). Two effects change the
//! states the forces are reconstructed from, not only the forces: a steady
//! wind (the air velocity is `Rᵀ(v - w)`, eqs. 5-6) and added mass (its
//! `-M_a dU/dt` belongs on the mass side of eq. 1,
//! `omniad_core::rigid_body::state_rate_with_added_mass`). Found on states
//! reconstructed without them, their parameters are biased (the filter's
//! process model explained their force by something else), so each round
//! here puts them into the process model
//! (`pipeline::process_effects`: `FilterConfig::wind`,
//! `FitConfig::added_mass`), reconstructs and fits every take again, and
//! runs the selection on the new states:
//! * the wind is a Gauss-Newton iteration: the wind candidate of a round
//!   is linearised about the round's wind and its estimate is added to it;
//!   a wind carried into a round stays when the round finds no significant
//!   change;
//! * added mass is estimated whole on each round's states (the frames'
//!   air wrench holds all of it) and must be selected again: a round that
//!   does not keep it drops it. On the first states an added mass that
//!   predicts held-out takes significantly better ([`significant`]) but is
//!   not positive semi-definite is tried in the process model projected
//!   onto PSD tensors ([`omniad_core::math::nearest_psd`]): it is kept
//!   only when the refitted states confirm it (selected, plausible).
//!
//! Rounds stop when the state effects are the same as the round's own and
//! the wind and M_a change by less than [`WIND_TOLERANCE`] and
//! [`ADDED_MASS_TOLERANCE`], after at most [`MAX_REFITS`] refits. When no
//! refit confirms an effect, the first round's result stands.

use crate::error::{Error, Result};
use crate::fit::context::FitContext;
use crate::input::recording::RecordingSet;
use crate::pipeline::{fit, FitConfig, FitOutcome};
use crate::reconstruct::run::Progress;
use crate::residual::candidates::{Candidate, ColumnContext};
use crate::residual::extend::{extend, Extended};
use crate::residual::problems::{self, Problems};
use crate::residual::select::{self, sign_threshold, Selection, MIN_GAIN};
use nalgebra::{Matrix3, Vector3};
use omniad_core::effect::EffectKind;
use omniad_core::Coefficients;
use serde::Serialize;

/// Most refits (rounds after the first).
pub const MAX_REFITS: usize = 5;

/// A wind change below `max(WIND_TOLERANCE, 5 % of |w|)` m/s ends the
/// rounds.
pub const WIND_TOLERANCE: f64 = 0.05;

/// A relative change of M_a (Frobenius norm) below this ends the rounds.
pub const ADDED_MASS_TOLERANCE: f64 = 0.1;

/// The effects of a round's process model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct StateEffects {
    /// Steady wind, world frame, m/s.
    pub wind: Option<Vector3<f64>>,
    /// Added mass, symmetric PSD, kg, body frame.
    pub added_mass: Option<Matrix3<f64>>,
}

impl StateEffects {
    fn is_empty(&self) -> bool {
        self.wind.is_none() && self.added_mass.is_none()
    }

    /// Same effects, each changed by less than its tolerance.
    fn close_to(&self, o: &Self) -> bool {
        let wind = match (self.wind, o.wind) {
            (None, None) => true,
            (Some(a), Some(b)) => (a - b).norm() <= WIND_TOLERANCE.max(0.05 * b.norm()),
            _ => false,
        };
        let mass = match (self.added_mass, o.added_mass) {
            (None, None) => true,
            (Some(a), Some(b)) => (a - b).norm() <= ADDED_MASS_TOLERANCE * b.norm(),
            _ => false,
        };
        wind && mass
    }
}

/// One round: the fit with the state effects in the process model, the
/// selection on its states and the extended model.
pub(crate) struct Round {
    /// The process model's state effects.
    pub effects: StateEffects,
    /// The refinement's outcome (its model carries the round's added mass).
    pub outcome: FitOutcome,
    /// The joint problems on its frames.
    pub p: Problems,
    /// The selection.
    pub sel: Selection,
    /// The selected design fitted on all takes (no process-model effect).
    pub ext: Extended,
}

/// Runs one round with `effects` in the process model.
pub(crate) fn round(
    set: &RecordingSet,
    cfg: &FitConfig,
    effects: StateEffects,
    given: Option<&Coefficients<f64>>,
    progress: &dyn Progress,
) -> Result<Round> {
    let mut base_cfg = cfg.clone();
    base_cfg.lsq.extensions = false;
    base_cfg.filter.wind = effects.wind.unwrap_or_else(Vector3::zeros);
    base_cfg.added_mass = effects.added_mass;
    let outcome = fit(set, &base_cfg, progress)?;
    let smoothing = outcome
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .and_then(|r| r.smoothing)
        .ok_or_else(|| Error::Data("the base fit chose no smoothing".into()))?;
    // The coefficients alone: the frames' air wrench holds the process
    // model's added mass, which the selection estimates again.
    // A given baseline is held as it is (`fixed::hold`).
    let model = match given {
        Some(g) => g.clone(),
        None => {
            let mut m = outcome.model.clone();
            m.remove_effect(EffectKind::AddedMass);
            m
        }
    };
    let (rho, l) = (set.world.air_density, set.object.reference_length);
    let ctx = FitContext {
        air_density: rho,
        reference_length: l,
        pole: set.object.pole,
    };
    let cols = ColumnContext {
        air_density: rho,
        reference_length: l,
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
    let sel = select::select(&p, rho, l, progress).ok_or_else(|| {
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
    })
}

/// Whether a tried candidate predicts held-out takes significantly better
/// (gain at least [`MIN_GAIN`], sign test passed), plausible or not.
fn significant(t: &select::Tried) -> bool {
    t.gain >= MIN_GAIN && t.takes_better.0 >= sign_threshold(t.takes_better.1)
}

/// Symmetric tensor of six parameters (xx, yy, zz, xy, xz, yz) projected
/// onto PSD tensors; `None` when nothing positive is left.
fn psd(six: &[f64]) -> Option<Matrix3<f64>> {
    let s: [f64; 6] = std::array::from_fn(|i| six.get(i).copied().unwrap_or(0.0));
    let m = omniad_core::math::nearest_psd(&omniad_core::math::symmetric_from_six(s));
    (m.iter().all(|x| x.is_finite()) && m.trace() > 0.0).then_some(m)
}

/// The state effects round `r` points to.
fn proposal(r: &Round, first: bool) -> StateEffects {
    let param = |c: Candidate| r.ext.params.iter().find(|(d, _)| *d == c).map(|x| &x.1);
    let wind = match (param(Candidate::Wind), r.effects.wind) {
        (Some(v), carried) => {
            let dw = Vector3::new(v[0], v[1], v[2]);
            Some(carried.unwrap_or_else(Vector3::zeros) + dw)
        }
        (None, carried) => carried,
    };
    // Added mass as estimated when it was kept (with alpha and the effects
    // kept before it): later effects fitted jointly with it can share its
    // columns (buoyancy's Rᵀg and a drop's dU/dt are nearly parallel).
    let am = Candidate::Named(EffectKind::AddedMass);
    let kept = r
        .sel
        .selected
        .iter()
        .position(|c| *c == am)
        .and_then(|step| {
            r.sel
                .tried
                .iter()
                .find(|t| t.candidate == am && t.step == step)
        });
    let added_mass = match kept {
        Some(t) => psd(&t.params),
        None if first => r
            .sel
            .tried
            .iter()
            .find(|t| t.step == 0 && t.candidate == am && significant(t))
            .and_then(|t| psd(&t.params)),
        None => None,
    };
    StateEffects { wind, added_mass }
}

/// Largest contraction ratio [`accelerate`] extrapolates with (a ratio
/// near 1 would send the estimate far on a noisy step).
pub const MAX_RATIO: f64 = 0.75;

/// A round's change of each state effect (wind, m/s; M_a's six, kg); empty
/// where the effect is not in both.
#[derive(Clone, Debug, Default)]
struct Steps {
    wind: Vec<f64>,
    added_mass: Vec<f64>,
}

fn steps(trial: &StateEffects, next: &StateEffects) -> Steps {
    let six = omniad_core::math::six_from_symmetric::<f64>;
    Steps {
        wind: match (trial.wind, next.wind) {
            (Some(a), Some(b)) => (b - a).iter().copied().collect(),
            _ => Vec::new(),
        },
        added_mass: match (trial.added_mass, next.added_mass) {
            (Some(a), Some(b)) => six(&(b - a)).to_vec(),
            _ => Vec::new(),
        },
    }
}

/// Aitken's extrapolation of the fixed-point iteration `x -> f(x)` (one
/// round: the state effects found on states reconstructed with `x`),
/// which converges linearly: with successive steps `d = f(x) - x` and
/// `d'` the previous one, the contraction ratio is `r ≈ (d·d')/|d'|²`
/// (clamped to `[-MAX_RATIO, MAX_RATIO]`) and the fixed point
/// `x + d/(1 - r)`; per effect (wind and M_a have their own ratios). A
/// negative ratio is an oscillation (box `added_mass=1.0` seed 1: M_a
/// alternating between two values, r ≈ -1), which the step then damps
/// towards the cycle's middle. The first step is plain.
/// M_a is projected onto PSD tensors again.
fn accelerate(
    trial: &StateEffects,
    next: &StateEffects,
    step: &Steps,
    previous: Option<&Steps>,
) -> StateEffects {
    let factor = |d: &[f64], p: Option<&Vec<f64>>| {
        let p = match p {
            Some(p) if p.len() == d.len() && !d.is_empty() => p,
            _ => return 1.0,
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let r = dot(d, p) / dot(p, p);
        1.0 / (1.0
            - if r.is_finite() {
                r.clamp(-MAX_RATIO, MAX_RATIO)
            } else {
                0.0
            })
    };
    let mut out = *next;
    if let (Some(a), Some(b)) = (trial.wind, next.wind) {
        out.wind = Some(a + (b - a) * factor(&step.wind, previous.map(|p| &p.wind)));
    }
    if let (Some(a), Some(b)) = (trial.added_mass, next.added_mass) {
        let k = factor(&step.added_mass, previous.map(|p| &p.added_mass));
        let m = a + (b - a) * k;
        out.added_mass = Some(omniad_core::math::nearest_psd(&(0.5 * (m + m.transpose()))));
    }
    out
}

/// One round in the report.
#[derive(Clone, Debug, Serialize)]
pub struct RefitRound {
    /// The process model's wind (world, m/s), if any.
    pub wind: Option<[f64; 3]>,
    /// The process model's added mass (xx, yy, zz, xy, xz, yz; kg), if any.
    pub added_mass: Option<[f64; 6]>,
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
        added_mass: r
            .effects
            .added_mass
            .map(|m| omniad_core::math::six_from_symmetric(&m)),
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
    let first = round(set, cfg, StateEffects::default(), given, progress)?;
    let mut trial = proposal(&first, true);
    let as_array = |w: Option<Vector3<f64>>| w.map(|w| [w.x, w.y, w.z]);
    let mut refit = Refit {
        wind_before_refilter: as_array(trial.wind),
        rounds: vec![summary(&first)],
        ..Refit::default()
    };
    let mut last: Option<(Round, StateEffects)> = None;
    let mut previous: Option<Steps> = None;
    while !trial.is_empty() && refit.refits < MAX_REFITS {
        let r = round(set, cfg, trial, given, progress)?;
        refit.refits += 1;
        refit.rounds.push(summary(&r));
        let next = proposal(&r, false);
        // Added mass the refitted states do not select is not confirmed:
        // the last confirmed round (or the first) stands.
        if trial.added_mass.is_some() && next.added_mass.is_none() {
            refit.converged = false;
            break;
        }
        refit.converged = next.close_to(&trial);
        last = Some((r, next));
        if refit.converged {
            break;
        }
        let step = steps(&trial, &next);
        trial = accelerate(&trial, &next, &step, previous.as_ref());
        previous = Some(step);
    }
    refit.confirmed = last.is_some();
    let (last, wind) = match last {
        Some((r, e)) => (Some(r), e.wind),
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
    let what = match r.rounds.get(1) {
        Some(x) if x.wind.is_some() && x.added_mass.is_some() => "the wind and the added mass",
        Some(x) if x.wind.is_some() => "the wind",
        _ => "the added mass",
    };
    let mut out = vec![format!(
        "Refit around the effect: every take was reconstructed and fitted again with {what} in the process model, {} time(s); {}.",
        r.refits,
        match (r.confirmed, r.converged) {
            (false, _) => "the refitted states did not confirm it, so the first result stands",
            (true, true) => "the selection and the parameters settled",
            (true, false) => "the parameters had not settled at the cap",
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

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear contraction `f(x) = x* + r (x - x*)` (what a round does
    /// to the wind and M_a, measured r ≈ 0.3-0.6), the second step lands on
    /// the fixed point; M_a stays symmetric PSD; a settled round converges.
    #[test]
    fn aitken_step_finds_the_fixed_point_and_keeps_added_mass_psd() {
        let truth_w = Vector3::new(1.0, 0.0, 0.2);
        let truth_m = Matrix3::from_diagonal(&Vector3::new(3e-5, 1e-5, 6.6e-3));
        let r = 0.45;
        let f = |x: &StateEffects| StateEffects {
            wind: x.wind.map(|w| truth_w + (w - truth_w) * r),
            added_mass: x.added_mass.map(|m| truth_m + (m - truth_m) * r),
        };
        let mut x = StateEffects {
            wind: Some(Vector3::new(0.5, 0.01, 0.3)),
            added_mass: Some(Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 2.6e-3))),
        };
        let mut previous = None;
        for _ in 0..2 {
            let next = f(&x);
            assert!(!next.close_to(&x));
            let step = steps(&x, &next);
            x = accelerate(&x, &next, &step, previous.as_ref());
            previous = Some(step);
        }
        let (w, m) = (x.wind.expect("wind"), x.added_mass.expect("M_a"));
        assert!((w - truth_w).norm() < 1e-9, "{w}");
        assert!((m - truth_m).norm() < 1e-9 * truth_m.norm() + 1e-12, "{m}");
        assert!(f(&x).close_to(&x));
        // A step that would leave PSD tensors is projected back.
        let bad = StateEffects {
            wind: None,
            added_mass: Some(Matrix3::from_diagonal(&Vector3::new(-4e-3, 1e-3, 5e-3))),
        };
        let start = StateEffects {
            wind: None,
            added_mass: Some(Matrix3::from_diagonal(&Vector3::new(1e-3, 1e-3, 5e-3))),
        };
        let y = accelerate(&start, &bad, &steps(&start, &bad), None);
        let e = y.added_mass.expect("M_a").symmetric_eigenvalues();
        assert!(e.min() >= -1e-15, "{e}");
    }

    /// Significant-but-implausible added mass is projected; an all-negative
    /// one gives nothing to try.
    #[test]
    fn psd_projection_of_six_parameters() {
        let m = psd(&[-6e-4, -1.1e-3, 2.6e-3, 0.0, 0.0, 0.0]).expect("positive part");
        assert!((m[(2, 2)] - 2.6e-3).abs() < 1e-12 && m[(0, 0)].abs() < 1e-12);
        assert!(psd(&[-1e-3, -1e-3, -1e-3, 0.0, 0.0, 0.0]).is_none());
    }
}
