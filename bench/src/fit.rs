//! `fit_seconds`: what `omniad fit SET -o OUT` (degree 8, 3 iterations,
//! extensions auto) takes on a 13-take synthetic plate set (`omniad synth`
//! defaults: 8 drops, 5 spinning throws, seed 1), generated at bench time
//! into a temporary folder (nothing bundled) and removed afterwards.

use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::pipeline::{self, FitConfig};
use omniad_acquire::reconstruct::run::Silent;
use omniad_acquire::synth::{write::generate, SynthConfig};
use std::time::Instant;

/// Seconds of load + fit (as `omniad fit` reports), or why not measured.
pub fn measure() -> Result<f64, String> {
    let dir = std::env::temp_dir().join(format!("omniad-bench-{}", std::process::id()));
    let result = timed(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn timed(dir: &std::path::Path) -> Result<f64, String> {
    let cfg = SynthConfig {
        seed: 1,
        takes: (8, 5),
        ..SynthConfig::default()
    };
    generate(dir, &cfg).map_err(|e| format!("synth: {e}"))?;
    let start = Instant::now();
    let set = RecordingSet::load(dir).map_err(|e| format!("loading the set: {e}"))?;
    let fit = FitConfig {
        degree: 8,
        iterations: 3,
        ..FitConfig::default()
    };
    pipeline::fit(&set, &fit, &Silent).map_err(|e| format!("fit: {e}"))?;
    Ok(start.elapsed().as_secs_f64())
}
