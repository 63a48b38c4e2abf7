//! The acquisition pipeline with iterative refinement (§6): reconstruct
//! every take with the current model, reconstruct forces, fit, repeat.

mod carry;
mod cross_fit;
mod diagnose;
mod process_effects;
mod provenance;

use crate::error::{Error, Result};
use crate::fit::config::LsqConfig;
use crate::fit::context::FitContext;
use crate::fit::extensions::ExtensionTest;
use crate::fit::model::{with_raw, zero_model, FitSmoothing};
use crate::fit::residuals::{frame_residuals, rms_dimensional, summary};
use crate::fit::torque::{refit_final_torque, TorqueFrames};
use crate::fit::weights::{add_velocity_spread, with_markers_only_covariances};
use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::{FilterConfig, FilterStats, Smoothed};
use crate::reconstruct::first::{first, LeftOut};
use crate::reconstruct::forces::{ForceStats, Sample};
use crate::reconstruct::noise::{initial_noise, next_noise, ProcessNoise};
use crate::reconstruct::run::{samples_in_wind, Progress, TakeModels};
use crate::reconstruct::schedule::most_likely_bias_time_scored;
use omniad_core::Coefficients;
use provenance::{fill_provenance, total_stats};
use std::time::Instant;

/// Fitting method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Regularised least squares on the frames (default).
    Lsq,
    /// The paper's 3-NN grid interpolation and SH convolution.
    Paper,
}

/// Pipeline settings.
#[derive(Clone, Debug, PartialEq)]
pub struct FitConfig {
    /// SH degree N (the paper uses 8).
    pub degree: u8,
    /// Method.
    pub method: Method,
    /// Refinement iterations (fit count; §6 uses 3; default
    /// [`DEFAULT_ITERATIONS`]).
    pub iterations: usize,
    /// Least-squares settings (degree is taken from `degree`).
    pub lsq: LsqConfig,
    /// Filter settings (pixel noise is taken from the camera).
    pub filter: FilterConfig,
    /// Lower bound of the refined process noise, as a fraction of the
    /// no-model noise of [`initial_noise`] (default 0.02).
    pub noise_floor: f64,
    /// The turn of the air's direction (rad) over which the unexplained
    /// torque of a fitted model decorrelates, making its correlation time
    /// shrink with the spin (`Process::torque_bias_time`); default
    /// `f64::INFINITY`, off: 1, 3 and 10 rad helped the plates' C_T
    /// (plate-mujoco 14.72 -> 11.58 % at 1 rad) but made openbox-clean's
    /// worse at every value (BENCHMARKS.md issue 20, stop 18).
    pub torque_turn: f64,
    /// How many of the last iterations reconstruct with the filter's
    /// relinearised sweeps (`filter.relinearise`; the others with none).
    /// Default: all. (With the old noise floor of 0.1, relinearised early
    /// iterations were seen to lead the mirror-branch test astray; with
    /// the floor at 0.02 all-relinearised runs were better on every set
    /// measured, see BENCHMARKS.md.)
    pub relinearised_iterations: usize,
    /// The object's named effects (the core's library,
    /// `omniad_core::effect`, at most one per kind) held in the process
    /// model and taken off the frames' air wrench before the coefficient
    /// fit; empty normally: the residual analysis's refit sets them (see
    /// `pipeline::process_effects`; the wind is `filter.wind`).
    pub effects: Vec<omniad_core::effect::Effect<f64>>,
    /// Reconstruct each take, after the first iteration, with the force
    /// model fitted without its own frames (`pipeline::cross_fit`;
    /// default false: with 4 iterations it improved C_F and C_T on the
    /// sets measured, but kept a spurious spin coupling on the buoyant
    /// synthetic plate of `tests/acquire_end_to_end.rs`, see BENCHMARKS.md
    /// issue 20).
    pub cross_fit: bool,
}

/// The default number of refinement iterations (§6). Not a convergence
/// test: the refinement's fixed point is not the truth (it confirms its
/// own model, and iterated on it drifts away: C_F after 8 iterations is
/// worse than after 3-4 on five of six sets measured, BENCHMARKS.md issue
/// 20), so the count is an early stop. With [`FitConfig::cross_fit`], 4
/// was better than 3 and 5 on the sets measured.
pub const DEFAULT_ITERATIONS: usize = 3;

impl FitConfig {
    /// The least-squares settings at the fit's SH degree.
    pub(crate) fn lsq_at_degree(&self) -> LsqConfig {
        LsqConfig {
            degree: usize::from(self.degree),
            ..self.lsq.clone()
        }
    }
}

impl Default for FitConfig {
    fn default() -> Self {
        Self {
            degree: 8,
            method: Method::Lsq,
            iterations: DEFAULT_ITERATIONS,
            lsq: LsqConfig::default(),
            filter: FilterConfig::default(),
            noise_floor: 0.02,
            torque_turn: f64::INFINITY,
            relinearised_iterations: usize::MAX,
            effects: Vec::new(),
            cross_fit: false,
        }
    }
}

/// What one refinement iteration did.
#[derive(Clone, Debug, PartialEq)]
pub struct IterationReport {
    /// Process noise the filter used.
    pub noise: ProcessNoise,
    /// Filter counts over all takes.
    pub filter: FilterStats,
    /// Stability-enforcement counts.
    pub forces: ForceStats,
    /// Non-dimensional RMS residuals (force, torque) of the fitted model.
    pub residual: (f64, f64),
    /// RMS residual force (N) and torque (N m).
    pub residual_dimensional: (f64, f64),
    /// Wall time, s.
    pub seconds: f64,
    /// The iteration's model was worse than the best and was not kept.
    pub rejected: bool,
    /// The held-out test of the model extensions (least squares with
    /// extensions allowed).
    pub extension_test: Option<ExtensionTest>,
    /// The smoothness penalties the least-squares fit chose.
    pub smoothing: Option<FitSmoothing>,
    /// The takes (indices in the set) whose fresh reconstruction with this
    /// iteration's model missed their markers over a stretch by more than
    /// their noise beyond the previous iteration's, and which kept its
    /// pose branch (`pipeline::carry`).
    pub kept_previous: Vec<usize>,
}

/// An iteration is rejected (see [`fit`]) when its force or torque residual
/// or its count of gated marker rows exceeds the last kept iteration's by
/// this factor (gated rows: plus 0.5 % of all rows), or when the filter had
/// to restart more often.
pub const REJECT_RATIO: f64 = 1.25;

fn worse(new: &IterationReport, kept: &IterationReport) -> bool {
    let rows = (new.filter.used + new.filter.gated) as f64;
    let gated_limit = REJECT_RATIO * kept.filter.gated as f64 + 0.005 * rows;
    let exceeds = |a: f64, b: f64| a.is_nan() || a > REJECT_RATIO * b;
    exceeds(new.residual.0, kept.residual.0)
        || exceeds(new.residual.1, kept.residual.1)
        || new.filter.gated as f64 > gated_limit
        || new.filter.restarts > kept.filter.restarts
}

/// Result of [`fit`].
#[derive(Clone, Debug)]
pub struct FitOutcome {
    /// The fitted model, with provenance filled in.
    pub model: Coefficients<f64>,
    /// One report per iteration.
    pub iterations: Vec<IterationReport>,
    /// The last reconstruction, one per take.
    pub reconstruction: Vec<Smoothed>,
    /// The last iteration's frames.
    pub samples: Vec<Sample>,
    /// Which of `samples` the model's torque part was fitted on.
    pub torque_frames: TorqueFrames,
    /// Per take: the air-wrench scale of its noise (`reconstruct::first`),
    /// `None` for a take left out.
    pub take_scales: Vec<Option<f64>>,
    /// The takes left out (their first reconstruction was implausible).
    pub left_out: Vec<LeftOut>,
    /// The takes' names, in the set's order (for `take_scales`).
    pub takes: Vec<String>,
}

/// Fits the model of the samples.
pub fn fit_samples(
    base: &Coefficients<f64>,
    samples: &[Sample],
    set: &RecordingSet,
    cfg: &FitConfig,
) -> Result<Coefficients<f64>> {
    fit_samples_tested(base, samples, set, cfg).map(|(m, _)| m)
}

/// What a fit decided besides the model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FitDetails {
    /// The held-out test of the model extensions (when run).
    pub extension_test: Option<ExtensionTest>,
    /// The smoothness penalties (least squares).
    pub smoothing: Option<FitSmoothing>,
}

/// [`fit_samples`], with the held-out test of the model extensions and the
/// smoothing chosen.
pub fn fit_samples_tested(
    base: &Coefficients<f64>,
    samples: &[Sample],
    set: &RecordingSet,
    cfg: &FitConfig,
) -> Result<(Coefficients<f64>, FitDetails)> {
    let ctx = FitContext::of_set(set);
    let raw = match cfg.method {
        Method::Lsq => crate::fit::lsq::fit(samples, &ctx, &cfg.lsq_at_degree()),
        Method::Paper => crate::fit::paper::fit(samples, &ctx, usize::from(cfg.degree)),
    };
    let details = FitDetails {
        extension_test: raw.extension_test,
        smoothing: raw.smoothing,
    };
    Ok((with_raw(base, &raw)?, details))
}

/// The whole pipeline: `cfg.iterations` rounds of reconstruct-and-fit.
pub fn fit(set: &RecordingSet, cfg: &FitConfig, progress: &dyn Progress) -> Result<FitOutcome> {
    if cfg.iterations == 0 {
        return Err(Error::Data("at least one iteration is needed".into()));
    }
    let base = process_effects::with_effects(zero_model(&set.object, cfg.degree)?, &cfg.effects)?;
    let mut model = base.clone();
    let first = initial_noise(set);
    let mut noise = first;
    let mut iterations: Vec<IterationReport> = Vec::with_capacity(cfg.iterations);
    let mut best: Option<(Coefficients<f64>, Vec<Smoothed>, Vec<Sample>)> = None;
    // The first, model-free reconstruction (see
    // `with_markers_only_covariances`).
    let mut markers_only: Option<Vec<Smoothed>> = None;
    let mut takes = Takes::default();
    let mut own: Vec<Coefficients<f64>> = Vec::new();
    for it in 0..cfg.iterations {
        let start = Instant::now();
        let previous = best.as_ref().map_or(&[][..], |b| &b.1[..]);
        let (smoothed, frames, fstats, kept_previous) = weighed_frames(
            set,
            &TakeModels {
                shared: &model,
                own: &own,
            },
            noise,
            cfg,
            it,
            (&mut markers_only, &mut takes, previous),
            progress,
        )?;
        progress.stage(&format!("iteration {}/{}: fit", it + 1, cfg.iterations), 1);
        // A later iteration whose reconstruction diverged can give a
        // non-finite fit: it is rejected like a worse one (below).
        // Extensions refine a fitted model: the first iteration's forces
        // come from a reconstruction with no model (§6, A_0 = 0), whose
        // errors correlate with anything, so it fits the paper's model only.
        let mut fit_cfg = cfg.clone();
        fit_cfg.lsq.extensions &= it > 0;
        let net = process_effects::net_of_effects(&frames, &base, set.world.air_density);
        let (fitted, details) = match fit_samples_tested(&base, &net, set, &fit_cfg) {
            Ok((m, d)) => (Some(m), d),
            Err(e) if iterations.is_empty() => {
                return Err(diagnose::first_fit_failed(e, set, &smoothed, &frames))
            }
            Err(_) => (None, FitDetails::default()),
        };
        progress.tick();
        let nan = (f64::NAN, f64::NAN);
        let res = fitted
            .as_ref()
            .map(|m| frame_residuals(m, &net, set.world.air_density));
        let mut report = IterationReport {
            noise,
            filter: total_stats(&smoothed),
            forces: fstats,
            residual: res.as_deref().map_or(nan, summary),
            residual_dimensional: res.as_deref().map_or(nan, rms_dimensional),
            seconds: start.elapsed().as_secs_f64(),
            rejected: false,
            extension_test: details.extension_test,
            smoothing: details.smoothing,
            kept_previous,
        };
        if iterations.is_empty() {
            if let Some(why) = diverged(&report, set, &smoothed) {
                return Err(Error::Data(why));
            }
        }
        // Refinement must not make things worse: a model whose filter run
        // fits clearly worse than the best so far is rejected and the
        // refinement stops (the filter went astray with it).
        let kept = iterations.iter().rfind(|r| !r.rejected);
        match fitted {
            Some(fitted) if !kept.is_some_and(|b| worse(&report, b)) => {
                noise = next_noise(
                    set,
                    first,
                    report.residual_dimensional,
                    (cfg.noise_floor, cfg.torque_turn),
                );
                if cfg.cross_fit && it + 1 < cfg.iterations {
                    own = cross_fit::per_take_models(
                        &fitted,
                        &net,
                        set.takes.len(),
                        &FitContext::of_set(set),
                        &cfg.lsq,
                        report.smoothing,
                    );
                }
                model = fitted.clone();
                best = Some((fitted, smoothed, frames));
                iterations.push(report);
            }
            _ => {
                report.rejected = true;
                iterations.push(report);
                break;
            }
        }
    }
    let Some((mut model, reconstruction, samples)) = best else {
        return Err(Error::Data("no iteration produced a model".into()));
    };
    let mut torque_frames = TorqueFrames::Stable;
    if cfg.method == Method::Lsq {
        model = final_torque(&model, &base, &samples, set, cfg)?;
        torque_frames = TorqueFrames::NoThrust;
    }
    fill_provenance(&mut model, set, cfg, &iterations, &samples)?;
    Ok(FitOutcome {
        model,
        iterations,
        reconstruction,
        samples,
        torque_frames,
        take_scales: takes.scales,
        left_out: takes.left_out,
        takes: set.takes.iter().map(|t| t.name.clone()).collect(),
    })
}

/// `model` with its torque part refitted on the kept iteration's frames
/// (net of the named effects) with every frame that passes the no-thrust
/// test ([`refit_final_torque`]; the reconstruction is unchanged).
fn final_torque(
    model: &Coefficients<f64>,
    base: &Coefficients<f64>,
    samples: &[Sample],
    set: &RecordingSet,
    cfg: &FitConfig,
) -> Result<Coefficients<f64>> {
    let net = process_effects::net_of_effects(samples, base, set.world.air_density);
    refit_final_torque(model, &net, &FitContext::of_set(set), &cfg.lsq_at_degree())
}

/// What the first reconstruction decided about the takes
/// (`reconstruct::first`): each one's air-wrench scale, those left out.
#[derive(Default)]
struct Takes {
    scales: Vec<Option<f64>>,
    left_out: Vec<LeftOut>,
}

/// The first, model-free reconstruction with its per-take safety net; an
/// error when fewer than `MIN_TAKES` takes remain.
fn first_reconstruction(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    filter: &FilterConfig,
    takes: &mut Takes,
    progress: &dyn Progress,
) -> Result<Vec<Smoothed>> {
    let out = first(set, model, noise, filter, progress)?;
    let kept = out.scales.iter().filter(|s| s.is_some()).count();
    let min = crate::fit::select::MIN_TAKES.min(set.takes.len());
    if kept < min {
        return Err(diagnose::too_few_takes(
            kept,
            set.takes.len(),
            min,
            out.left_out
                .iter()
                .map(|l| (l.take.as_str(), l.why.as_str())),
        ));
    }
    takes.scales = out.scales;
    takes.left_out = out.left_out;
    Ok(out.smoothed)
}

/// An iteration's reconstruction, its frames, their counts and the takes
/// that kept the previous pose branch ([`weighed_frames`]).
type Weighed = (Vec<Smoothed>, Vec<Sample>, ForceStats, Vec<usize>);

/// Iteration `it`'s reconstruction with `model` and `noise` (after the
/// first, checked against `previous`, the last kept iteration's, see
/// [`carry`]; with the takes that kept its pose branch), and
/// its frames (eqs. 9-10) weighed by what the markers alone say about them: the
/// first, model-free reconstruction's covariances (kept in `markers_only`,
/// see [`with_markers_only_covariances`]) plus the velocity's spread
/// through the model's slope.
fn weighed_frames(
    set: &RecordingSet,
    models: &TakeModels<'_>,
    noise: ProcessNoise,
    cfg: &FitConfig,
    it: usize,
    (markers_only, takes, previous): (&mut Option<Vec<Smoothed>>, &mut Takes, &[Smoothed]),
    progress: &dyn Progress,
) -> Result<Weighed> {
    progress.stage(
        &format!("iteration {}/{}: filter + smoother", it + 1, cfg.iterations),
        set.takes.len(),
    );
    let mut filter = cfg.filter.clone();
    if it.saturating_add(cfg.relinearised_iterations) < cfg.iterations {
        filter.relinearise = 0;
    }
    let (smoothed, kept_previous) = if markers_only.is_none() {
        let first = first_reconstruction(set, models.shared, noise, &filter, takes, progress)?;
        (first, Vec::new())
    } else {
        let carried = (&mut takes.scales, previous);
        carry::reconstruct(set, models, noise, &filter, carried, progress)?
    };
    let mut fstats = ForceStats::default();
    let weighed = markers_only
        .as_deref()
        .map(|first| with_markers_only_covariances(&smoothed, first));
    let source = weighed.as_deref().unwrap_or(&smoothed);
    let mut frames = samples_in_wind(set, source, &cfg.filter.wind, &mut fstats);
    // With a model, the velocity's error spreads the frame's residual
    // too (nothing in the first iteration: the zero model has no slope).
    add_velocity_spread(&mut frames, source, models.shared, set.world.air_density);
    if markers_only.is_none() {
        *markers_only = Some(smoothed.clone());
    }
    if !frames.iter().any(|s| s.use_force) {
        return Err(Error::Data(
            "no usable frames: every frame failed the stability tests".into(),
        ));
    }
    Ok((smoothed, frames, fstats, kept_previous))
}

/// Largest non-dimensional residual of a usable first iteration: 100
/// times eq. (5)-(6)'s dynamic-pressure scale is no reconstruction.
pub const DIVERGED_RESIDUAL: f64 = 100.0;

/// Why the first iteration's reconstruction is unusable (there is no
/// earlier model to fall back to), naming the take the filter restarted
/// most in; `None` when it is usable.
fn diverged(report: &IterationReport, set: &RecordingSet, smoothed: &[Smoothed]) -> Option<String> {
    let (f, t) = report.residual;
    let bad = |r: f64| !r.is_finite() || r > DIVERGED_RESIDUAL;
    if !bad(f) && !bad(t) {
        return None;
    }
    let worst = set
        .takes
        .iter()
        .zip(smoothed)
        .max_by_key(|(_, s)| s.stats.restarts)
        .map(|(take, s)| {
            format!(
                "; most restarts in take {} ({})",
                take.name, s.stats.restarts
            )
        })
        .unwrap_or_default();
    Some(format!(
        "the reconstruction diverged in the first iteration: residual force {f:.3e}, torque \
         {t:.3e} (non-dimensional, limit {DIVERGED_RESIDUAL}), {} filter restarts{worst}. \
         Check the camera calibration, marker positions and pixel noise in recording.toml; \
         forces many times the object's weight (e.g. a strong synthetic effect) also do this",
        report.filter.restarts
    ))
}

/// The noise the filter should use after `outcome` (for a final
/// reconstruction): the last kept iteration's, with the unexplained
/// wrench's correlation time chosen by maximum innovation likelihood
/// ([`crate::reconstruct::schedule::most_likely_bias_time`]; the refinement iterations keep
/// `BIAS_TIME_SCALES``·τ`, whose slow decay bounds the depth drift that
/// would otherwise pass into the fitted forces).
pub fn final_noise(
    set: &RecordingSet,
    outcome: &FitOutcome,
    cfg: &FitConfig,
) -> Result<ProcessNoise> {
    Ok(final_noise_scored(set, outcome, cfg)?.0)
}

/// [`final_noise`] with the markers' innovation log-likelihood at it
/// ([`most_likely_bias_time_scored`]; `None` when no likelihood was
/// computed on the way).
pub fn final_noise_scored(
    set: &RecordingSet,
    outcome: &FitOutcome,
    cfg: &FitConfig,
) -> Result<(ProcessNoise, Option<f64>)> {
    let first = initial_noise(set);
    let noise = outcome
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .map(|r| {
            next_noise(
                set,
                first,
                r.residual_dimensional,
                (cfg.noise_floor, cfg.torque_turn),
            )
        })
        .unwrap_or(first);
    most_likely_bias_time_scored(set, &outcome.model, noise, &cfg.filter)
}
