//! The model-free first reconstruction (§6, A_0 = 0) with a safety net for
//! air that carries a strong effect nobody declared.
//!
//! Why it can fail: with no model the filter explains the air's wrench by
//! its random-walk unexplained wrench, whose prior and walk are sized to
//! the object's weight (`noise::initial_noise`). A wrench many times the
//! weight (a Magnus force of 15 weights on a spinning 48 g plate) moves the
//! object centimetres per frame away from the prediction; the predicted
//! marker covariance stays small, the chi-square gate rejects every marker,
//! the filter is lost (`FilterStats::lost`) and the ungated updates that
//! follow make jumps whose angular velocities the RK4 step of Euler's
//! equations cannot integrate (non-finite predictions, restarts, torques of
//! 1e48 N m). The cause is the noise's size, so the cure is a take whose
//! first reconstruction lost track is filtered again with its air's wrench
//! assumed [`WRENCH_SCALES`] times larger (every sigma of the process noise
//! and of the unexplained wrench's prior), and keeps that scale through the
//! refinement. A take that no scale makes plausible is named and left out.

use crate::error::Result;
use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::{FilterConfig, Smoothed};
use crate::reconstruct::forces::{self, ForceStats};
use crate::reconstruct::noise::{scales, ProcessNoise};
use crate::reconstruct::run::{refine_takes, Progress, Silent, TakeModels};
use omniad_core::Coefficients;
use serde::Serialize;

/// Factors on a take's air-wrench scale tried in turn while its first
/// reconstruction has lost track (restarts, lost runs, implausible forces):
/// 16 covers forces of tens of weights (the strongest synthetic Magnus sets).
pub const WRENCH_SCALES: [f64; 3] = [1.0, 4.0, 16.0];

/// Largest reconstructed force (in object weights `M|g|`) and torque (in
/// `M|g| L/2`) of a plausible take: beyond, the reconstruction is no
/// measurement (a well-tracked 15-weight Magnus set stays below 40).
pub const MAX_WRENCH_SCALES: f64 = 200.0;

/// A take left out of a fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LeftOut {
    /// The take's name.
    pub take: String,
    /// Why, in words.
    pub why: String,
}

/// The first reconstruction of a set.
pub struct First {
    /// One per take (empty for a take left out).
    pub smoothed: Vec<Smoothed>,
    /// Per take: the air-wrench scale used, `None` when left out.
    pub scales: Vec<Option<f64>>,
    /// The takes left out.
    pub left_out: Vec<LeftOut>,
}

/// Fraction of a take's marker rows gated beyond which its first
/// reconstruction counts as having lost track (outliers of a tracker are a
/// few per cent; a filter that cannot follow the object gates tens; 5 % was seen to fire on a clean box take, seed 1, whose reconstruction the larger noise made worse).
pub const GATED_FRACTION: f64 = 0.1;

/// How far a take's reconstruction is from tracked: implausible (a reason),
/// restarts, lost runs, gated rows beyond [`GATED_FRACTION`]; all
/// zero/`None` is tracked. Lexicographic order.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Trouble {
    implausible: Option<String>,
    restarts: usize,
    lost: usize,
    excess_gated: usize,
}

impl Trouble {
    fn none(&self) -> bool {
        self.implausible.is_none() && self.restarts == 0 && self.lost == 0 && self.excess_gated == 0
    }
}

fn trouble(set: &RecordingSet, take: usize, s: &Smoothed) -> Trouble {
    let (force, torque, _) = scales(set);
    let Some(kind) = set.takes.get(take).map(|t| t.kind) else {
        return Trouble {
            implausible: None,
            restarts: 0,
            lost: 0,
            excess_gated: 0,
        };
    };
    let mut stats = ForceStats::default();
    let frames = forces::reconstruct(
        take,
        kind,
        s,
        &set.object,
        (&set.world.gravity, &nalgebra::Vector3::zeros()),
        &mut stats,
    );
    let f = frames.iter().map(|x| x.force.norm()).fold(0.0, f64::max) / force;
    let t = frames.iter().map(|x| x.torque.norm()).fold(0.0, f64::max) / torque;
    let finite = s.states.iter().all(|x| x.is_finite());
    let implausible = if !finite || stats.non_finite > 0 {
        Some(format!(
            "non-finite reconstruction ({} frames)",
            stats.non_finite
        ))
    } else if f.max(t) > MAX_WRENCH_SCALES {
        Some(format!(
            "implausible wrench: force up to {f:.3e} weights, torque up to {t:.3e} weight \
             half-lengths (limit {MAX_WRENCH_SCALES})"
        ))
    } else {
        None
    };
    Trouble {
        implausible,
        restarts: s.stats.restarts,
        lost: s.stats.lost,
        excess_gated: excess_gated(s),
    }
}

/// Gated rows beyond [`GATED_FRACTION`] of all rows.
fn excess_gated(s: &Smoothed) -> usize {
    let rows = (s.stats.used + s.stats.gated) as f64;
    let allowed = (GATED_FRACTION * rows).floor() as usize;
    s.stats.gated.saturating_sub(allowed)
}

/// The first reconstruction of every take with `model` (the zero model)
/// and `noise` (`initial_noise`), each take that lost track filtered again
/// at the next of [`WRENCH_SCALES`] while that helps; takes still
/// implausible are left out (see the module doc).
pub fn first(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    progress: &dyn Progress,
) -> Result<First> {
    let start = vec![Some(1.0); set.takes.len()];
    let models = TakeModels::shared(model);
    let (mut smoothed, mut scales, troubles) = track(set, &models, noise, cfg, &start, progress)?;
    let mut left_out = Vec::new();
    for (i, t) in troubles.into_iter().enumerate() {
        if let (Some(why), Some(take)) = (t.implausible, set.takes.get(i)) {
            left_out.push(LeftOut {
                take: take.name.clone(),
                why: format!(
                    "{why}, even with the air's wrench assumed {}x larger",
                    WRENCH_SCALES.last().copied().unwrap_or(1.0)
                ),
            });
            scales[i] = None;
            smoothed[i] = Smoothed::default();
        }
    }
    Ok(First {
        smoothed,
        scales,
        left_out,
    })
}

/// A later iteration's reconstruction of the takes in `scales` (`None`:
/// left out, its reconstruction empty) with the same safety net as
/// [`first`]: a take that lost track is filtered again with its scale
/// times [`WRENCH_SCALES`] (the fitted model may still lack a strong
/// effect, and the refined noise is smaller than the first's); nothing is
/// left out (the refinement rejects an iteration that went astray).
/// `scales` is updated.
pub fn again(
    set: &RecordingSet,
    models: &TakeModels<'_>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    scales: &mut Vec<Option<f64>>,
    progress: &dyn Progress,
) -> Result<Vec<Smoothed>> {
    let (smoothed, new, _) = track(set, models, noise, cfg, scales, progress)?;
    *scales = new;
    Ok(smoothed)
}

type Tracked = (Vec<Smoothed>, Vec<Option<f64>>, Vec<Trouble>);

/// Every take in `start` reconstructed at its scale, each that lost track
/// again at its scale times the next of [`WRENCH_SCALES`] while that
/// lowers its [`Trouble`].
fn track(
    set: &RecordingSet,
    models: &TakeModels<'_>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    start: &[Option<f64>],
    progress: &dyn Progress,
) -> Result<Tracked> {
    let mut scales = start.to_vec();
    let mut smoothed = refine_takes(set, models, noise, cfg, &[], &scales, progress)?;
    let empty = Smoothed::default();
    let mut troubles: Vec<Trouble> = (0..set.takes.len())
        .map(|i| match scales.get(i) {
            Some(Some(_)) => trouble(set, i, smoothed.get(i).unwrap_or(&empty)),
            _ => trouble(set, usize::MAX, &empty),
        })
        .collect();
    for &k in WRENCH_SCALES.get(1..).unwrap_or(&[]) {
        let retry: Vec<Option<f64>> = troubles
            .iter()
            .zip(start)
            .map(|(t, s)| s.filter(|_| !t.none()).map(|s| s * k))
            .collect();
        if retry.iter().all(Option::is_none) {
            break;
        }
        let again = refine_takes(set, models, noise, cfg, &[], &retry, &Silent)?;
        for (i, s) in again.into_iter().enumerate() {
            let Some(k) = retry.get(i).copied().flatten() else {
                continue;
            };
            let t = trouble(set, i, &s);
            if troubles.get(i).is_some_and(|old| t < *old) {
                smoothed[i] = s;
                scales[i] = Some(k);
                troubles[i] = t;
            }
        }
    }
    Ok((smoothed, scales, troubles))
}
