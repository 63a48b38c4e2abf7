//! The acquisition pipeline with iterative refinement (§6): reconstruct
//! every take with the current model, reconstruct forces, fit, repeat.

use crate::fit::coverage;
use crate::error::{Error, Result};
use crate::reconstruct::filter::{Filter, FilterConfig, FilterStats, Smoothed};
use crate::fit::extensions::ExtensionTest;
use crate::fit::lsq::{FitContext, FitSmoothing, LsqConfig};
use crate::reconstruct::forces::{self, ForceStats, Sample};
use crate::fit::model::{with_raw, zero_model};
use crate::reconstruct::process::Process;
use crate::input::recording::RecordingSet;
use crate::fit::residuals::{frame_residuals, rms_dimensional, summary};
use crate::input::tracks::Observation;
use nalgebra::Vector3;
use omniad_core::{Coefficients, Environment, RigidBody, State};
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
    /// Refinement iterations (fit count; §6 uses 3).
    pub iterations: usize,
    /// Least-squares settings (degree is taken from `degree`).
    pub lsq: LsqConfig,
    /// Filter settings (pixel noise is taken from the camera).
    pub filter: FilterConfig,
    /// Lower bound of the refined process noise, as a fraction of the
    /// no-model noise of [`initial_noise`] (default 0.02).
    pub noise_floor: f64,
    /// How many of the last iterations reconstruct with the filter's
    /// relinearised sweeps (`filter.relinearise`; the others with none).
    /// Default: all. (With the old noise floor of 0.1, relinearised early
    /// iterations were seen to lead the mirror-branch test astray; with
    /// the floor at 0.02 all-relinearised runs were better on every set
    /// measured, see BENCHMARKS.md.)
    pub relinearised_iterations: usize,
}

impl Default for FitConfig {
    fn default() -> Self {
        Self {
            degree: 8,
            method: Method::Lsq,
            iterations: 3,
            lsq: LsqConfig::default(),
            filter: FilterConfig::default(),
            noise_floor: 0.02,
            relinearised_iterations: usize::MAX,
        }
    }
}

/// Progress reporting (the CLI draws bars; tests ignore it). Takes are
/// reconstructed on several threads, which tick the same reporter.
pub trait Progress: Sync {
    /// A stage with `total` steps starts.
    fn stage(&self, name: &str, total: usize);
    /// One step of the current stage is done.
    fn tick(&self);
}

/// No progress reporting.
pub struct Silent;

impl Progress for Silent {
    fn stage(&self, _: &str, _: usize) {}
    fn tick(&self) {}
}

/// Process noise of the filter (1 sigma per axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProcessNoise {
    /// White acceleration per step, m/s².
    pub accel: f64,
    /// White angular acceleration per step, rad/s².
    pub angular_accel: f64,
    /// Random walk of the unexplained force, N/√s.
    pub force_walk: f64,
    /// Random walk of the unexplained torque, N m/√s.
    pub torque_walk: f64,
    /// Correlation time of the unexplained wrench, s (`f64::INFINITY`: a
    /// random walk; see [`Process::bias_time`]).
    pub bias_time: f64,
}

impl ProcessNoise {
    /// The same unexplained wrench with correlation time `bias_time` (s)
    /// and the same stationary RMS `walk·sqrt(τ_b/2)`: the walks scale by
    /// `sqrt(τ_b/bias_time)`. Both times must be finite and positive.
    pub fn with_bias_time(self, bias_time: f64) -> Self {
        let k = (self.bias_time / bias_time).sqrt();
        Self {
            force_walk: self.force_walk * k,
            torque_walk: self.torque_walk * k,
            bias_time,
            ..self
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
}

/// The environment of a set (no wind).
pub fn environment(set: &RecordingSet) -> Environment<f64> {
    Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind: Vector3::zeros(),
    }
}

/// Scales of the object: a gravity-sized force `M|g|`, the torque of that
/// force at `L/2`, and the time `τ = sqrt(L/|g|)` to fall through one
/// reference length from rest (the time scale of the air's wrench changing).
fn scales(set: &RecordingSet) -> (f64, f64, f64) {
    let g = set.world.gravity.norm().max(1.0);
    let l = set.object.reference_length;
    let force = set.object.mass * g;
    (force, 0.5 * force * l, (l / g).sqrt())
}

/// Correlation time of the unexplained wrench once a model is fitted, in
/// units of the object's time scale `τ` (see `next_noise`): 2 keeps the
/// driving walk `RMS/sqrt(τ)` of a random walk, so only the decay is new.
pub const BIAS_TIME_SCALES: f64 = 2.0;

/// Process noise with no aerodynamic model: the unexplained wrench may
/// change by its full scale over `τ` (a random walk: the air's wrench has a
/// non-zero mean the filter must find); white noise of 10 % of the scales.
pub fn initial_noise(set: &RecordingSet) -> ProcessNoise {
    let (force, torque, tau) = scales(set);
    let i_max = set.object.inertia.symmetric_eigen().eigenvalues.max();
    ProcessNoise {
        accel: 0.1 * force / set.object.mass,
        angular_accel: 0.1 * torque / i_max,
        force_walk: force / tau.sqrt(),
        torque_walk: torque / tau.sqrt(),
        bias_time: f64::INFINITY,
    }
}

fn initial_state(
    epochs: &[crate::input::tracks::Epoch],
    guess: Option<(Vector3<f64>, nalgebra::UnitQuaternion<f64>)>,
) -> Result<State<f64>> {
    if let Some((p, q)) = guess {
        return Ok(State {
            position: p,
            orientation: q,
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
        });
    }
    match (epochs.first(), epochs.get(1)) {
        (Some(a), Some(b)) => match (&a.observation, &b.observation) {
            (Observation::Pose(y0, q0), Observation::Pose(y1, q1)) => {
                let dt = b.t - a.t;
                let w = (q0.inverse() * q1).scaled_axis() / dt;
                Ok(State {
                    position: *y0,
                    orientation: *q0,
                    velocity: (y1 - y0) / dt,
                    angular_velocity: w,
                })
            }
            _ => Err(Error::Data("a marker take needs an initial guess".into())),
        },
        _ => Err(Error::Data("a take needs at least two epochs".into())),
    }
}

/// The rough initial state of a take, errors naming it.
fn take_start(take: &crate::input::recording::Take) -> Result<State<f64>> {
    initial_state(&take.epochs, take.initial)
        .map_err(|e| Error::Data(format!("take {}: {e}", take.name)))
}

/// The filter of a set with `model` and `noise`.
fn filter<'a>(
    set: &'a RecordingSet,
    model: &'a Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<Filter<'a>> {
    let body = RigidBody::new(set.object.mass, set.object.inertia)
        .map_err(|e| Error::Data(format!("object: {e}")))?;
    let mut config = cfg.clone();
    if let Some(c) = &set.camera {
        config.pixel_noise = c.pixel_noise;
    }
    let process = Process {
        body,
        environment: environment(set),
        model,
        accel_noise: noise.accel,
        angular_accel_noise: noise.angular_accel,
        force_walk: noise.force_walk,
        torque_walk: noise.torque_walk,
        bias_time: noise.bias_time,
    };
    let (force, torque, _) = scales(set);
    config.initial_bias = [force, torque];
    Ok(Filter {
        process,
        object: &set.object,
        camera: set.camera.as_ref(),
        config,
    })
}

/// Smooths every take with `model` and `noise` from the takes' rough
/// initial guesses.
pub fn reconstruct(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    progress: &dyn Progress,
) -> Result<Vec<Smoothed>> {
    refine(set, model, noise, cfg, &[], progress)
}

/// Smooths every take with `model` and `noise`, relinearising about the
/// take's trajectory in `previous` (one per take, from an earlier model;
/// see [`Filter::refine`]); takes without one are reconstructed from their
/// rough initial guess.
pub fn refine(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    previous: &[Smoothed],
    progress: &dyn Progress,
) -> Result<Vec<Smoothed>> {
    let filter = filter(set, model, noise, cfg)?;
    crate::parallel::map(&set.takes, |i, take| {
        let initial = take_start(take)?;
        let smoothed = match previous.get(i) {
            Some(p) => filter.refine(&take.epochs, initial, p),
            None => filter.run(&take.epochs, initial),
        };
        progress.tick();
        Ok(smoothed)
    })
    .into_iter()
    .collect()
}

/// The forward filter's innovation log-likelihood of every take's
/// markers with `model` and `noise` ([`Filter::log_likelihood`]), summed.
pub fn log_likelihood(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<f64> {
    let filter = filter(set, model, noise, cfg)?;
    let per: Vec<Result<f64>> = crate::parallel::map(&set.takes, |_, take| {
        Ok(filter.log_likelihood(&take.epochs, take_start(take)?))
    });
    // Summed in take order, so the total does not depend on the threads.
    per.into_iter().sum()
}

/// Correlation times tried by [`most_likely_bias_time`], as fractions of
/// the default `BIAS_TIME_SCALES·τ`, in steps of 4 down to a quarter of a
/// frame at 60 fps for a 0.58 m object (the unexplained wrench is then
/// white).
pub const BIAS_TIME_FRACTIONS: [f64; 5] = [1.0, 0.25, 0.0625, 0.015625, 0.00390625];

/// `noise` with the correlation time of its unexplained wrench chosen by
/// maximum innovation likelihood of the markers ([`log_likelihood`]) over
/// [`BIAS_TIME_FRACTIONS`], the wrench's stationary RMS kept. `noise` itself
/// when it has no finite correlation time (no model yet).
pub fn most_likely_bias_time(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<ProcessNoise> {
    if !noise.bias_time.is_finite() || noise.bias_time <= 0.0 {
        return Ok(noise);
    }
    let mut best = (f64::NEG_INFINITY, noise);
    for fraction in BIAS_TIME_FRACTIONS {
        let candidate = noise.with_bias_time(noise.bias_time * fraction);
        let ll = log_likelihood(set, model, candidate, cfg)?;
        if ll > best.0 {
            best = (ll, candidate);
        }
    }
    Ok(best.1)
}

/// Eqs. (9)-(10) on every take.
pub fn samples(set: &RecordingSet, smoothed: &[Smoothed], stats: &mut ForceStats) -> Vec<Sample> {
    let mut out = Vec::new();
    for (i, (take, s)) in set.takes.iter().zip(smoothed).enumerate() {
        out.extend(forces::reconstruct(
            i,
            take.kind,
            s,
            &set.object,
            &set.world.gravity,
            stats,
        ));
    }
    out
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
    let ctx = FitContext {
        air_density: set.world.air_density,
        reference_length: set.object.reference_length,
        pole: set.object.pole,
    };
    let degree = usize::from(cfg.degree);
    let raw = match cfg.method {
        Method::Lsq => crate::fit::lsq::fit(
            samples,
            &ctx,
            &LsqConfig {
                degree,
                ..cfg.lsq.clone()
            },
        ),
        Method::Paper => crate::fit::paper::fit(samples, &ctx, degree),
    };
    let details = FitDetails {
        extension_test: raw.extension_test,
        smoothing: raw.smoothing,
    };
    Ok((with_raw(base, &raw)?, details))
}

/// The next iteration's process noise: with a fitted model the unexplained
/// wrench is the fit's residual, a zero-mean first-order Gauss-Markov
/// process (not a random walk) with correlation time [`BIAS_TIME_SCALES`]`·τ`
/// and stationary RMS the fit's RMS residual wrench; its driving walk
/// (`RMS·sqrt(2/τ_b)` = `RMS/sqrt(τ)`) is clamped between `floor` and 1
/// times the no-model walks. A random walk lets a slowly drifting depth
/// error (the poorly observed direction of §5's marker updates) pass as
/// unexplained force; the decay bounds that drift. The white noise is kept.
fn next_noise(
    set: &RecordingSet,
    first: ProcessNoise,
    rms: (f64, f64),
    floor: f64,
) -> ProcessNoise {
    let (_, _, tau) = scales(set);
    let bias_time = BIAS_TIME_SCALES * tau;
    let k = (2.0 / bias_time).sqrt();
    ProcessNoise {
        force_walk: (rms.0 * k).clamp(floor * first.force_walk, first.force_walk),
        torque_walk: (rms.1 * k).clamp(floor * first.torque_walk, first.torque_walk),
        bias_time,
        ..first
    }
}

/// The whole pipeline: `cfg.iterations` rounds of reconstruct-and-fit.
pub fn fit(set: &RecordingSet, cfg: &FitConfig, progress: &dyn Progress) -> Result<FitOutcome> {
    if cfg.iterations == 0 {
        return Err(Error::Data("at least one iteration is needed".into()));
    }
    let base = zero_model(&set.object, cfg.degree)?;
    let mut model = base.clone();
    let first = initial_noise(set);
    let mut noise = first;
    let mut iterations: Vec<IterationReport> = Vec::with_capacity(cfg.iterations);
    let mut best: Option<(Coefficients<f64>, Vec<Smoothed>, Vec<Sample>)> = None;
    // The first, model-free reconstruction (see
    // `with_markers_only_covariances`).
    let mut markers_only: Option<Vec<Smoothed>> = None;
    for it in 0..cfg.iterations {
        let start = Instant::now();
        progress.stage(
            &format!("iteration {}/{}: filter + smoother", it + 1, cfg.iterations),
            set.takes.len(),
        );
        let mut filter = cfg.filter.clone();
        if it.saturating_add(cfg.relinearised_iterations) < cfg.iterations {
            filter.relinearise = 0;
        }
        let smoothed = reconstruct(set, &model, noise, &filter, progress)?;
        let mut fstats = ForceStats::default();
        // Frames are weighed by what the markers alone say about them.
        let weighed = markers_only
            .as_deref()
            .map(|first| with_markers_only_covariances(&smoothed, first));
        let source = weighed.as_deref().unwrap_or(&smoothed);
        let mut frames = samples(set, source, &mut fstats);
        // With a model, the velocity's error spreads the frame's residual
        // too (nothing in the first iteration: the zero model has no slope).
        add_velocity_spread(&mut frames, source, &model, set.world.air_density);
        if markers_only.is_none() {
            markers_only = Some(smoothed.clone());
        }
        if !frames.iter().any(|s| s.use_force) {
            return Err(Error::Data(
                "no usable frames: every frame failed the stability tests".into(),
            ));
        }
        progress.stage(&format!("iteration {}/{}: fit", it + 1, cfg.iterations), 1);
        // A later iteration whose reconstruction diverged can give a
        // non-finite fit: it is rejected like a worse one (below).
        // Extensions refine a fitted model: the first iteration's forces
        // come from a reconstruction with no model (§6, A_0 = 0), whose
        // errors correlate with anything, so it fits the paper's model only.
        let mut fit_cfg = cfg.clone();
        fit_cfg.lsq.extensions &= it > 0;
        let (fitted, details) = match fit_samples_tested(&base, &frames, set, &fit_cfg) {
            Ok((m, d)) => (Some(m), d),
            Err(e) if iterations.is_empty() => return Err(e),
            Err(_) => (None, FitDetails::default()),
        };
        progress.tick();
        let nan = (f64::NAN, f64::NAN);
        let res = fitted
            .as_ref()
            .map(|m| frame_residuals(m, &frames, set.world.air_density));
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
                noise = next_noise(set, first, report.residual_dimensional, cfg.noise_floor);
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
    fill_provenance(&mut model, set, cfg, &iterations, &samples)?;
    Ok(FitOutcome {
        model,
        iterations,
        reconstruction,
        samples,
    })
}

/// `smoothed` with the covariances of `first`, the same takes smoothed with
/// no model (§6's first iteration): that of eq. (9)'s velocity difference
/// (world frame) and that of the attitude and velocity, which
/// [`Smoothed::body_velocity_cov`] turns into the body velocity's about
/// `smoothed`'s own states. A take whose epochs differ in number keeps
/// its own.
///
/// Why: with a model, the smoother's posterior is tight wherever the
/// model rather than the markers fixed the state, above all the velocity
/// along the camera's line of sight, which the markers show only through
/// their spread. Those frames repeat the model being refined; weighed by
/// that posterior they counted most, and the refinement confirmed its own
/// model (through the camera's tilt the line-of-sight velocity sets |V|).
/// Weighed by what the markers alone say, the refit can move away from it.
fn with_markers_only_covariances(smoothed: &[Smoothed], first: &[Smoothed]) -> Vec<Smoothed> {
    smoothed
        .iter()
        .zip(first)
        .map(|(s, f)| {
            let mut out = s.clone();
            if f.velocity_difference_cov.len() == s.states.len()
                && f.attitude_velocity_cov.len() == s.states.len()
            {
                out.velocity_difference_cov
                    .clone_from(&f.velocity_difference_cov);
                out.attitude_velocity_cov
                    .clone_from(&f.attitude_velocity_cov);
            }
            out
        })
        .collect()
}

/// Adds to each frame's force covariance the spread of the model's force
/// that the uncertainty of its body-frame velocity causes, `J Σ_V Jᵀ`
/// with `J = ∂F_model/∂V` (central differences) and `Σ_V` the smoother's
/// ([`Smoothed::body_velocity_cov`]): the fit regresses the force on the
/// velocity, whose error makes a residual of its own (errors in
/// variables; the effective-variance method).
fn add_velocity_spread(
    frames: &mut [Sample],
    smoothed: &[Smoothed],
    model: &Coefficients<f64>,
    air_density: f64,
) {
    for s in frames {
        let Some(cov) = smoothed
            .get(s.take)
            .and_then(|x| x.body_velocity_cov(s.index))
        else {
            continue;
        };
        let speed = s.velocity.norm();
        if speed.is_nan() || speed <= 0.0 {
            continue;
        }
        let h = 1e-4 * speed;
        let mut j = nalgebra::Matrix3::zeros();
        for c in 0..3 {
            let mut e = Vector3::zeros();
            e[c] = h;
            let f = |v: Vector3<f64>| model.wrench(&v, &s.angular_velocity, air_density).force;
            j.set_column(c, &((f(s.velocity + e) - f(s.velocity - e)) / (2.0 * h)));
        }
        let spread = j * cov * j.transpose();
        if spread.iter().all(|v| v.is_finite()) {
            s.force_cov += spread;
        }
    }
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

fn total_stats(smoothed: &[Smoothed]) -> FilterStats {
    smoothed
        .iter()
        .fold(FilterStats::default(), |a, s| FilterStats {
            used: a.used + s.stats.used,
            gated: a.gated + s.stats.gated,
            empty_frames: a.empty_frames + s.stats.empty_frames,
            unprojectable: a.unprojectable + s.stats.unprojectable,
            restarts: a.restarts + s.stats.restarts,
            mirror_switches: a.mirror_switches + s.stats.mirror_switches,
        })
}

/// The noise the filter should use after `outcome` (for a final
/// reconstruction): the last kept iteration's, with the unexplained
/// wrench's correlation time chosen by maximum innovation likelihood
/// ([`most_likely_bias_time`]; the refinement iterations keep
/// [`BIAS_TIME_SCALES`]`·τ`, whose slow decay bounds the depth drift that
/// would otherwise pass into the fitted forces).
pub fn final_noise(
    set: &RecordingSet,
    outcome: &FitOutcome,
    cfg: &FitConfig,
) -> Result<ProcessNoise> {
    let first = initial_noise(set);
    let noise = outcome
        .iterations
        .iter()
        .rfind(|r| !r.rejected)
        .map(|r| next_noise(set, first, r.residual_dimensional, cfg.noise_floor))
        .unwrap_or(first);
    most_likely_bias_time(set, &outcome.model, noise, &cfg.filter)
}

fn truncated<const N: usize>(s: &str) -> heapless::String<N> {
    let mut out = heapless::String::new();
    for c in s.chars() {
        if out.push(c).is_err() {
            break;
        }
    }
    out
}

fn fill_provenance(
    model: &mut Coefficients<f64>,
    set: &RecordingSet,
    cfg: &FitConfig,
    its: &[IterationReport],
    samples: &[Sample],
) -> Result<()> {
    let p = &mut model.provenance;
    p.method = truncated(match cfg.method {
        Method::Lsq => "fit-lsq",
        Method::Paper => "fit-paper",
    });
    p.source = truncated(&set.root.display().to_string());
    let used = samples.iter().filter(|s| s.use_force).count();
    p.frames_used = u32::try_from(used).unwrap_or(u32::MAX);
    p.frames_dropped = u32::try_from(samples.len() - used).unwrap_or(u32::MAX);
    for r in its
        .iter()
        .rev()
        .take(omniad_core::coefficients::MAX_ITERATIONS)
        .rev()
    {
        let _ = p.force_residuals.push(r.residual.0);
        let _ = p.torque_residuals.push(r.residual.1);
    }
    let dirs = samples
        .iter()
        .filter(|s| s.use_force && s.velocity.norm() > 0.0)
        .map(|s| s.velocity.normalize());
    for c in coverage::histogram(&set.object.pole, dirs) {
        p.coverage
            .push(c)
            .map_err(|_| Error::Data("coverage grid size".into()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::recording::TakeKind;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use nalgebra::Matrix3;

    fn frame(velocity: Vector3<f64>) -> Sample {
        Sample {
            take: 0,
            index: 1,
            t: 0.0,
            kind: TakeKind::Drop,
            velocity,
            angular_velocity: Vector3::new(1.0, -2.0, 0.5),
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            gravity_body: Vector3::new(0.0, 0.0, -9.81),
            force_cov: Matrix3::identity() * 1e-4,
            use_force: true,
            use_torque: true,
        }
    }

    #[test]
    fn velocity_spread_is_the_models_slope_times_the_velocity_covariance() {
        let model = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let cov = Matrix3::new(4e-4, 1e-4, 0.0, 1e-4, 9e-4, -2e-4, 0.0, -2e-4, 1e-3);
        // At rest and unrotated, the body velocity's covariance is the
        // world velocity's block.
        let mut block = nalgebra::Matrix6::zeros();
        block.fixed_view_mut::<3, 3>(3, 3).copy_from(&cov);
        let rest = State {
            position: Vector3::zeros(),
            orientation: nalgebra::UnitQuaternion::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
        };
        let smoothed = vec![Smoothed {
            times: vec![0.0; 3],
            states: vec![rest; 3],
            cuts: Vec::new(),
            velocity_difference_cov: Vec::new(),
            attitude_velocity_cov: vec![
                nalgebra::Matrix6::zeros(),
                block,
                nalgebra::Matrix6::zeros(),
            ],
            stats: FilterStats::default(),
        }];
        let v = Vector3::new(1.0, -3.0, 2.0);
        let mut frames = vec![frame(v)];
        add_velocity_spread(&mut frames, &smoothed, &model, 1.2);
        // The slope by a coarser difference than the function's own.
        let f = |v: Vector3<f64>| model.wrench(&v, &Vector3::new(1.0, -2.0, 0.5), 1.2).force;
        let h = 1e-3;
        let j = Matrix3::from_columns(&[0, 1, 2].map(|c| {
            let e = Vector3::ith(c, h);
            (f(v + e) - f(v - e)) / (2.0 * h)
        }));
        let expected = Matrix3::identity() * 1e-4 + j * cov * j.transpose();
        let got = frames.first().map(|s| s.force_cov).unwrap_or_default();
        assert!(
            (got - expected).norm() < 1e-4 * expected.norm(),
            "{got} vs {expected}"
        );
        assert!(j.norm() > 0.0);
        // The zero model has no slope; a frame without a covariance keeps
        // its own.
        let zero = Coefficients::zeros(6, model.pole(), model.reference_length()).expect("zero");
        let mut frames = vec![frame(v)];
        add_velocity_spread(&mut frames, &smoothed, &zero, 1.2);
        assert_eq!(
            frames.first().map(|s| s.force_cov),
            Some(Matrix3::identity() * 1e-4)
        );
        let mut frames = vec![Sample {
            index: 7,
            ..frame(v)
        }];
        add_velocity_spread(&mut frames, &smoothed, &model, 1.2);
        assert_eq!(
            frames.first().map(|s| s.force_cov),
            Some(Matrix3::identity() * 1e-4)
        );
    }

    fn take(states: Vec<State<f64>>, scale: f64) -> Smoothed {
        let n = states.len();
        Smoothed {
            times: (0..n).map(|k| k as f64 / 60.0).collect(),
            states,
            cuts: vec![false; n],
            velocity_difference_cov: vec![Matrix3::identity() * scale; n],
            attitude_velocity_cov: (0..n)
                .map(|k| {
                    let a = nalgebra::Matrix6::<f64>::from_fn(|i, j| {
                        scale * (1.0 + (i * 6 + j + k) as f64 * 0.01)
                    });
                    a * a.transpose()
                })
                .collect(),
            stats: FilterStats::default(),
        }
    }

    #[test]
    fn markers_only_covariances_are_the_first_runs_about_the_current_states() {
        let state = |k: usize| State {
            position: Vector3::zeros(),
            orientation: nalgebra::UnitQuaternion::from_euler_angles(0.3 * k as f64, -0.2, 1.0),
            velocity: Vector3::new(0.5, -0.2 * k as f64, -2.0),
            angular_velocity: Vector3::zeros(),
        };
        let current = take((0..3).map(state).collect(), 1e-4);
        // The model-free run sat elsewhere (a mirror branch, say).
        let other = |k: usize| State {
            orientation: nalgebra::UnitQuaternion::from_euler_angles(1.0, 0.4, -0.3 * k as f64),
            velocity: Vector3::new(-1.0, 0.0, -1.5),
            ..state(k)
        };
        let first = take((0..3).map(other).collect(), 3e-3);
        let got = with_markers_only_covariances(
            std::slice::from_ref(&current),
            std::slice::from_ref(&first),
        );
        let got = got.first().expect("one take");
        assert_eq!(got.states, current.states);
        assert_eq!(got.velocity_difference_cov, first.velocity_difference_cov);
        assert_eq!(got.attitude_velocity_cov, first.attitude_velocity_cov);
        for k in 0..3 {
            // The body velocity's covariance is about the current state,
            // not the first run's.
            let expected = crate::reconstruct::filter::body_velocity_cov(
                &current.states[k],
                &first.attitude_velocity_cov[k],
            );
            let own = first.body_velocity_cov(k).expect("first run's");
            assert_eq!(got.body_velocity_cov(k), Some(expected));
            assert!((expected - own).norm() > 1e-6);
        }
        // A take whose epochs differ in number keeps its own covariances.
        let short = take((0..2).map(other).collect(), 3e-3);
        let kept = with_markers_only_covariances(std::slice::from_ref(&current), &[short]);
        assert_eq!(kept.first(), Some(&current));
    }
}
