//! Reconstructing a whole set: every take filtered and smoothed with a
//! model (on all cores, results in take order), and eqs. (9)-(10) on every
//! take.

use crate::error::{Error, Result};
use crate::input::recording::RecordingSet;
use crate::input::tracks::Observation;
use crate::reconstruct::filter::{Filter, FilterConfig, Smoothed};
use crate::reconstruct::forces::{self, ForceStats, Sample};
use crate::reconstruct::noise::{scales, ProcessNoise};
use crate::reconstruct::process::Process;
use nalgebra::Vector3;
use omniad_core::{Coefficients, Environment, RigidBody, State};

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

/// The environment of a set (no wind).
pub fn environment(set: &RecordingSet) -> Environment<f64> {
    Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind: Vector3::zeros(),
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
pub(crate) fn take_start(take: &crate::input::recording::Take) -> Result<State<f64>> {
    initial_state(&take.epochs, take.initial)
        .map_err(|e| Error::Data(format!("take {}: {e}", take.name)))
}

/// The filter of a set with `model` and `noise`.
pub(crate) fn filter<'a>(
    set: &'a RecordingSet,
    model: &'a Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<Filter<'a>> {
    scaled_filter(set, model, noise, cfg, 1.0)
}

/// [`filter`] for a take whose air wrench is `scale` times the object's
/// scales (see [`ProcessNoise::scaled`]): the noise and the unexplained
/// wrench's prior are `scale` times larger.
fn scaled_filter<'a>(
    set: &'a RecordingSet,
    model: &'a Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    scale: f64,
) -> Result<Filter<'a>> {
    let noise = noise.scaled(scale);
    let body = RigidBody::new(set.object.mass, set.object.inertia)
        .map_err(|e| Error::Data(format!("object: {e}")))?;
    let mut config = cfg.clone();
    if let Some(c) = &set.camera {
        config.pixel_noise = c.pixel_noise;
    }
    let process = Process {
        body,
        environment: Environment {
            wind: config.wind,
            ..environment(set)
        },
        model,
        accel_noise: noise.accel,
        angular_accel_noise: noise.angular_accel,
        force_walk: noise.force_walk,
        torque_walk: noise.torque_walk,
        bias_time: noise.bias_time,
        torque_turn: noise.torque_turn,
    };
    let (force, torque, _) = scales(set);
    config.initial_bias = [force * scale, torque * scale];
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
    refine_takes(
        set,
        &TakeModels::shared(model),
        noise,
        cfg,
        previous,
        &[],
        progress,
    )
}

/// The model each take is reconstructed with: its own where given (the
/// refinement's cross-fitted models, `pipeline::cross_fit`), else the
/// shared one.
#[derive(Clone, Copy)]
pub struct TakeModels<'a> {
    /// The model of every take without its own.
    pub shared: &'a Coefficients<f64>,
    /// Per take (in the set's order); may be empty or shorter.
    pub own: &'a [Coefficients<f64>],
}

impl<'a> TakeModels<'a> {
    /// `model` for every take.
    pub fn shared(model: &'a Coefficients<f64>) -> Self {
        Self {
            shared: model,
            own: &[],
        }
    }

    /// Take `i`'s model.
    pub fn of(&self, i: usize) -> &'a Coefficients<f64> {
        self.own.get(i).unwrap_or(self.shared)
    }
}

/// Per take: the factor on its unexplained wrench's noise and prior (see
/// [`scaled_filter`]; the first reconstruction chooses it,
/// `reconstruct::first`), or `None` for a take left out (its
/// reconstruction is empty). Takes beyond the slice: 1.
pub type TakeScales = [Option<f64>];

/// [`refine`] with a scale per take ([`TakeScales`]).
pub fn refine_takes(
    set: &RecordingSet,
    models: &TakeModels<'_>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
    previous: &[Smoothed],
    scales: &TakeScales,
    progress: &dyn Progress,
) -> Result<Vec<Smoothed>> {
    crate::parallel::map(&set.takes, |i, take| {
        let Some(scale) = scales.get(i).copied().unwrap_or(Some(1.0)) else {
            progress.tick();
            return Ok(Smoothed::default());
        };
        let filter = scaled_filter(set, models.of(i), noise, cfg, scale)?;
        let initial = take_start(take)?;
        let smoothed = match previous.get(i).filter(|p| !p.states.is_empty()) {
            Some(p) => filter.refine(&take.epochs, initial, p),
            None => filter.run(&take.epochs, initial),
        };
        progress.tick();
        Ok(smoothed)
    })
    .into_iter()
    .collect()
}

/// Eqs. (9)-(10) on every take (no wind).
pub fn samples(set: &RecordingSet, smoothed: &[Smoothed], stats: &mut ForceStats) -> Vec<Sample> {
    samples_in_wind(set, smoothed, &Vector3::zeros(), stats)
}

/// Eqs. (9)-(10) on every take of a recording whose air moved with the
/// steady `wind` (world frame, m/s): the frames' velocities are relative
/// to the air.
pub fn samples_in_wind(
    set: &RecordingSet,
    smoothed: &[Smoothed],
    wind: &Vector3<f64>,
    stats: &mut ForceStats,
) -> Vec<Sample> {
    let mut out = Vec::new();
    for (i, (take, s)) in set.takes.iter().zip(smoothed).enumerate() {
        out.extend(forces::reconstruct(
            i,
            take.kind,
            s,
            &set.object,
            (&set.world.gravity, wind),
            stats,
        ));
    }
    out
}
