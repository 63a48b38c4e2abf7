//! On a synthetic set, the generating model itself scored on the frames
//! `after` is scored on: the report's `truth_model`.
//!
//! Why: the acceptance's ratio (held-out force RMS after over before,
//! issue 15) compares two models on reconstructed forces, and those carry
//! the reconstruction's own noise, which no model removes. Where an
//! effect is one C_F can nearly take over (a force linear in V over drops
//! flown near one speed per direction, BENCHMARKS.md stop 17) the base
//! model's residual is mostly that noise. Scoring the exactly right model
//! on the same frames says what ratio it would get there, measured rather
//! than argued. It is not a bound: the states were reconstructed with the
//! fitted model in the filter's process model and lean toward it, so a
//! fitted model can score below the truth (a clean plate's fitted base
//! 0.039 N against the truth's 0.058 N, BENCHMARKS.md stop 31). The truth is `truth/model.omni`, which `omniad synth`
//! writes (the generating coefficients with the object's effects); it is
//! held as it is (`fixed::hold`, nothing fitted, so its "held-out" error is
//! its residual on every take), in the set's true wind
//! (`truth/model.toml`'s `wind`), which may differ from the round's.

use super::wind_search::in_wind;
use super::{problems_on, Round};
use crate::input::recording::RecordingSet;
use crate::residual::fixed;
use crate::residual::select::score;
use crate::residual::HeldOut;
use nalgebra::Vector3;
use omniad_core::{file, Coefficients};
use std::path::Path;

/// The generating model's errors on round `r`'s frames (the takes its
/// selection scored), when `dir` holds `truth/model.omni` of this set's
/// object; `Err` says why a truth file present could not be used.
pub(crate) fn truth_on(
    dir: &Path,
    set: &RecordingSet,
    r: &Round,
) -> Result<Option<HeldOut>, String> {
    let path = dir.join("truth").join("model.omni");
    if !path.exists() {
        return Ok(None);
    }
    let model = read(&path)?;
    fixed::check(&model, set).map_err(|e| format!("{}: {e}", path.display()))?;
    let wind = true_wind(&dir.join("truth").join("model.toml"))?;
    let shift = wind - r.effects.wind.unwrap_or_else(Vector3::zeros);
    let frames = in_wind(&r.selection_samples(), &r.outcome.reconstruction, &shift);
    let p = problems_on(set, &r.outcome, &frames, &model)
        .and_then(|p| fixed::hold(p, &model))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let s =
        score(&p, &[]).ok_or_else(|| format!("{}: its errors are not finite", path.display()))?;
    Ok(Some(HeldOut {
        heldout_force_rms: s.force_rms,
        heldout_torque_rms: s.torque_rms,
    }))
}

fn read(path: &Path) -> Result<Coefficients<f64>, String> {
    let bytes = omniad_io::read_capped(path, file::MAX_FILE_SIZE)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    file::decode::<f64>(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// `wind = [x, y, z]` of `truth/model.toml` (world, m/s); zero when the
/// file or the key is absent (a set without a wind).
fn true_wind(path: &Path) -> Result<Vector3<f64>, String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(Vector3::zeros());
    };
    let value: toml::Value =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let Some(w) = value.get("wind") else {
        return Ok(Vector3::zeros());
    };
    let bad = || {
        format!(
            "{}: `wind` must be three numbers [x, y, z] in m/s",
            path.display()
        )
    };
    let w = w.as_array().ok_or_else(bad)?;
    let c: Vec<f64> = w
        .iter()
        .map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    match c[..] {
        [x, y, z] if c.iter().all(|v| v.is_finite()) => Ok(Vector3::new(x, y, z)),
        _ => Err(bad()),
    }
}
