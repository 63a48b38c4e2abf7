//! The research measurements behind BENCHMARKS.md, run as `omniad lab
//! <measurement> SET [flags]` (one function per measurement; the CLI only
//! parses and prints). Most need a synthetic set's `truth/`.
//!
//! * [`accept`]: the acceptance numbers (state errors, C_F error);
//! * [`deleak`]: the steering model's leak, measured and taken out;
//! * [`depth`]: per-frame depth from the markers and its Cramér-Rao bound;
//! * [`diag`]: reconstruction errors in the camera frame with a given model;
//! * [`forcebudget`]: the C_F error budget, one error source at a time;
//! * [`forcenoise`]: is the C_F error force noise or force bias?
//! * [`missing_terms`]: residual analysis of terms the model lacks;
//! * [`mixfit`]: forces or velocities — which carries the C_F error?
//! * [`steering`]: does the steering model leak into `dΩ/dt`?
//! * [`torquereg`]: is the torque fit's regularisation right for its noise?
//! * [`torquesplit`]: which frames' torque error makes the C_T error?
//! * [`truthfit`]: the fit from the true states (fit error alone).

pub mod accept;
pub mod deleak;
pub mod depth;
pub mod diag;
pub mod forcebudget;
pub mod forcenoise;
pub mod missing_terms;
pub mod mixfit;
pub mod steering;
pub mod torquereg;
pub mod torquesplit;
pub mod truthfit;

use crate::pipeline::{FitConfig, Method};
use std::path::PathBuf;

/// A measurement's result (its report goes to the writer it is given).
pub type LabResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// `writeln!` to a lab report, returning its error.
macro_rules! say {
    ($out:expr, $($t:tt)*) => {
        writeln!($out, $($t)*)?
    };
}
pub(crate) use say;

/// The knobs of the measurements: the pipeline's settings a study varies
/// (each `None`/`false` keeps [`FitConfig::default`]'s).
#[derive(Clone, Debug, Default)]
pub struct Knobs {
    /// Fit method (default least squares).
    pub method: Option<Method>,
    /// Refinement iterations (default 3).
    pub iterations: Option<usize>,
    /// `FitConfig::noise_floor`.
    pub noise_floor: Option<f64>,
    /// `FitConfig::torque_turn`, rad.
    pub torque_turn: Option<f64>,
    /// `FilterConfig::mirror_window` (0: no mirror-branch tests).
    pub mirror_window: Option<usize>,
    /// A fixed smoothing weight instead of the cross-validated one.
    pub smoothing: Option<f64>,
    /// The paper's model only (no extensions).
    pub no_extensions: bool,
    /// `FilterConfig::relinearise`.
    pub relinearise: Option<usize>,
    /// `FitConfig::relinearised_iterations`.
    pub relinearised_iterations: Option<usize>,
    /// `FitConfig::cross_fit`.
    pub cross_fit: bool,
    /// `FilterConfig::relinearise` of the final reconstruction (diag).
    pub relinearise_final: Option<usize>,
    /// SH degree.
    pub degree: Option<u8>,
    /// `LsqConfig::torque_degree`: the final torque fit's N_T, forced.
    pub torque_degree: Option<u8>,
    /// `LsqConfig::torque_window`: the final torque fit's window, forced.
    pub torque_window: Option<usize>,
    /// `LsqConfig::smoothness_order`.
    pub order: Option<u32>,
    /// Per-take errors of the last iteration too (accept).
    pub per_take: bool,
    /// Where to write the per-direction C_F comparison (accept).
    pub dump: Option<PathBuf>,
    /// A take whose errors over time are printed (diag).
    pub take: Option<String>,
}

impl Knobs {
    /// The pipeline configuration these knobs give.
    pub fn fit_config(&self) -> FitConfig {
        let mut cfg = FitConfig::default();
        if let Some(m) = self.method {
            cfg.method = m;
        }
        if let Some(k) = self.iterations {
            cfg.iterations = k;
        }
        if let Some(f) = self.noise_floor {
            cfg.noise_floor = f;
        }
        if let Some(t) = self.torque_turn {
            cfg.torque_turn = t;
        }
        if let Some(w) = self.mirror_window {
            cfg.filter.mirror_window = w;
        }
        if let Some(r) = self.smoothing {
            cfg.lsq.smoothing = r;
            cfg.lsq.cross_validate = false;
        }
        if self.no_extensions {
            cfg.lsq.extensions = false;
        }
        if let Some(r) = self.relinearise {
            cfg.filter.relinearise = r;
        }
        if let Some(r) = self.relinearised_iterations {
            cfg.relinearised_iterations = r;
        }
        if self.cross_fit {
            cfg.cross_fit = true;
        }
        if let Some(d) = self.degree {
            cfg.degree = d;
        }
        if let Some(d) = self.torque_degree {
            cfg.lsq.torque_degree = Some(usize::from(d));
        }
        if let Some(m) = self.torque_window {
            cfg.lsq.torque_window = m;
        }
        if let Some(p) = self.order {
            cfg.lsq.smoothness_order = Some(p);
        }
        cfg
    }
}

/// A set fitted with the default pipeline, and the frames (eqs. 9-10) of
/// its true states: what the studies that compare the two start from.
pub(crate) struct FittedWithTruth {
    /// The set.
    pub set: crate::input::recording::RecordingSet,
    /// The default configuration it was fitted with.
    pub cfg: FitConfig,
    /// The pipeline's outcome.
    pub fit: crate::pipeline::FitOutcome,
    /// `truth/`'s states, one per take.
    pub truth_states: Vec<crate::reconstruct::filter::Smoothed>,
    /// The frames (eqs. 9-10) of `truth_states`.
    pub truth_frames: Vec<crate::reconstruct::forces::Sample>,
}

/// [`FittedWithTruth`] of the set in `dir` (with `truth/`).
pub(crate) fn fitted_with_truth(
    dir: &std::path::Path,
) -> Result<FittedWithTruth, Box<dyn std::error::Error>> {
    fitted_with_truth_by(dir, FitConfig::default())
}

/// [`fitted_with_truth`] with the configuration `cfg`.
pub(crate) fn fitted_with_truth_by(
    dir: &std::path::Path,
    cfg: FitConfig,
) -> Result<FittedWithTruth, Box<dyn std::error::Error>> {
    let set = crate::input::recording::RecordingSet::load(dir)?;
    let fit = crate::pipeline::fit(&set, &cfg, &crate::reconstruct::run::Silent)?;
    let truth_states = crate::synth::truth::true_trajectories(dir, &set)?;
    let mut st = crate::reconstruct::forces::ForceStats::default();
    let truth_frames = crate::reconstruct::run::samples(&set, &truth_states, &mut st);
    Ok(FittedWithTruth {
        set,
        cfg,
        fit,
        truth_states,
        truth_frames,
    })
}

/// The truth grid (`[E, C_F, C_T]` rows, `synth::truth::read_coefficients`)
/// as frames at |V| = 1 m/s and no spin, so that a fit of them projects the
/// truth onto the model's space: eqs. (5) and (6) give F = ½ρL² C_F(E) and
/// T = ½ρL³ C_T(E) (N, N·m; body frame). The other fields come from
/// `template`; the rows are spread over five pseudo-takes so that the fits'
/// leave-one-take-out machinery has takes to leave out.
pub(crate) fn truth_grid_frames(
    set: &crate::input::recording::RecordingSet,
    template: &crate::reconstruct::forces::Sample,
    truth: &[[nalgebra::Vector3<f64>; 3]],
) -> Vec<crate::reconstruct::forces::Sample> {
    let ctx = crate::fit::context::FitContext::of_set(set);
    let q = 0.5 * ctx.air_density * ctx.reference_length.powi(2);
    let l = ctx.reference_length;
    truth
        .iter()
        .enumerate()
        .map(|(i, [e, cf, ct])| crate::reconstruct::forces::Sample {
            take: i % 5,
            velocity: e.normalize(),
            angular_velocity: nalgebra::Vector3::zeros(),
            force: cf * q,
            torque: ct * (q * l),
            force_cov: nalgebra::Matrix3::zeros(),
            use_force: true,
            use_torque: true,
            ..*template
        })
        .collect()
}
