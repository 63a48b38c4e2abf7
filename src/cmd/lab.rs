//! `omniad lab`: the research measurements behind BENCHMARKS.md (issue
//! 14 item 6; formerly seven `omniad-acquire` examples configured by
//! environment variables). Parses flags, runs
//! `omniad_acquire::lab::<measurement>::run`, prints its report.

use super::fit::MethodArg;
use anyhow::Result;
use clap::{Args, Subcommand};
use omniad_acquire::lab::{self, Knobs};
use omniad_acquire::pipeline::Method;
use std::path::PathBuf;

/// The measurements.
#[derive(Subcommand, Debug)]
pub enum LabCommand {
    /// Acceptance numbers of a synthetic set: state errors and C_F error.
    Accept(Common),
    /// Per-frame depth from the markers and its Cramér-Rao bound.
    Depth(Set),
    /// Reconstruction errors in the camera frame with a given model.
    Diag(DiagArgs),
    /// Is the fitted C_F error force noise or force bias?
    Forcenoise(Set),
    /// Residual analysis from the true states: terms the model lacks.
    MissingTerms(Set),
    /// Forces or velocities: which carries the C_F error?
    Mixfit(Set),
    /// The C_F error budget: one error source at a time.
    Forcebudget(Common),
    /// Which frames' torque error makes the C_T error?
    Torquesplit(Set),
    /// Is the torque fit's regularisation right for its noise?
    Torquereg(Set),
    /// The steering model's leak into dΩ/dt, measured and taken out.
    Deleak(Set),
    /// Does the model that steered the last reconstruction leak into dΩ/dt?
    Steering(Set),
    /// The fit from the true states (fit error alone).
    Truthfit(TruthfitArgs),
}

/// A synthetic recording set (with `truth/`).
#[derive(Args, Debug)]
pub struct Set {
    /// The set's folder.
    pub set: PathBuf,
}

/// The set and the pipeline knobs.
#[derive(Args, Debug)]
pub struct Common {
    /// The set's folder (with `truth/`).
    pub set: PathBuf,
    /// Fitting method.
    #[arg(long, value_enum, default_value_t = MethodArg::Lsq)]
    pub method: MethodArg,
    /// Refinement iterations.
    #[arg(long, default_value_t = omniad_acquire::pipeline::DEFAULT_ITERATIONS)]
    pub iterations: usize,
    /// SH degree.
    #[arg(long)]
    pub degree: Option<u8>,
    /// The torque's own SH degree N_T, forced (default: chosen by held-out
    /// takes, as `omniad fit`).
    #[arg(long, value_parser = clap::value_parser!(u8).range(0..=12))]
    pub torque_degree: Option<u8>,
    /// The final torque fit's window: the mean equations of every other
    /// frame over 2M-1 frames about each frame (`fit::torque_window`;
    /// default 3; 1: each frame alone).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=15))]
    pub torque_window: Option<u16>,
    /// Order p of the smoothness penalty (default: cross-validated).
    #[arg(long)]
    pub order: Option<u32>,
    /// A fixed smoothing weight instead of the cross-validated one.
    #[arg(long)]
    pub smoothing: Option<f64>,
    /// The paper's model only (no spin or gravity coupling).
    #[arg(long)]
    pub no_extensions: bool,
    /// Floor of the process noise's walks, relative to the no-model walks.
    #[arg(long)]
    pub noise_floor: Option<f64>,
    /// Turn of the air's direction (rad) over which the unexplained torque
    /// decorrelates (`FitConfig::torque_turn`; default: off). Positive.
    #[arg(long, value_parser = positive_angle)]
    pub torque_turn: Option<f64>,
    /// Frames of the mirror-branch test (0: none).
    #[arg(long)]
    pub mirror_window: Option<usize>,
    /// Relinearisations of the filter (`FilterConfig::relinearise`).
    #[arg(long)]
    pub relinearise: Option<usize>,
    /// Iterations (from the last) that relinearise.
    #[arg(long)]
    pub relinearised_iterations: Option<usize>,
    /// Reconstruct each take with the force model fitted without its own
    /// frames (`FitConfig::cross_fit`).
    #[arg(long)]
    pub cross_fit: bool,
    /// Per-take state errors of the last iteration too.
    #[arg(long)]
    pub per_take: bool,
    /// Write the true and fitted C_F at every truth grid direction (CSV).
    #[arg(long)]
    pub dump: Option<PathBuf>,
}

/// `omniad lab diag`.
#[derive(Args, Debug)]
pub struct DiagArgs {
    /// The set's folder (with `truth/`).
    pub set: PathBuf,
    /// Model to reconstruct with: plate, box (the synthetic generating
    /// models), zero, or fit (the pipeline's).
    #[arg(long, default_value = "zero")]
    pub model: String,
    /// Scale of the unexplained wrench's walk.
    #[arg(long, default_value_t = 1.0)]
    pub walk_scale: f64,
    /// Scale of the white acceleration noise.
    #[arg(long, default_value_t = 1.0)]
    pub white_scale: f64,
    /// Scale of the initial unexplained wrench.
    #[arg(long, default_value_t = 1.0)]
    pub bias_scale: f64,
    /// Frames of the mirror-branch test (0: none).
    #[arg(long)]
    pub mirror_window: Option<usize>,
    /// Relinearisations of the filter.
    #[arg(long)]
    pub relinearise: Option<usize>,
    /// Relinearisations of the final reconstruction (`--model fit`).
    #[arg(long)]
    pub relinearise_final: Option<usize>,
    /// Print this take's errors over time.
    #[arg(long)]
    pub take: Option<String>,
}

/// `omniad lab truthfit`.
#[derive(Args, Debug)]
pub struct TruthfitArgs {
    /// The set's folder (with `truth/`).
    pub set: PathBuf,
    /// Smoothing weight where cross-validation cannot choose one.
    #[arg(long)]
    pub fallback_smoothing: Option<f64>,
    /// Relinearisations of the filter.
    #[arg(long)]
    pub relinearise: Option<usize>,
}

impl Common {
    fn knobs(&self) -> Knobs {
        Knobs {
            method: Some(match self.method {
                MethodArg::Lsq => Method::Lsq,
                MethodArg::Paper => Method::Paper,
            }),
            iterations: Some(self.iterations),
            noise_floor: self.noise_floor,
            torque_turn: self.torque_turn,
            mirror_window: self.mirror_window,
            smoothing: self.smoothing,
            no_extensions: self.no_extensions,
            relinearise: self.relinearise,
            relinearised_iterations: self.relinearised_iterations,
            cross_fit: self.cross_fit,
            degree: self.degree,
            torque_degree: self.torque_degree,
            torque_window: self.torque_window.map(usize::from),
            order: self.order,
            per_take: self.per_take,
            dump: self.dump.clone(),
            ..Knobs::default()
        }
    }
}

/// Runs one measurement, its report on stdout.
pub fn run(c: &LabCommand) -> Result<()> {
    let mut out = std::io::stdout().lock();
    let result = match c {
        LabCommand::Accept(a) => lab::accept::run(&a.set, &a.knobs(), &mut out),
        LabCommand::Depth(a) => lab::depth::run(&a.set, &mut out),
        LabCommand::Diag(a) => {
            let knobs = Knobs {
                mirror_window: a.mirror_window,
                relinearise: a.relinearise,
                relinearise_final: a.relinearise_final,
                take: a.take.clone(),
                ..Knobs::default()
            };
            let scales = [a.walk_scale, a.white_scale, a.bias_scale];
            lab::diag::run(&a.set, &a.model, scales, &knobs, &mut out)
        }
        LabCommand::Forcenoise(a) => lab::forcenoise::run(&a.set, &mut out),
        LabCommand::MissingTerms(a) => lab::missing_terms::run(&a.set, &mut out),
        LabCommand::Mixfit(a) => lab::mixfit::run(&a.set, &mut out),
        LabCommand::Forcebudget(a) => lab::forcebudget::run(&a.set, &a.knobs(), &mut out),
        LabCommand::Torquesplit(a) => lab::torquesplit::run(&a.set, &mut out),
        LabCommand::Deleak(a) => lab::deleak::run(&a.set, &mut out),
        LabCommand::Torquereg(a) => lab::torquereg::run(&a.set, &mut out),
        LabCommand::Steering(a) => lab::steering::run(&a.set, &mut out),
        LabCommand::Truthfit(a) => {
            let knobs = Knobs {
                relinearise: a.relinearise,
                ..Knobs::default()
            };
            lab::truthfit::run(&a.set, a.fallback_smoothing, &knobs, &mut out)
        }
    };
    result.map_err(|e| anyhow::anyhow!("{e}"))
}

/// `--torque-turn`: a positive, finite angle in radians (a zero or negative
/// turn would make the unexplained torque's correlation rate infinite or
/// negative).
fn positive_angle(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|e| format!("{s:?} is not a number: {e}"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} rad: the turn must be positive and finite"))
    }
}
