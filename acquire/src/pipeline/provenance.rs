//! The fitted model's provenance: method, frames, per-iteration
//! residuals and direction coverage.

use crate::error::{Error, Result};
use crate::fit::coverage;
use crate::input::recording::RecordingSet;
use crate::pipeline::{FitConfig, IterationReport, Method};
use crate::reconstruct::filter::{FilterStats, Smoothed};
use crate::reconstruct::forces::Sample;
use omniad_core::Coefficients;

pub(super) fn total_stats(smoothed: &[Smoothed]) -> FilterStats {
    smoothed
        .iter()
        .fold(FilterStats::default(), |a, s| FilterStats {
            used: a.used + s.stats.used,
            gated: a.gated + s.stats.gated,
            empty_frames: a.empty_frames + s.stats.empty_frames,
            unprojectable: a.unprojectable + s.stats.unprojectable,
            restarts: a.restarts + s.stats.restarts,
            mirror_switches: a.mirror_switches + s.stats.mirror_switches,
            lost: a.lost + s.stats.lost,
        })
}

fn truncated<const N: usize>(s: &str) -> heapless::String<N> {
    let mut out = heapless::String::new();
    for c in s.chars() {
        if out.push(c).is_err() {
            break;
        }
    }
    out
}

pub(super) fn fill_provenance(
    model: &mut Coefficients<f64>,
    set: &RecordingSet,
    cfg: &FitConfig,
    its: &[IterationReport],
    samples: &[Sample],
) -> Result<()> {
    let p = &mut model.provenance;
    p.method = truncated(match cfg.method {
        Method::Lsq => "fit-lsq",
        Method::Paper => "fit-paper",
    });
    p.source = truncated(&set.root.display().to_string());
    let used = samples.iter().filter(|s| s.use_force).count();
    p.frames_used = u32::try_from(used).unwrap_or(u32::MAX);
    p.frames_dropped = u32::try_from(samples.len() - used).unwrap_or(u32::MAX);
    for r in its
        .iter()
        .rev()
        .take(omniad_core::coefficients::MAX_ITERATIONS)
        .rev()
    {
        let _ = p.force_residuals.push(r.residual.0);
        let _ = p.torque_residuals.push(r.residual.1);
    }
    let dirs = samples
        .iter()
        .filter(|s| s.use_force && s.velocity.norm() > 0.0)
        .map(|s| s.velocity.normalize());
    for c in coverage::histogram(&set.object.pole, dirs) {
        p.coverage
            .push(c)
            .map_err(|_| Error::Data("coverage grid size".into()))?;
    }
    Ok(())
}
