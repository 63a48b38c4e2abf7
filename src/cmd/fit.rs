//! `omniad fit`: a recording set to a coefficient file (paper §5-6, issue 3).

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::pipeline::{self, FitConfig, FitOutcome, IterationReport, Method};
use omniad_acquire::reconstruct::run::Progress;
use serde_json::json;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

/// Fitting method.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MethodArg {
    /// Regularised least squares on the frames (default).
    Lsq,
    /// The paper's 3-NN grid interpolation and SH convolution (eqs. 11-13).
    Paper,
}

/// Arguments of `omniad fit`.
#[derive(Args, Debug)]
pub struct FitArgs {
    /// Recording set folder (holding recording.toml).
    pub set: PathBuf,
    /// Output coefficient file (.omni).
    #[arg(short, long)]
    pub output: PathBuf,
    /// SH degree N.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u8).range(0..=12))]
    pub degree: u8,
    /// SH degree N_T of the torque (its own; default: N or N+2, up to 12,
    /// whichever predicts the held-out takes' torques better).
    #[arg(long, value_parser = clap::value_parser!(u8).range(0..=12))]
    pub torque_degree: Option<u8>,
    /// Fitting method.
    #[arg(long, value_enum, default_value_t = MethodArg::Lsq)]
    pub method: MethodArg,
    /// Refinement iterations (filter + fit rounds, §6). More rounds are not
    /// better: the refinement drifts towards its own model (C_F on five of
    /// six sets measured is worse after 8 rounds than after 3; about 1.2 s
    /// per round, see BENCHMARKS.md issue 20); a round that fits worse is
    /// rejected and stops the refinement.
    #[arg(long, default_value_t = omniad_acquire::pipeline::DEFAULT_ITERATIONS)]
    pub iterations: usize,
    /// Model extensions beyond eqs. (5)-(6): the spin coupling (a force
    /// bilinear in Ω and V: Magnus, added-mass coupling) and the gravity
    /// coupling (a force linear in gravity seen from the body: buoyancy,
    /// added mass). `auto` keeps those that leave-one-take-out
    /// cross-validation says predict held-out takes better; `off` fits the
    /// paper's model only. `--method paper` never fits them.
    #[arg(long, value_enum, default_value_t = ExtensionsArg::Auto)]
    pub extensions: ExtensionsArg,
    /// Reconstruct each take, after the first round, with the force model
    /// fitted without its own frames (cross-fitting; with `--iterations 4`
    /// it improved C_F and C_T on the sets measured, BENCHMARKS.md issue 20).
    #[arg(long)]
    pub cross_fit: bool,
    /// Print a JSON report on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Whether `omniad fit` may add model extensions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ExtensionsArg {
    /// Fit them; keep those cross-validation keeps.
    Auto,
    /// Never fit them.
    Off,
}

/// Progress bars on stderr, one per pipeline stage.
#[derive(Default)]
pub struct Bars(Mutex<Option<ProgressBar>>);

impl Progress for Bars {
    fn stage(&self, name: &str, total: usize) {
        let bar = ProgressBar::new(total as u64).with_message(name.to_owned());
        if let Ok(style) = ProgressStyle::with_template("{msg:40} [{bar:30}] {pos}/{len} {elapsed}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        let old = self.0.lock().ok().and_then(|mut b| b.replace(bar));
        if let Some(old) = old {
            old.finish();
        }
    }
    fn tick(&self) {
        if let Some(b) = self.0.lock().ok().as_ref().and_then(|b| b.as_ref()) {
            b.inc(1);
        }
    }
}

impl Bars {
    /// Starts the final-reconstruction stage.
    pub fn stage_final(&self, takes: usize) {
        self.stage("final reconstruction", takes);
    }
}

impl Drop for Bars {
    fn drop(&mut self) {
        if let Some(b) = self.0.get_mut().ok().and_then(Option::take) {
            b.finish();
        }
    }
}

/// Loads a set, naming it in errors.
pub fn load(set: &std::path::Path) -> Result<RecordingSet> {
    RecordingSet::load(set)
        .map_err(|e| anyhow::anyhow!("{e}"))
        .with_context(|| format!("reading recording set {}", set.display()))
}

/// Runs `omniad fit`.
pub fn run(a: &FitArgs) -> Result<()> {
    let start = Instant::now();
    let set = load(&a.set)?;
    super::common::refuse_input(&a.output, &set.files)?;
    let loaded = start.elapsed().as_secs_f64();
    let method = match a.method {
        MethodArg::Lsq => Method::Lsq,
        MethodArg::Paper => Method::Paper,
    };
    let mut cfg = FitConfig {
        degree: a.degree,
        method,
        iterations: a.iterations,
        cross_fit: a.cross_fit,
        ..FitConfig::default()
    };
    cfg.lsq.extensions = a.extensions == ExtensionsArg::Auto;
    cfg.lsq.torque_degree = a.torque_degree.map(usize::from);
    let outcome = {
        let bars = Bars::default();
        pipeline::fit(&set, &cfg, &bars).map_err(|e| anyhow::anyhow!("{e}"))?
    };
    super::common::write_coefficients(&a.output, &outcome.model)?;
    let total = start.elapsed().as_secs_f64();
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report(&outcome, loaded, total))?
        );
    } else {
        summary(&outcome, a, total);
    }
    Ok(())
}

fn summary(o: &FitOutcome, a: &FitArgs, total: f64) {
    let p = &o.model.provenance;
    println!(
        "wrote {} ({}, degree {}, torque degree {})",
        a.output.display(),
        p.method,
        o.model.degree(),
        o.model.torque_degree()
    );
    for (i, r) in o.iterations.iter().enumerate() {
        let note = if r.rejected {
            " (worse: rejected, refinement stopped)"
        } else {
            ""
        };
        let smoothing = r.smoothing.map_or(String::new(), |s| {
            format!(
                "; smoothing force {:.0e} order {}, torque {:.0e} order {}",
                s.force.weight, s.force.order, s.torque.weight, s.torque.order
            )
        });
        let kept = kept_previous(o, r);
        let kept = if kept.is_empty() {
            String::new()
        } else {
            format!(
                "; {} kept the previous pose branch (this model's run missed their markers)",
                kept.join(", ")
            )
        };
        println!(
            "iteration {}: residual force {:.4}, torque {:.4} ({:.2} s){smoothing}{kept}{note}",
            i + 1,
            r.residual.0,
            r.residual.1,
            r.seconds
        );
    }
    let test = o
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .and_then(|r| r.extension_test);
    if let Some(t) = test {
        println!(
            "extensions, leave one take out ({} takes, {} frames): force RMS {:.4} N without, {:.4} N spin coupling, {:.4} N gravity coupling, {:.4} N both",
            t.takes, t.frames, t.held_out_rms_without, t.held_out_rms_spin, t.held_out_rms_gravity, t.held_out_rms_both
        );
    }
    match o.model.gravity_coupling() {
        Some(g) => println!(
            "gravity coupling kept: buoyancy-equivalent volume {:.3e} m^3",
            g.buoyancy_volume(o.model.reference_length())
        ),
        None => println!("gravity coupling: none"),
    }
    match o.model.spin_coupling() {
        Some(k) => println!(
            "spin coupling kept: Magnus part {:.4}, |K| {:.4}",
            k.magnus_scale(),
            k.norm()
        ),
        None => println!("spin coupling: none"),
    }
    for l in &o.left_out {
        println!("take {} left out: {}", l.take, l.why);
    }
    let strong: Vec<String> = o
        .take_scales
        .iter()
        .zip(&o.takes)
        .filter_map(|(s, name)| s.filter(|&k| k > 1.0).map(|k| format!("{name} x{k}")))
        .collect();
    if !strong.is_empty() {
        println!(
            "air wrench assumed larger in the reconstruction of: {}",
            strong.join(", ")
        );
    }
    let covered = p.coverage.iter().filter(|&&c| c > 0).count();
    println!(
        "frames used {}, dropped {}; {covered}/512 direction cells covered; {total:.2} s",
        p.frames_used, p.frames_dropped
    );
}

fn report(o: &FitOutcome, loaded: f64, total: f64) -> serde_json::Value {
    let p = &o.model.provenance;
    let last = o.iterations.last();
    let its: Vec<_> = o
        .iterations
        .iter()
        .map(|r| {
            json!({
                "force_residual": r.residual.0, "torque_residual": r.residual.1,
                "force_residual_n": r.residual_dimensional.0, "torque_residual_nm": r.residual_dimensional.1,
                "process_noise": { "force_walk": r.noise.force_walk, "torque_walk": r.noise.torque_walk },
                "marker_rows_used": r.filter.used, "marker_rows_gated": r.filter.gated,
                "empty_frames": r.filter.empty_frames, "filter_restarts": r.filter.restarts,
                "mirror_switches": r.filter.mirror_switches,
                "rejected": r.rejected, "seconds": r.seconds,
                "kept_previous_takes": kept_previous(o, r),
                "smoothing": r.smoothing.map(|s| json!({
                    "force": { "weight": s.force.weight, "order": s.force.order },
                    "torque": { "weight": s.torque.weight, "order": s.torque.order },
                })),
                "extension_test": r.extension_test.map(|t| json!({
                    "kept": { "spin_coupling": t.kept.spin, "gravity_coupling": t.kept.gravity },
                    "held_out_force_rms_n": {
                        "without": t.held_out_rms_without,
                        "spin_coupling": t.held_out_rms_spin,
                        "gravity_coupling": t.held_out_rms_gravity,
                        "both": t.held_out_rms_both,
                    },
                    "frames": t.frames, "takes": t.takes,
                })),
            })
        })
        .collect();
    json!({
        "method": p.method.as_str(),
        "degree": o.model.degree(),
        "torque_degree": o.model.torque_degree(),
        "frames": {
            "reconstructed": last.map(|r| r.forces.frames),
            "used": p.frames_used,
            "dropped": {
                "thrust_f_dot_v_positive": last.map(|r| r.forces.dropped_thrust),
                "spin_up_t_dot_omega_positive_torque_fit_only": last.map(|r| r.forces.dropped_spin_up),
                "difference_across_a_branch_cut": last.map(|r| r.forces.across_cut),
                "outlier_marker_rows_gated": last.map(|r| r.filter.gated),
                "empty_frames": last.map(|r| r.filter.empty_frames),
            },
        },
        "iterations": its,
        "left_out_takes": o.left_out,
        "take_wrench_scales": o.takes.iter().zip(&o.take_scales).map(|(n, s)| json!({ "take": n, "scale": s })).collect::<Vec<_>>(),
        "coverage": {
            "grid": [32, 16],
            "cells_covered": p.coverage.iter().filter(|&&c| c > 0).count(),
            "counts_longitude_major": p.coverage.as_slice(),
        },
        "damping": o.model.damping().as_slice(),
        "spin_coupling": o.model.spin_coupling().map(|k| json!({
            "tensor_k_ijk": k.k,
            "magnus_scale": k.magnus_scale(),
        })),
        "gravity_coupling": o.model.gravity_coupling().map(|g| json!({
            "matrix_g_rows": [g.g.row(0).iter().collect::<Vec<_>>(), g.g.row(1).iter().collect::<Vec<_>>(), g.g.row(2).iter().collect::<Vec<_>>()],
            "buoyancy_volume_m3": g.buoyancy_volume(o.model.reference_length()),
        })),
        "timings": { "load_s": loaded, "total_s": total },
    })
}

/// The names of the takes that kept the previous iteration's
/// reconstruction in iteration `r` (`pipeline::carry`).
fn kept_previous<'a>(o: &'a FitOutcome, r: &IterationReport) -> Vec<&'a str> {
    r.kept_previous
        .iter()
        .filter_map(|&i| o.takes.get(i).map(String::as_str))
        .collect()
}
