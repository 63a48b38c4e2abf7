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
//! 0.039 N against the truth's 0.058 N, BENCHMARKS.md stop 31).
//!
//! The truth is `truth/model.omni`, which `omniad synth` writes (the
//! generating coefficients with the object's effects); it is held as it
//! is (`fixed::hold`, nothing fitted, so its "held-out" error is its
//! residual on every take), in the set's true wind (`truth/model.toml`'s
//! `wind`), which may differ from the round's.

use super::base_states::scored_on;
use super::Round;
use crate::input::recording::RecordingSet;
use crate::omni_file;
use crate::residual::fixed;
use crate::residual::HeldOut;
use nalgebra::Vector3;
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
    let model = omni_file::read(&path).map_err(|e| e.to_string())?;
    let named = |e: String| format!("{}: {e}", path.display());
    fixed::check(&model, set).map_err(named)?;
    let wind = true_wind(&dir.join("truth").join("model.toml"))?;
    let shift = wind - r.effects.wind.unwrap_or_else(Vector3::zeros);
    let (_, s) = scored_on(set, r, &shift, &model, true).map_err(named)?;
    Ok(Some(HeldOut {
        heldout_force_rms: s.force_rms,
        heldout_torque_rms: s.torque_rms,
    }))
}

/// `wind = [x, y, z]` of `truth/model.toml` (world, m/s); zero when the
/// file or the key is absent (a set without a wind). A file present but
/// unreadable is an error, not a still air.
fn true_wind(path: &Path) -> Result<Vector3<f64>, String> {
    if !path.exists() {
        return Ok(Vector3::zeros());
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
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
