//! `omniad simulate FILE --duration S`: one body through air, RK4 (§4.3).

use super::common::read_coefficients;
use anyhow::{bail, Context, Result};
use clap::Args;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use omniad_acquire::input::state_csv::{self, TimeFormat};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Environment, RigidBody, State};
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `omniad simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// Coefficient file (.omni).
    pub file: PathBuf,
    /// Simulated time, s.
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
    /// Initial velocity x,y,z (world), m/s.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub velocity: Vector3<f64>,
    /// Initial angular velocity x,y,z (body), rad/s.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub angular_velocity: Vector3<f64>,
    /// Uniform wind x,y,z (world), m/s.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,0", allow_hyphen_values = true)]
    pub wind: Vector3<f64>,
    /// Air density ρ, kg/m³.
    #[arg(long, default_value_t = 1.2)]
    pub air_density: f64,
    /// Mass, kg (default: the file's).
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

/// Runs `omniad simulate`.
pub fn run(a: &SimulateArgs) -> Result<()> {
    if !(a.duration.is_finite() && a.duration >= 0.0) {
        bail!("--duration must be a finite non-negative number of seconds");
    }
    if !(a.dt.is_finite() && a.dt > 0.0 && a.rate.is_finite() && a.rate > 0.0) {
        bail!("--dt and --rate must be positive");
    }
    if !(a.air_density.is_finite() && a.air_density >= 0.0) {
        bail!("--air-density must be non-negative");
    }
    let model = read_coefficients(&a.file)?;
    let body = body_of(&model, a)?;
    let env = Environment {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        air_density: a.air_density,
        wind: a.wind,
    };
    let forces = AirForces {
        model: &model,
        environment: env,
    };
    let mut s = State {
        position: a.position,
        orientation: a.orientation,
        velocity: a.velocity,
        angular_velocity: a.angular_velocity,
    };
    let steps = (a.duration / a.dt).round() as u64;
    let every = ((1.0 / a.rate) / a.dt).round().max(1.0) as u64;
    let mut csv = state_csv::header();
    let mut t = 0.0;
    state_csv::push_row(&mut csv, t, &s, TimeFormat::Micros);
    let mut step = 0;
    while step < steps {
        s = rk4_step(&body, &env, &forces, t, a.dt, &s);
        step += 1;
        t = step as f64 * a.dt;
        if !s.is_finite() {
            bail!("the state became non-finite at t = {t:.4} s (step too large for this body?)");
        }
        let grounded = a.stop_at_ground && s.position.z <= 0.0;
        if step % every == 0 || step == steps || grounded {
            state_csv::push_row(&mut csv, t, &s, TimeFormat::Micros);
        }
        if grounded {
            break;
        }
    }
    if a.csv {
        print!("{csv}");
    }
    let summary = json!({
        "duration_s": t, "steps": step,
        "final_position_m": [s.position.x, s.position.y, s.position.z],
        "final_velocity_m_s": [s.velocity.x, s.velocity.y, s.velocity.z],
        "final_speed_m_s": s.velocity.norm(),
        "horizontal_distance_m": (s.position.xy() - a.position.xy()).norm(),
        "kinetic_energy_j": s.kinetic_energy(&body),
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

fn body_of(model: &omniad_core::Coefficients<f64>, a: &SimulateArgs) -> Result<RigidBody<f64>> {
    let props = model
        .body
        .context("the coefficient file records no mass properties")?;
    let mut body = RigidBody::from_properties(&props)
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.file.display()))?;
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
