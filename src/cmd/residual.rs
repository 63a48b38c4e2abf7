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
    /// Write SVG figures of the residual into this folder (created), and
    /// the per-frame held-out force residuals they are drawn from,
    /// `residual-frames.csv` (body frame; the base and the extended model).
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// SH degree of the fit (default 8; with --coeffs, the file's).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=8))]
    pub degree: Option<u8>,
    /// Use this coefficient file (.omni) as the base model instead of
    /// fitting one. It must be of the set's object (same pole and
    /// reference length). Nothing of it is fitted, so its error is its
    /// residual on every take; candidates are fitted on top of it
    /// (leave one take out) and their parameters are increments.
    #[arg(long, value_name = "FILE")]
    pub coeffs: Option<PathBuf>,
}

/// Runs `omniad residual`.
pub fn run(a: &ResidualArgs) -> Result<()> {
    let set = load(&a.set)?;
    if let Some(out) = &a.output {
        // The set's files, the given base model and the truth it reads.
        let mut inputs = set.files.clone();
        inputs.extend(a.coeffs.iter().cloned());
        inputs.push(a.set.join("truth").join("model.omni"));
        super::common::refuse_input(out, &inputs)?;
    }
    let given = match a.coeffs.as_deref() {
        Some(path) => Some(given_model(path, &a.set, &set, a.degree)?),
        None => None,
    };
    let mut cfg = FitConfig {
        degree: given.as_ref().map_or(a.degree.unwrap_or(8), |g| g.degree()),
        ..FitConfig::default()
    };
    // A given model's refits are at its degrees, the torque's own too.
    cfg.lsq.torque_degree = given.as_ref().map(|g| usize::from(g.torque_degree()));
    let analysis = {
        let bars = Bars::default();
        analyse(&a.set, &set, &cfg, given.as_ref(), &bars).map_err(|e| anyhow::anyhow!("{e}"))?
    };
    if let Some(out) = &a.output {
        super::common::write_coefficients(out, &analysis.extended)?;
    }
    if let Some(dir) = &a.plots {
        let mut files = omniad_acquire::residual::plots::figures(&analysis.report);
        let takes: Vec<String> = set.takes.iter().map(|t| t.name.clone()).collect();
        files.push((
            "residual-frames.csv".into(),
            omniad_acquire::residual::frames::csv(&analysis.frames, &takes),
        ));
        omniad_io::write_files_atomic(dir, files)
            .map_err(|e| anyhow::anyhow!("cannot write the plots: {e}"))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&analysis.report)?);
    } else {
        print_text(&analysis.report);
    }
    Ok(())
}

/// Reads `--coeffs FILE` and checks it can be the base model of the set
/// (`residual::fixed::check`); a `--degree` other than the file's is an
/// error too. Every error names the file.
fn given_model(
    path: &std::path::Path,
    dir: &std::path::Path,
    set: &omniad_acquire::input::recording::RecordingSet,
    degree: Option<u8>,
) -> Result<omniad_core::Coefficients<f64>> {
    let m = super::common::read_coefficients(path)?;
    let why = match degree.filter(|d| *d != m.degree()) {
        Some(d) => Err(format!(
            "its degree is {} but --degree {d} was given",
            m.degree()
        )),
        None => omniad_acquire::residual::fixed::check(&m, set),
    };
    why.map_err(|why| {
        anyhow::anyhow!(
            "{}: cannot be the base model of {}: {why}",
            path.display(),
            dir.display()
        )
    })?;
    Ok(m)
}

fn print_text(r: &Report) {
    if r.baseline_model == "given" {
        println!(
            "base model: the given --coeffs file, held fixed (its errors are its residual on every take)"
        );
    }
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
    if let Some(s) = &r.resimulation {
        println!(
            "re-simulation, first 0.5 s of each take held out (models fitted without it): {:.4} m base, {:.4} m extended",
            s.base_m, s.extended_m
        );
        for t in &s.takes {
            println!(
                "  {:<16} {:.4} m base, {:.4} m extended",
                t.take, t.base_m, t.extended_m
            );
        }
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
