//! `omniad reconstruct`: the smoothed rigid-body states of every take
//! (§5), after the refinement iterations of §6, as `truth/`-layout CSV.

use anyhow::{Context, Result};
use clap::Args;
use omniad_acquire::input::state_csv::{self, TimeFormat};
use omniad_acquire::pipeline::{self, FitConfig};
use omniad_acquire::reconstruct::run::Progress as _;
use std::path::PathBuf;

/// Arguments of `omniad reconstruct`.
#[derive(Args, Debug)]
pub struct ReconstructArgs {
    /// Recording set folder (holding recording.toml).
    pub set: PathBuf,
    /// Output folder: one `<take>.csv` per take.
    #[arg(short, long)]
    pub output: PathBuf,
    /// SH degree N of the process model.
    #[arg(long, default_value_t = 8)]
    pub degree: u8,
    /// Refinement iterations before the final reconstruction.
    #[arg(long, default_value_t = omniad_acquire::pipeline::DEFAULT_ITERATIONS)]
    pub iterations: usize,
}

/// Runs `omniad reconstruct`.
pub fn run(a: &ReconstructArgs) -> Result<()> {
    let set = super::fit::load(&a.set)?;
    let paths: Vec<PathBuf> = set
        .takes
        .iter()
        .map(|take| a.output.join(format!("{}.csv", take.name)))
        .collect();
    for path in &paths {
        super::common::refuse_input(path, &set.files)?;
    }
    let cfg = FitConfig {
        degree: a.degree,
        iterations: a.iterations,
        ..FitConfig::default()
    };
    let bars = super::fit::Bars::default();
    let outcome = pipeline::fit(&set, &cfg, &bars).map_err(|e| anyhow::anyhow!("{e}"))?;
    bars.stage("final reconstruction: process noise by likelihood", 1);
    let noise = pipeline::final_noise(&set, &outcome, &cfg).map_err(|e| anyhow::anyhow!("{e}"))?;
    bars.tick();
    bars.stage_final(set.takes.len());
    let smoothed = omniad_acquire::reconstruct::run::refine(
        &set,
        &outcome.model,
        noise,
        &cfg.filter,
        &outcome.reconstruction,
        &bars,
    )
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    drop(bars);
    std::fs::create_dir_all(&a.output)
        .with_context(|| format!("cannot create {}", a.output.display()))?;
    for (path, s) in paths.iter().zip(&smoothed) {
        let rows = s.times.iter().copied().zip(&s.states);
        state_csv::write_states(path, rows, TimeFormat::Micros)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    println!("wrote {} takes to {}", smoothed.len(), a.output.display());
    Ok(())
}
