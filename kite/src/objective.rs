//! What `kite optimise` climbs ([`crate::optimise`]): one trial design
//! checked and scored (the verdict's rank plus a shaped margin), and the
//! searches' shared record of what they checked (the flight check's
//! candidates, each search's best).

use crate::assemble::Design;
use crate::check::{check, Verdict};
use crate::connect::pieces;
use crate::design_params::apply;
use crate::flight::FlightOptions;
use crate::modes::ModesReport;
use crate::spec::KiteSpec;
use anyhow::Result;
use serde::Serialize;

/// How good one trial is.
#[derive(Clone, Debug, Serialize)]
pub struct Score {
    /// The verdict.
    pub verdict: Verdict,
    /// `-σ_max`, 1/s (positive: every mode decays); NaN without an
    /// equilibrium.
    pub margin: f64,
    /// The gust margin of [`crate::gusts::GustReport::margin`] (1: the
    /// gusts do not move the kite, 0: predicted to reach a flight limit);
    /// NaN when a mode grows.
    pub gust_margin: f64,
    /// The least damping ratio `ζ` of the oscillatory modes (NaN without
    /// an equilibrium, 1 when no mode oscillates).
    pub damping_ratio: f64,
    /// Line elevation at the equilibrium, degrees (NaN without one).
    pub elevation_deg: f64,
    /// What the search maximises (feasible designs score above every
    /// infeasible one).
    pub objective: f64,
}

/// Scores `spec` (assembled by `assemble`); `None` when it does not
/// assemble or its frame is in more than `pieces_allowed` pieces.
fn score(
    spec: &KiteSpec,
    assemble: &dyn Fn(KiteSpec) -> Result<Design>,
    pieces_allowed: usize,
) -> Option<Score> {
    if pieces(spec) > pieces_allowed {
        return None;
    }
    let design = assemble(spec.clone()).ok()?;
    let c = check(&design, None).ok()?;
    let elevation = c
        .modes
        .equilibrium
        .as_ref()
        .map_or(f64::NAN, |e| e.elevation_deg);
    let margin = -c.modes.max_growth_rate;
    let gust_margin = c.modes.gusts.as_ref().map_or(f64::NAN, |g| g.margin);
    let damping_ratio = least_damping(&c.modes);
    let rank = match c.verdict {
        Verdict::Stable => 0.0,
        Verdict::GustSensitive => -50.0,
        Verdict::DynamicallyUnstable | Verdict::StaticallyUnstable => -100.0,
        Verdict::NoEquilibrium => -1e4,
        Verdict::StringPushes | Verdict::Unflyable | Verdict::Disconnected => -1e5,
    };
    let shaped = if gust_margin.is_finite() {
        gust_margin
            .clamp(-5.0, 1.0)
            .min(settling(margin))
            .min(damping_ratio / ZETA_REF)
    } else if margin.is_finite() {
        margin.clamp(-50.0, 50.0)
    } else {
        -(c.overlaps.len() as f64)
    };
    Some(Score {
        verdict: c.verdict,
        margin,
        gust_margin,
        damping_ratio,
        elevation_deg: elevation,
        objective: rank + shaped,
    })
}

/// The damping ratio a design's least damped oscillatory mode needs to
/// count as well damped: MIL-F-8785C's Level 1 minimum for the Dutch roll
/// (flight phase categories B and C, `ζ_d >= 0.08`; Level 2 is 0.02), the
/// aircraft mode closest to a kite's roll-yaw oscillation. The objective
/// takes `min(ζ/ζ_ref, 1)` beside the gust margin. Why: the linear gust
/// response of a lightly damped mode underestimates the flight's: the
/// search's `stable` result on box-classic (gust margin +0.59) has a
/// 1.37 Hz pitch + roll-yaw flutter at ζ = 0.02 that the gusts drive to
/// three times its predicted |Ω| (BENCHMARKS, issue 17).
const ZETA_REF: f64 = 0.08;

/// The least damping ratio `ζ = -σ/|λ|` of the modes that oscillate
/// (`ω > 0`), 1 when none does, NaN without an equilibrium.
fn least_damping(m: &ModesReport) -> f64 {
    if m.equilibrium.is_none() {
        return f64::NAN;
    }
    m.modes
        .iter()
        .filter(|x| x.imag > 0.0)
        .map(|x| x.damping_ratio)
        .fold(1.0, f64::min)
}

/// The fraction of a disturbance the slowest mode removes over the span
/// the flight judges (`1 - e^{-σ T}`, `σ` the decay rate, 1/s; `T` the
/// second half of `kite fly`'s default run): 1 for a kite that settles
/// well within it, near 0 for one whose slowest mode barely decays (the
/// search used to trade the decay rate down to 0.001/s for a larger gust
/// margin, and such kites crash on some seeds: BENCHMARKS, issue 17).
fn settling(decay_rate: f64) -> f64 {
    let span = FlightOptions::default().seconds / 2.0;
    1.0 - (-decay_rate * span).exp()
}

/// The index [`Search::evaluate`] files the evaluations made before the
/// searches under (the file, its quarter turns, the pair scan).
pub(crate) const STARTS: usize = usize::MAX;

/// One design the verdict called stable or gust-sensitive (a flight
/// check candidate), and the search that found it.
#[derive(Clone, Debug)]
pub(crate) struct Found {
    pub(crate) plan: usize,
    pub(crate) x: Vec<f64>,
    pub(crate) score: Score,
}

/// The searches' shared state: what they search from, what they have
/// spent, the flight check's candidates and each search's best score.
pub(crate) struct Search<'a> {
    pub(crate) base: &'a KiteSpec,
    pub(crate) assemble: &'a dyn Fn(KiteSpec) -> Result<Design>,
    pub(crate) allowed: usize,
    pub(crate) evaluations: usize,
    pub(crate) found: Vec<Found>,
    pub(crate) best: Vec<Option<Score>>,
}

impl Search<'_> {
    /// Scores parameters `x` for search `plan` (one evaluation), keeping it
    /// when stable or gust-sensitive and the search's best.
    pub(crate) fn evaluate(&mut self, plan: usize, x: &[f64]) -> Option<Score> {
        self.evaluations += 1;
        let s = score(&apply(self.base, x), self.assemble, self.allowed)?;
        if matches!(s.verdict, Verdict::Stable | Verdict::GustSensitive) {
            let (x, score) = (x.to_vec(), s.clone());
            self.found.push(Found { plan, x, score });
        }
        if plan != STARTS {
            if self.best.len() <= plan {
                self.best.resize(plan + 1, None);
            }
            if let Some(b) = self.best.get_mut(plan) {
                if b.as_ref().is_none_or(|b| s.objective > b.objective) {
                    *b = Some(s.clone());
                }
            }
        }
        Some(s)
    }
}
