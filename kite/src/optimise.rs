//! `kite optimise`: searches the kite's free trim parameters — pitch, the
//! string offset along the eq. (16) line (equivalently γ), and each
//! primitive's yaw about its own centre — for the largest stability
//! margin, keeping the geometry buildable.
//!
//! Margin: `-σ_max` (1/s), minus the largest real part among the modes of
//! the linearised kite on its line ([`crate::modes`]): how fast the
//! slowest motion decays. A design counts only when the verdict is
//! `stable` (no overlap along the wind, the string pulls down, an
//! equilibrium, no static divergence, every mode decays); below that, the
//! search climbs the same quantity (a less fast growth is closer to
//! flyable) after the constraints, so an unflyable start is walked to a
//! flyable design when one lies within reach. A small term for the
//! equilibrium's line elevation (0.003/s per degree) prefers, among
//! equally damped trims, the one hanging higher on its line, where gusts
//! have further to bring it down.
//!
//! Constraints: no overlap along the wind and the string pulls down
//! (the verdict's first two tests), and the frame stays connected: extra
//! `[[rod]]`s whose ends sit on a primitive's frame turn with it
//! ([`crate::connect`]), and a trial whose frame falls apart is refused.
//!
//! Search: compass (pattern) search from the file's values, steps 4° of
//! pitch, 3 cm of offset, 10° of yaw, halved when no neighbour improves,
//! to a budget of evaluations (each one `kite check`).

use crate::assemble::Design;
use crate::check::{check, Verdict};
use crate::connect::{pieces, turn_primitive};
use crate::spec::{KiteSpec, StringSpec};
use anyhow::Result;
use serde::Serialize;

/// How far each kind of parameter may move from the file's value:
/// pitch 20°, offset 0.3 m (about a kite's size: further and the bridle
/// would leave the kite), yaw 45°.
const REACH: [f64; 3] = [20.0, 0.3, 45.0];

/// Search settings.
#[derive(Clone, Copy, Debug)]
pub struct OptimiseOptions {
    /// Largest number of designs checked.
    pub max_evaluations: usize,
}

impl Default for OptimiseOptions {
    fn default() -> Self {
        Self {
            max_evaluations: 200,
        }
    }
}

/// How good one trial is.
#[derive(Clone, Debug, Serialize)]
pub struct Score {
    /// The verdict.
    pub verdict: Verdict,
    /// `-σ_max`, 1/s (positive: every mode decays); NaN without an
    /// equilibrium.
    pub margin: f64,
    /// Line elevation at the equilibrium, degrees (NaN without one).
    pub elevation_deg: f64,
    /// What the search maximises (feasible designs score above every
    /// infeasible one).
    pub objective: f64,
}

/// One parameter's change.
#[derive(Clone, Debug, Serialize)]
pub struct Change {
    /// `orientation.pitch`, `string.offset`, `primitive[i].rotation.z`.
    pub parameter: String,
    /// Value in the file (degrees or metres).
    pub before: f64,
    /// Value found.
    pub after: f64,
}

/// What `kite optimise` found.
#[derive(Clone, Debug, Serialize)]
pub struct OptimiseReport {
    /// Kite name.
    pub name: String,
    /// The file as given.
    pub before: Score,
    /// The best design found.
    pub after: Score,
    /// Parameters that changed.
    pub changes: Vec<Change>,
    /// Designs checked.
    pub evaluations: usize,
    /// The best design's kite file.
    #[serde(skip)]
    pub spec: KiteSpec,
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
    let rank = match c.verdict {
        Verdict::Stable => 0.0,
        Verdict::DynamicallyUnstable | Verdict::StaticallyUnstable => -100.0,
        Verdict::NoEquilibrium => -1e4,
        Verdict::StringPushes | Verdict::Unflyable => -1e5,
    };
    let shaped = if margin.is_finite() {
        margin.clamp(-50.0, 50.0) + 0.003 * elevation
    } else {
        -(c.overlaps.len() as f64)
    };
    Some(Score {
        verdict: c.verdict,
        margin,
        elevation_deg: elevation,
        objective: rank + shaped,
    })
}

/// The parameters: pitch (deg), offset (m), each primitive's yaw change
/// (deg), applied to the file's spec.
fn apply(base: &KiteSpec, x: &[f64]) -> KiteSpec {
    let mut s = base.clone();
    s.orientation[1] = x[0];
    s.string = StringSpec {
        gamma: None,
        offset: Some(x[1]),
        length: base.string.length,
    };
    for (i, dz) in x.iter().skip(2).enumerate() {
        if *dz != 0.0 {
            turn_primitive(&mut s, i, *dz);
        }
    }
    s
}

/// Searches from `design` (its file spec, assembled again by `assemble`
/// for each trial: object files stay relative to the original file).
pub fn optimise(
    design: &Design,
    assemble: &dyn Fn(KiteSpec) -> Result<Design>,
    opts: &OptimiseOptions,
) -> Result<OptimiseReport> {
    let base = design.spec.clone();
    let offset = check(design, None)?.attachment_offset;
    let n = base.primitives.len();
    let mut x: Vec<f64> = [base.orientation[1], offset]
        .into_iter()
        .chain(std::iter::repeat_n(0.0, n))
        .collect();
    let x0 = x.clone();
    let mut step: Vec<f64> = [4.0, 0.03]
        .into_iter()
        .chain(std::iter::repeat_n(10.0, n))
        .collect();
    // A frame in one piece stays in one piece (a file already in several
    // pieces may not come further apart).
    let allowed = pieces(&base).max(1);
    let before = score(&apply(&base, &x), assemble, allowed).ok_or_else(|| {
        anyhow::anyhow!("the kite as given does not assemble or is not connected")
    })?;
    let mut best = before.clone();
    let mut evaluations = 1;
    while evaluations < opts.max_evaluations && step[1] > 0.002 {
        let mut improved = false;
        'coords: for k in 0..x.len() {
            for sign in [1.0, -1.0] {
                if evaluations >= opts.max_evaluations {
                    break 'coords;
                }
                let mut trial = x.clone();
                trial[k] += sign * step[k];
                if (trial[k] - x0[k]).abs() > REACH[k.min(2)] {
                    continue;
                }
                evaluations += 1;
                if let Some(s) = score(&apply(&base, &trial), assemble, allowed) {
                    if s.objective > best.objective + 1e-6 {
                        (x, best, improved) = (trial, s, true);
                        break;
                    }
                }
            }
        }
        if !improved {
            step.iter_mut().for_each(|s| *s /= 2.0);
        }
    }
    let spec = apply(&base, &x);
    Ok(OptimiseReport {
        name: base.name.clone(),
        changes: changes(&base, offset, &x),
        before,
        after: best,
        evaluations,
        spec,
    })
}

fn changes(base: &KiteSpec, offset: f64, x: &[f64]) -> Vec<Change> {
    let mut out = Vec::new();
    let mut push = |parameter: String, before: f64, after: f64| {
        if (after - before).abs() > 1e-9 {
            out.push(Change {
                parameter,
                before,
                after,
            });
        }
    };
    push("orientation.pitch".into(), base.orientation[1], x[0]);
    push("string.offset".into(), offset, x[1]);
    for (i, p) in base.primitives.iter().enumerate() {
        let z = p.rotation[2];
        push(format!("primitive[{i}].rotation.z"), z, z + x[2 + i]);
    }
    out
}

/// Human-readable summary.
pub fn render(r: &OptimiseReport) -> String {
    let s = |x: &Score| {
        format!(
            "{} (margin {:+.3}/s, line elevation {:.0}°)",
            x.verdict.name(),
            x.margin,
            x.elevation_deg
        )
    };
    let mut out = format!(
        "kite {:?}: {} designs checked\n  before: {}\n  after:  {}\n",
        r.name,
        r.evaluations,
        s(&r.before),
        s(&r.after)
    );
    if r.changes.is_empty() {
        out += "  no change improves the margin\n";
    }
    for c in &r.changes {
        out += &format!(
            "  {:<26} {:+.3} -> {:+.3}\n",
            c.parameter, c.before, c.after
        );
    }
    out
}
