//! `omniad flight fit DIR --train CYCLES --test CYCLES`: the OmniAD model
//! of a real kite from flight telemetry, with effects chosen on held-out
//! cycles (logic in `omniad-flight`).

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use omniad_flight::kite::KiteProperties;
use omniad_flight::log::parse_cycles;
use omniad_flight::{run as fit_flight, FlightFitConfig, Report};
use std::path::PathBuf;

/// `omniad flight ...`
#[derive(Subcommand, Debug)]
pub enum FlightCommand {
    /// Fit C_F of the kite on training cycles, find and add the effects the
    /// held-out residual points to, report before and after on test cycles.
    Fit(FitArgs),
}

/// Arguments of `omniad flight fit`.
#[derive(Args, Debug)]
pub struct FitArgs {
    /// Folder of cycle files (`*_NNNN.csv`, the Kitepower 2019-10-08 layout).
    pub dir: PathBuf,
    /// Training cycles, e.g. `1-30` or `1-5,8`.
    #[arg(long)]
    pub train: String,
    /// Test cycles, e.g. `31-40` (never used by any fitting step).
    #[arg(long)]
    pub test: String,
    /// Write the base model's coefficients here (.omni, body frame FRD).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write SVG figures into this folder (created if needed).
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// SH degree of C_F.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u8).range(1..=8))]
    pub degree: u8,
    /// Airborne mass, kg (default 36.2, the README's masses summed).
    #[arg(long)]
    pub mass: Option<f64>,
    /// Share of the tether's weight the kite carries, 0-1 (default 0.5).
    #[arg(long)]
    pub tether_weight_share: Option<f64>,
    /// Of the airborne mass, the control unit's hanging below the canopy, kg
    /// (default 22.0).
    #[arg(long)]
    pub kcu_mass: Option<f64>,
    /// Tether drag removed by the balance, as the drag-coefficient share c
    /// of `c ½ρ|V|² d l` (default 0: none; the tether_drag candidate tests it).
    #[arg(long)]
    pub tether_drag_share: Option<f64>,
    /// Tether diameter, m (default 0.01).
    #[arg(long)]
    pub tether_diameter: Option<f64>,
    /// Tether density, kg/m³ (default 724, Dyneema).
    #[arg(long)]
    pub tether_density: Option<f64>,
    /// Reference length L of the OmniAD model, m (default 9.2).
    #[arg(long)]
    pub reference_length: Option<f64>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `omniad flight`.
pub fn run(cmd: &FlightCommand) -> Result<()> {
    match cmd {
        FlightCommand::Fit(a) => fit(a),
    }
}

fn fit(a: &FitArgs) -> Result<()> {
    let mut kite = KiteProperties::default();
    if let Some(m) = a.mass {
        kite.mass = m;
    }
    let overrides = [
        (&mut kite.tether_weight_share, a.tether_weight_share),
        (&mut kite.tether_drag_share, a.tether_drag_share),
        (&mut kite.kcu_mass, a.kcu_mass),
        (&mut kite.tether_diameter, a.tether_diameter),
        (&mut kite.tether_density, a.tether_density),
        (&mut kite.reference_length, a.reference_length),
    ];
    for (slot, value) in overrides {
        if let Some(v) = value {
            *slot = v;
        }
    }
    let cfg = FlightFitConfig {
        dir: a.dir.clone(),
        train: parse_cycles(&a.train).map_err(|e| anyhow::anyhow!("--train: {e}"))?,
        test: parse_cycles(&a.test).map_err(|e| anyhow::anyhow!("--test: {e}"))?,
        kite,
        degree: usize::from(a.degree),
    };
    if let Some(path) = &a.output {
        // The cycle files the fit reads (a model written into the folder
        // before is none of them, so a re-run may replace it).
        let cycles: Vec<u32> = cfg.train.iter().chain(&cfg.test).copied().collect();
        let inputs = omniad_flight::log::find_cycles(&a.dir, &cycles).unwrap_or_default();
        super::common::refuse_input(path, &inputs)?;
    }
    anyhow::ensure!(!cfg.train.is_empty(), "--train names no cycle");
    anyhow::ensure!(!cfg.test.is_empty(), "--test names no cycle");
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        bar.set_style(style);
    }
    let outcome = fit_flight(&cfg, |m| bar.set_message(m.to_owned()))?;
    bar.finish_and_clear();
    if let Some(path) = &a.output {
        super::common::write_coefficients(path, &outcome.model)?;
    }
    if let Some(dir) = &a.plots {
        omniad_io::write_files_atomic(dir, outcome.plots.iter().map(|(n, svg)| (n, svg)))
            .context("cannot write the plots")?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&outcome.report)?);
    } else {
        print_text(&outcome.report);
    }
    Ok(())
}

fn print_text(r: &Report) {
    let rows = |k: &str| r.rows.get(k).map_or(0, |x| x.used);
    println!(
        "train cycles {:?} ({} samples), test cycles {:?} ({} samples)",
        r.train_cycles,
        rows("train"),
        r.test_cycles,
        rows("test")
    );
    for (k, v) in &r.rows {
        let dropped: usize = v.dropped_missing.values().sum();
        println!(
            "  {k}: {} rows read, {} used, {} dropped for a missing or impossible value {:?}, {} without airflow",
            v.read, v.used, dropped, v.dropped_missing, v.dropped_no_airflow
        );
    }
    println!("held-out (test cycles)      force RMS   tension RMS   tension rel.");
    let line = |name: &str, h: &omniad_flight::report::HeldOut| {
        println!(
            "  {name:<24} {:>8.0} N  {:>9.0} N  {:>10.1} %",
            h.heldout_force_rms,
            h.heldout_tension_rms,
            100.0 * h.tension_relative_error
        )
    };
    line("base model", &r.baseline);
    line("with selected effects", &r.after);
    println!("candidates (selection on training cycles, leave-one-cycle-out):");
    for c in &r.candidates {
        println!(
            "  step {} {:<22} CV {:>6.0} N  test {:>6.0} N  {}",
            c.tried.step,
            c.tried.effect,
            c.tried.cv_force_rms,
            c.heldout_force_rms,
            c.tried.rejected.as_deref().unwrap_or("")
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
    for (k, (v, e)) in &r.params {
        println!("  {k}: {v:.4} ± {e:.4} (jackknife over training cycles)");
    }
    println!("{}", r.verdict);
    println!("assumptions:");
    for a in &r.assumptions {
        println!("  - {a}");
    }
}
