//! The coefficient accuracy of a synthetic set's fit against its
//! generating model (`truth/coefficients.csv`): relative L2 errors of
//! C_F and C_T over the truth grid directions with >= 20 fitted frames
//! within 15° (the metric of `omniad lab accept` and BENCHMARKS.md).

use anyhow::{anyhow, Result};
use omniad_acquire::pipeline::FitOutcome;
use omniad_acquire::synth::truth::{
    coefficient_error, fitted_directions, force_error, read_coefficients, torque_directions,
    Coefficient,
};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// Frames within [`ANGLE_DEG`] a grid direction needs to be scored.
pub const MIN_FRAMES: usize = 20;
/// The coverage cone's half angle, degrees.
pub const ANGLE_DEG: f64 = 15.0;

/// Appends the accuracy section to `md` and returns its JSON, or `None`
/// when the set has no `truth/coefficients.csv` (a real recording).
pub fn against_truth(set_dir: &Path, fit: &FitOutcome, md: &mut String) -> Result<Option<Value>> {
    let path = set_dir.join("truth").join("coefficients.csv");
    if !path.is_file() {
        return Ok(None);
    }
    let truth = read_coefficients(&path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let angle = ANGLE_DEG.to_radians();
    let (cf, nf) = force_error(
        &fit.model,
        &truth,
        &fitted_directions(&fit.samples),
        MIN_FRAMES,
        angle,
    );
    let (ct, nt) = coefficient_error(
        &fit.model,
        &truth,
        &torque_directions(&fit.samples, fit.torque_frames),
        MIN_FRAMES,
        angle,
        Coefficient::Torque,
    );
    let _ = write!(
        md,
        "\n## Coefficient accuracy against the generating model\n\nRelative L2 error over the truth grid directions with >= {MIN_FRAMES} fitted frames within {ANGLE_DEG}° (`omniad lab accept`'s metric; C_T counts the torque fit's frames).\n\n| coefficient | error | directions |\n|---|---|---|\n| C_F | {} | {nf} |\n| C_T | {} | {nt} |\n",
        percent(cf),
        percent(ct)
    );
    Ok(Some(json!({
        "cf_rel_l2": cf, "cf_directions": nf, "ct_rel_l2": ct, "ct_directions": nt,
    })))
}

/// `x` as a percentage, or "n/a" when no direction was covered (NaN).
fn percent(x: f64) -> String {
    if x.is_finite() {
        format!("{:.2} %", 100.0 * x)
    } else {
        "n/a".into()
    }
}
