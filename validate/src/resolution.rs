//! The paper's Fig. 8: the same set fitted at several SH degrees N, judged
//! on held-out takes against the set's known generating model (synthetic
//! sets only: `truth/` and an object `omniad synth` knows).
//!
//! Every third take (2, 5, 8, ...) is held out; the rest are fitted with
//! the full pipeline ([`omniad_acquire::pipeline::fit`]). On the held-out
//! takes' true states (`truth/<take>.csv`):
//! * force and torque error: `√(Σ|F_fit - F_true|² / Σ|F_true|²)`, the
//!   wrench of eqs. (5)-(6) with damping, body frame, every frame;
//! * trajectory error: the fitted model re-simulated from the take's true
//!   first state (RK4, 1 ms) for [`HORIZON`] s, RMS of the centre of
//!   mass's distance from the true one at the frames, m.

use anyhow::{anyhow, Result};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::input::state_csv::read_states;
use omniad_acquire::pipeline::{self, FitConfig};
use omniad_acquire::reconstruct::run::Silent;
use omniad_acquire::synth::{truth_model, ObjectSpec, SynthObject};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Coefficients, Environment, RigidBody, State};
use serde::Serialize;
use std::time::Instant;

/// The degrees of the paper's Fig. 8 and more.
pub const DEGREES: [u8; 5] = [1, 4, 8, 10, 12];
/// Re-simulation horizon, s.
pub const HORIZON: f64 = 0.5;

/// One degree's result.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Row {
    /// N.
    pub degree: u8,
    /// Wall time of the fit, s.
    pub fit_seconds: f64,
    /// Held-out relative force error.
    pub force_error: f64,
    /// Held-out relative torque error.
    pub torque_error: f64,
    /// Held-out RMS position error over `HORIZON` s, m.
    pub trajectory_error_m: f64,
}

/// The generating model of a synthetic set, from its object's name.
pub fn generating_model(set: &RecordingSet) -> Option<Coefficients<f64>> {
    let object = [
        SynthObject::Plate,
        SynthObject::Box,
        SynthObject::TairaPlate,
    ]
    .into_iter()
    .find(|o| ObjectSpec::of(*o).name == set.object.name)?;
    truth_model(&ObjectSpec::of(object), 8).ok()
}

fn state(r: &[f64; 14]) -> State<f64> {
    State {
        position: Vector3::new(r[1], r[2], r[3]),
        orientation: UnitQuaternion::from_quaternion(Quaternion::new(r[4], r[5], r[6], r[7])),
        velocity: Vector3::new(r[8], r[9], r[10]),
        angular_velocity: Vector3::new(r[11], r[12], r[13]),
    }
}

/// Sums of squares `(Σ|ΔF|², Σ|F|², Σ|ΔT|², Σ|T|², Σ|Δy|², frames)`.
type Sums = [f64; 6];

fn score_take(
    fit: &Coefficients<f64>,
    truth: &Coefficients<f64>,
    body: &RigidBody<f64>,
    env: &Environment<f64>,
    rows: &[[f64; 14]],
    sums: &mut Sums,
) {
    let wrench = |m: &Coefficients<f64>, s: &State<f64>| {
        let g = s.orientation.inverse_transform_vector(&env.gravity);
        m.wrench_in_gravity(
            &s.air_velocity_body(&env.wind),
            &s.angular_velocity,
            &g,
            env.air_density,
        )
    };
    for r in rows {
        let s = state(r);
        let (a, b) = (wrench(fit, &s), wrench(truth, &s));
        sums[0] += (a.force - b.force).norm_squared();
        sums[1] += b.force.norm_squared();
        sums[2] += (a.torque - b.torque).norm_squared();
        sums[3] += b.torque.norm_squared();
    }
    let forces = AirForces {
        model: fit,
        environment: *env,
    };
    let Some(first) = rows.first() else { return };
    let (t0, mut s, mut t) = (first[0], state(first), first[0]);
    let dt = 1e-3;
    for r in rows
        .iter()
        .skip(1)
        .take_while(|r| r[0] - t0 <= HORIZON + 1e-9)
    {
        while t + 0.5 * dt < r[0] {
            s = rk4_step(body, env, &forces, t, dt, &s);
            t += dt;
        }
        sums[4] += (s.position - state(r).position).norm_squared();
        sums[5] += 1.0;
    }
}

/// Fits `set` (folder `dir`) at each of `degrees` on all but the held-out
/// takes and scores them; None when the set has no known generator.
pub fn sweep(
    dir: &std::path::Path,
    set: &RecordingSet,
    degrees: &[u8],
) -> Result<Option<Vec<Row>>> {
    let Some(truth) = generating_model(set) else {
        return Ok(None);
    };
    if !dir.join("truth").is_dir() {
        return Ok(None);
    }
    let held = |i: usize| i % 3 == 1;
    let mut train = set.clone();
    train.takes = set
        .takes
        .iter()
        .enumerate()
        .filter(|(i, _)| !held(*i))
        .map(|(_, t)| t.clone())
        .collect();
    let mut truth_rows = Vec::new();
    for t in set
        .takes
        .iter()
        .enumerate()
        .filter(|(i, _)| held(*i))
        .map(|(_, t)| t)
    {
        truth_rows.push(
            read_states(&dir.join("truth").join(format!("{}.csv", t.name)))
                .map_err(|e| anyhow!("{e}"))?,
        );
    }
    let body = RigidBody::new(set.object.mass, set.object.inertia).map_err(|e| anyhow!("{e}"))?;
    let env = Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind: Vector3::zeros(),
    };
    let mut out = Vec::new();
    for &degree in degrees {
        let start = Instant::now();
        // The paper's figure: force and torque at the one degree N.
        let mut cfg = FitConfig {
            degree,
            ..FitConfig::default()
        };
        cfg.lsq.torque_degree = Some(usize::from(degree));
        let fit = pipeline::fit(&train, &cfg, &Silent)
            .map_err(|e| anyhow!("fit at N = {degree}: {e}"))?;
        let fit_seconds = start.elapsed().as_secs_f64();
        let mut sums = [0.0; 6];
        for rows in &truth_rows {
            score_take(&fit.model, &truth, &body, &env, rows, &mut sums);
        }
        out.push(Row {
            degree,
            fit_seconds,
            force_error: (sums[0] / sums[1]).sqrt(),
            torque_error: (sums[2] / sums[3]).sqrt(),
            trajectory_error_m: (sums[4] / sums[5]).sqrt(),
        });
    }
    Ok(Some(out))
}
