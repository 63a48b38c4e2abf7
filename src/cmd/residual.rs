//! `omniad residual`: the base model's held-out residual, the effect it
//! points to, the model with it, errors before and after
//! (`omniad_acquire::residual`).

use crate::cmd::fit::{load, Bars};
use anyhow::Result;
use clap::Args;
use omniad_acquire::pipeline::FitConfig;
use omniad_acquire::residual::{analyse, Report};
use std::path::PathBuf;

/// Arguments of `omniad residual`.
#[derive(Args, Debug)]
pub struct ResidualArgs {
    /// Recording set folder (with recording.toml).
    pub set: PathBuf,
    /// Write the extended model (base coefficients refitted with the
    /// selected named effects stored) here.
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Write SVG figures of the residual into this folder (created).
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// SH degree of the fit.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u8).range(1..=8))]
    pub degree: u8,
}

/// Runs `omniad residual`.
pub fn run(a: &ResidualArgs) -> Result<()> {
    let set = load(&a.set)?;
    let cfg = FitConfig {
        degree: a.degree,
        ..FitConfig::default()
    };
    let analysis = {
        let bars = Bars::default();
        analyse(&a.set, &set, &cfg, &bars).map_err(|e| anyhow::anyhow!("{e}"))?
    };
    if let Some(out) = &a.output {
        super::common::write_coefficients(out, &analysis.extended)?;
    }
    if let Some(dir) = &a.plots {
        let figures = omniad_acquire::residual::plots::figures(&analysis.report);
        omniad_io::write_files_atomic(dir, figures)
            .map_err(|e| anyhow::anyhow!("cannot write the plots: {e}"))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&analysis.report)?);
    } else {
        print_text(&analysis.report);
    }
    Ok(())
}

fn print_text(r: &Report) {
    for l in &r.left_out_takes {
        println!("take {} left out: {}", l.take, l.why);
    }
    println!("candidates (held out, leave one take out):");
    for c in &r.candidates {
        println!(
            "  step {} {:18} force {:.4} N  torque {:.5} N m  gain {:+6.1} %  better on {}/{}  {}",
            c.step + 1,
            c.effect,
            c.heldout_force_rms,
            c.heldout_torque_rms,
            c.gain * 100.0,
            c.takes_better,
            c.takes,
            c.rejected.as_deref().unwrap_or("eligible")
        );
    }
    println!(
        "selected: {}",
        if r.selected.is_empty() {
            "nothing".to_owned()
        } else {
            r.selected.join(", ")
        }
    );
    if let Some(s) = r.resimulation {
        println!(
            "re-simulation, first 0.5 s of each take: {:.4} m base, {:.4} m extended",
            s.base_m, s.extended_m
        );
    }
    if let Some(t) = r.cf_error_vs_truth {
        println!(
            "C_F error vs truth: {:.2} % before, {:.2} % after ({} directions)",
            t.before * 100.0,
            t.after * 100.0,
            t.directions
        );
    }
    for w in &r.words {
        println!("{w}");
    }
}
