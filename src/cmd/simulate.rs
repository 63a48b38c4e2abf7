//! `omniad simulate FILE --duration S`: one body through air, RK4 (§4.3),
//! under the OmniAD model of FILE or, with `--model`, vacuum or one of the
//! paper's comparison models (Fig. 12) for a `--shape` (the core's
//! [`omniad_core::model::Model`]).

use super::common::read_coefficients;
use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use omniad_acquire::input::state_csv::{self, TimeFormat};
use omniad_core::integrate::rk4_step;
use omniad_core::model::{Model, ModelKind};
use omniad_core::reference::shape::{Shape, ShapeKind};
use omniad_core::{Environment, RigidBody, State};
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `omniad simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// Coefficient file (.omni); needed by `--model omniad` (the default)
    /// and for the body when no `--shape` is given.
    pub file: Option<PathBuf>,
    /// The air model: `omniad` (the file's coefficients), `vacuum`, or a
    /// comparison model of the paper's Fig. 12 for `--shape`: `kirchhoff`
    /// (added mass), `drag-traction`, `simplified`.
    #[arg(long, value_parser = parse_model, default_value = "omniad")]
    pub model: ModelKind,
    /// The body as a uniform shape (`plate` or `box`) of `--size` and
    /// `--mass` instead of the file's mass properties.
    #[arg(long, value_parser = parse_shape)]
    pub shape: Option<ShapeKind>,
    /// Extents of `--shape` x,y,z (body), m; default the paper's plate.
    #[arg(long, value_parser = parse_vec3, default_value = "0.3,0.5,0.02")]
    pub size: Vector3<f64>,
    /// Simulated time, s (at most 1e8 RK4 steps of --dt).
    #[arg(long)]
    pub duration: f64,
    /// Integration step, s.
    #[arg(long, default_value_t = 1e-3)]
    pub dt: f64,
    /// Output sample rate of the trajectory, Hz.
    #[arg(long, default_value_t = 60.0)]
    pub rate: f64,
    /// Initial centre of mass x,y,z (world, z up), m.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,6", allow_hyphen_values = true)]
    pub position: Vector3<f64>,
    /// Initial orientation quaternion w,x,y,z (body -> world; normalised).
    #[arg(long, value_parser = parse_quat, default_value = "1,0,0,0", allow_hyphen_values = true)]
    pub orientation: UnitQuaternion<f64>,
    /// Initial velocity x,y,z (world), m/s (|v| <= 340).
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub velocity: Vector3<f64>,
    /// Initial angular velocity x,y,z (body), rad/s.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub angular_velocity: Vector3<f64>,
    /// Uniform wind x,y,z (world), m/s (|wind| <= 340).
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub wind: Vector3<f64>,
    /// Air density ρ, kg/m³.
    #[arg(long, default_value_t = 1.2)]
    pub air_density: f64,
    /// Mass, kg (default: the file's; with `--shape` 0.048, the paper's plate).
    #[arg(long)]
    pub mass: Option<f64>,
    /// Stop when the centre of mass reaches z = 0.
    #[arg(long)]
    pub stop_at_ground: bool,
    /// Print the trajectory as CSV `t,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz`.
    #[arg(long)]
    pub csv: bool,
    /// Print a JSON summary.
    #[arg(long)]
    pub json: bool,
}

fn parse_numbers<const N: usize>(s: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {N} comma-separated numbers, got {:?}", s));
    }
    let mut out = [0.0; N];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p
            .parse::<f64>()
            .map_err(|_| format!("{p:?} is not a number"))?;
        if !o.is_finite() {
            return Err(format!("{p:?} is not finite"));
        }
    }
    Ok(out)
}

fn parse_model(s: &str) -> Result<ModelKind, String> {
    ModelKind::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = ModelKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown model {s:?} (known: {})", names.join(", "))
    })
}

fn parse_shape(s: &str) -> Result<ShapeKind, String> {
    match s {
        "plate" => Ok(ShapeKind::Plate),
        "box" => Ok(ShapeKind::Box),
        _ => Err(format!("unknown shape {s:?} (known: plate, box)")),
    }
}

fn parse_vec3(s: &str) -> Result<Vector3<f64>, String> {
    parse_numbers::<3>(s).map(Vector3::from)
}

fn parse_quat(s: &str) -> Result<UnitQuaternion<f64>, String> {
    let [w, x, y, z] = parse_numbers::<4>(s)?;
    let q = Quaternion::new(w, x, y, z);
    if q.norm() == 0.0 {
        return Err("quaternion has zero length".into());
    }
    Ok(UnitQuaternion::from_quaternion(q))
}

/// The most RK4 steps one run may take (about two minutes of work at the
/// measured ~1.2 µs a step): `--duration / --dt` beyond it is refused, not
/// left to run for ever.
pub const MAX_STEPS: f64 = 1e8;
/// Speeds (initial velocity, wind) above this are refused, m/s: the model
/// is quasi-steady and incompressible (§4), which fails long before the
/// speed of sound, and larger numbers only overflow |V|² (eq. 5).
pub const MAX_SPEED: f64 = 340.0;
/// Angular speeds above this are refused, rad/s (|Ω|² overflows eq. 6 and
/// no light rigid body survives it).
pub const MAX_ANGULAR_SPEED: f64 = 1e4;
/// Positions beyond this distance from the origin are refused, m.
pub const MAX_DISTANCE: f64 = 1e6;
/// Air densities above this are refused, kg/m³ (water is 1000; the model
/// is for air, §3).
pub const MAX_AIR_DENSITY: f64 = omniad_acquire::input::recording::MAX_AIR_DENSITY;

/// Checks every physical input before any work: finite, in range, the
/// option named in the error.
fn validate(a: &SimulateArgs) -> Result<u64> {
    if !(a.duration.is_finite() && a.duration >= 0.0) {
        bail!("--duration must be a finite non-negative number of seconds");
    }
    if !(a.dt.is_finite() && a.dt > 0.0 && a.rate.is_finite() && a.rate > 0.0) {
        bail!("--dt and --rate must be positive");
    }
    if !(a.air_density.is_finite() && (0.0..=MAX_AIR_DENSITY).contains(&a.air_density)) {
        bail!("--air-density must be between 0 and {MAX_AIR_DENSITY} kg/m³");
    }
    if a.dt > a.duration && a.duration > 0.0 {
        bail!(
            "--dt {} s is longer than --duration {} s: one step would overshoot the run",
            a.dt,
            a.duration
        );
    }
    // At least the duration asked for (rounding gave 0.7 s of a 1 s run at
    // --dt 0.7); the relative tolerance keeps 1 / 0.001 at 1000 steps and
    // 2.2 / 1e-7 at 22 million.
    // (An overflowing ratio stays infinite: inf - inf would be NaN, and
    // NaN.max(0) zero steps.)
    let ratio = a.duration / a.dt;
    let steps = if ratio.is_finite() {
        (ratio - 1e-12 * ratio.max(1.0)).ceil().max(0.0)
    } else {
        f64::INFINITY
    };
    if steps > MAX_STEPS {
        bail!(
            "--duration {} s at --dt {} s is {steps:.3e} RK4 steps; at most {MAX_STEPS:.0e} are run \
             (raise --dt or shorten --duration)",
            a.duration,
            a.dt
        );
    }
    let limits = [
        ("--velocity", a.velocity.norm(), MAX_SPEED, "m/s"),
        ("--wind", a.wind.norm(), MAX_SPEED, "m/s"),
        (
            "--angular-velocity",
            a.angular_velocity.norm(),
            MAX_ANGULAR_SPEED,
            "rad/s",
        ),
        ("--position", a.position.norm(), MAX_DISTANCE, "m"),
    ];
    for (name, value, max, unit) in limits {
        if value.is_nan() || value > max {
            bail!("{name} has magnitude {value:.3e} {unit}; at most {max} {unit} is accepted");
        }
    }
    Ok(steps as u64)
}

/// Runs `omniad simulate`.
pub fn run(a: &SimulateArgs) -> Result<()> {
    let steps = validate(a)?;
    let coefficients = match &a.file {
        Some(f) => Some(read_coefficients(f)?),
        None => None,
    };
    let shape = shape_of(a)?;
    let body = match (&shape, &coefficients) {
        (Some(sh), _) => RigidBody::new(sh.mass, sh.inertia())
            .map_err(|e| anyhow::anyhow!("--shape {:?} --size: {e}", sh.kind))?,
        (None, Some(m)) => body_of(m, a)?,
        (None, None) => bail!("give a coefficient FILE or --shape"),
    };
    let env = Environment {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        air_density: a.air_density,
        wind: a.wind,
    };
    let forces = Model::new(a.model, shape.as_ref(), coefficients.as_ref(), env)
        .map_err(|e| anyhow::anyhow!("--model: {e}"))?;
    let mut s = State {
        position: a.position,
        orientation: a.orientation,
        velocity: a.velocity,
        angular_velocity: a.angular_velocity,
    };
    let every = ((1.0 / a.rate) / a.dt).round().max(1.0) as u64;
    // Rows are streamed, so a long run needs no memory for its trajectory.
    let mut csv = a
        .csv
        .then(|| std::io::BufWriter::new(std::io::stdout().lock()));
    if let Some(out) = csv.as_mut() {
        out.write_all(state_csv::header().as_bytes())?;
        write_row(out, 0.0, &s)?;
    }
    let bar = progress(steps);
    let (mut t, mut step) = (0.0, 0);
    while step < steps {
        s = rk4_step(&body, &env, &forces, t, a.dt, &s);
        step += 1;
        t = step as f64 * a.dt;
        if !s.is_finite() {
            bail!(
                "numerical blow-up: the state became non-finite at t = {t:.4} s \
                 (step too large for this body?)"
            );
        }
        let grounded = a.stop_at_ground && s.position.z <= 0.0;
        if step % every == 0 || step == steps || grounded {
            if let Some(out) = csv.as_mut() {
                write_row(out, t, &s)?;
            }
        }
        if step % PROGRESS_EVERY == 0 {
            bar.set_position(step);
        }
        if grounded {
            break;
        }
    }
    bar.finish_and_clear();
    if let Some(mut out) = csv {
        out.flush()?;
    }
    report(a, &body, t, step, &s)
}

/// Steps between progress-bar updates.
const PROGRESS_EVERY: u64 = 1 << 16;

/// A progress bar on stderr for runs of more than about a second (one
/// million steps); hidden otherwise and when stderr is not a terminal.
fn progress(steps: u64) -> ProgressBar {
    if steps < 1_000_000 {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(steps).with_message("RK4 steps");
    if let Ok(style) = ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} eta {eta}") {
        bar.set_style(style);
    }
    bar
}

fn report(
    a: &SimulateArgs,
    body: &RigidBody<f64>,
    t: f64,
    step: u64,
    s: &State<f64>,
) -> Result<()> {
    let summary = json!({
        "duration_s": t, "steps": step,
        "final_position_m": [s.position.x, s.position.y, s.position.z],
        "final_velocity_m_s": [s.velocity.x, s.velocity.y, s.velocity.z],
        "final_speed_m_s": s.velocity.norm(),
        "horizontal_distance_m": (s.position.xy() - a.position.xy()).norm(),
        "kinetic_energy_j": s.kinetic_energy(body),
    });
    if a.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else if !a.csv {
        println!("simulated {t:.3} s in {step} RK4 steps of {} s", a.dt);
        println!(
            "final position  [{:.3}, {:.3}, {:.3}] m",
            s.position.x, s.position.y, s.position.z
        );
        println!(
            "final velocity  [{:.3}, {:.3}, {:.3}] m/s",
            s.velocity.x, s.velocity.y, s.velocity.z
        );
        println!("(use --csv for the trajectory, --json for this summary)");
    }
    Ok(())
}

/// The `--shape` body: `--size` (positive, finite) and `--mass`.
fn shape_of(a: &SimulateArgs) -> Result<Option<Shape>> {
    let Some(kind) = a.shape else {
        return Ok(None);
    };
    if !a.size.iter().all(|x| x.is_finite() && *x > 0.0) {
        bail!("--size must be three positive extents, m");
    }
    let mass = a.mass.unwrap_or(Shape::PAPER_PLATE.mass);
    if !(mass.is_finite() && mass > 0.0) {
        bail!("--mass must be positive");
    }
    Ok(Some(Shape {
        kind,
        size: a.size,
        mass,
    }))
}

fn body_of(model: &omniad_core::Coefficients<f64>, a: &SimulateArgs) -> Result<RigidBody<f64>> {
    let props = model
        .body
        .context("the coefficient file records no mass properties")?;
    let name = a.file.as_deref().unwrap_or(std::path::Path::new("FILE"));
    let mut body = RigidBody::from_properties(&props)
        .map_err(|e| anyhow::anyhow!("{}: {e}", name.display()))?;
    if let Some(m) = a.mass {
        if !(m.is_finite() && m > 0.0) {
            bail!("--mass must be positive");
        }
        let scale = m / body.mass;
        body =
            RigidBody::new(m, body.inertia * scale).map_err(|e| anyhow::anyhow!("--mass: {e}"))?;
    }
    Ok(body)
}

/// One state-CSV row (the format's one writer) onto the output stream.
fn write_row(out: &mut impl Write, t: f64, s: &State<f64>) -> std::io::Result<()> {
    let mut row = String::new();
    state_csv::push_row(&mut row, t, s, TimeFormat::Micros);
    out.write_all(row.as_bytes())
}
