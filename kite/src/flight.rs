//! Tethered flight: the kite as a rigid body (eqs. 1-2, RK4 from the core)
//! on an elastic string in gusty wind ([`crate::wind`]).
//!
//! * Air: eqs. (14)-(15) with each primitive's own air velocity
//!   `V_p = Q_pᵀ (Rᵀ(v - v_wind) + Ω × Y_p)` and damping.
//! * String: a tension-only spring-damper from the attachment point P
//!   (body frame) to the anchor, `T = k (d - ℓ) + c ḋ` when taut, `T >= 0`.
//! * Ground: `z = 0`; the kite crashes when its centre of mass comes
//!   within [`GROUND_CLEARANCE`] of it.
//!
//! Outcome: **flies** when it stays aloft for the whole run and its motion
//! over the second half is bounded (line elevation above
//! [`MIN_ELEVATION_DEG`], `|Ω|` below [`MAX_SPIN`]); **crashes** when it hits
//! the ground (or the state diverges); **unsettled** when aloft but
//! looping or lying low.

use crate::assemble::Design;
use crate::wind::Wind;
use anyhow::{anyhow, Result};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::aero::Wrench;
use omniad_core::integrate::rk4_step;
use omniad_core::kite::{statics, Primitive};
use omniad_core::rigid_body::{Environment, Forces, State};
use serde::Serialize;

/// Crash height of the centre of mass, m.
pub const GROUND_CLEARANCE: f64 = 0.3;
/// Lowest line elevation counted as flying, degrees.
pub const MIN_ELEVATION_DEG: f64 = 15.0;
/// Highest angular speed counted as bounded, rad/s.
pub const MAX_SPIN: f64 = 10.0;
/// Anchor (the flyer's hand), world frame, m.
pub const ANCHOR: [f64; 3] = [0.0, 0.0, 1.5];

/// Simulation settings.
#[derive(Clone, Debug)]
pub struct FlightOptions {
    /// Duration, s.
    pub seconds: f64,
    /// Gust strength G (std of the along-wind gust), m/s.
    pub gust: f64,
    /// Turbulence seed.
    pub seed: u64,
    /// Wind speed, m/s (default: the file's).
    pub wind: Option<f64>,
    /// RK4 step, s.
    pub dt: f64,
    /// Trace sample interval, s.
    pub sample: f64,
    /// Line stiffness k, N/m.
    pub stiffness: f64,
    /// Line damping c, N s/m.
    pub damping: f64,
}

impl Default for FlightOptions {
    fn default() -> Self {
        Self {
            seconds: 60.0,
            gust: 1.0,
            seed: 1,
            wind: None,
            dt: 1e-3,
            sample: 0.05,
            stiffness: 200.0,
            damping: 2.0,
        }
    }
}

/// The forces on a tethered kite.
pub struct Tether<'a> {
    /// The primitives (offsets from the centre of mass).
    pub primitives: &'a [Primitive<'a, f64>],
    /// Attachment P, body frame, m.
    pub attachment: Vector3<f64>,
    /// Anchor, world frame, m.
    pub anchor: Vector3<f64>,
    /// Rest length ℓ, m.
    pub length: f64,
    /// k, N/m.
    pub stiffness: f64,
    /// c, N s/m.
    pub damping: f64,
    /// Wind field.
    pub wind: &'a Wind,
    /// ρ, kg/m³.
    pub air_density: f64,
}

impl Tether<'_> {
    /// The string's force on the kite, world frame, N.
    pub fn string_force(&self, s: &State<f64>) -> Vector3<f64> {
        let r = s.orientation;
        let at = s.position + r.transform_vector(&self.attachment);
        let v_at = s.velocity + r.transform_vector(&s.angular_velocity.cross(&self.attachment));
        let d = self.anchor - at;
        let dist = d.norm();
        if !(dist > self.length) {
            return Vector3::zeros();
        }
        let dir = d / dist;
        let stretch_rate = -dir.dot(&v_at);
        let tension =
            (self.stiffness * (dist - self.length) + self.damping * stretch_rate).max(0.0);
        dir * tension
    }
}

impl Forces<f64> for Tether<'_> {
    fn wrench(&self, t: f64, s: &State<f64>) -> Wrench<f64> {
        let v = s.air_velocity_body(&self.wind.at(t));
        let air = statics::air_wrench(self.primitives, &v, &s.angular_velocity, self.air_density);
        let f = s
            .orientation
            .inverse_transform_vector(&self.string_force(s));
        Wrench {
            force: air.force + f,
            torque: air.torque + self.attachment.cross(&f),
        }
    }
}

/// Outcome of a flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Outcome {
    /// Aloft throughout with bounded motion.
    Flies,
    /// Aloft but looping, spinning or lying low.
    Unsettled,
    /// Hit the ground or diverged.
    Crashes,
}

/// One trace sample.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// s.
    pub t: f64,
    /// Centre of mass, world, m.
    pub position: [f64; 3],
    /// Roll, pitch, yaw (x, y, z Euler), degrees.
    pub attitude_deg: [f64; 3],
    /// |Ω|, rad/s.
    pub spin: f64,
    /// Line tension, N.
    pub tension: f64,
    /// Line elevation seen from the anchor, degrees.
    pub elevation_deg: f64,
    /// Wind, world, m/s.
    pub wind: [f64; 3],
}

/// Flight summary.
#[derive(Clone, Debug, Serialize)]
pub struct FlightReport {
    /// Kite name.
    pub name: String,
    /// Outcome.
    pub outcome: Outcome,
    /// Time of the crash, s.
    pub crash_time: Option<f64>,
    /// Simulated time, s.
    pub seconds: f64,
    /// Gust G, m/s; seed.
    pub gust: f64,
    /// Seed.
    pub seed: u64,
    /// Lowest centre-of-mass height, m.
    pub min_height: f64,
    /// Mean and lowest line elevation over the second half, degrees.
    pub mean_elevation_deg: f64,
    /// Lowest line elevation over the second half, degrees.
    pub min_elevation_deg: f64,
    /// Largest |Ω| over the second half, rad/s.
    pub max_spin: f64,
    /// Mean and largest line tension, N.
    pub mean_tension: f64,
    /// Largest line tension, N.
    pub max_tension: f64,
    /// Trace.
    #[serde(skip)]
    pub trace: Vec<Sample>,
}

/// Initial state: at the file's orientation, on a taut line along the
/// static string direction (or at 45° when the string would pull upward).
fn initial_state(
    design: &Design,
    wind: f64,
    tether: &Tether<'_>,
    r: &UnitQuaternion<f64>,
) -> Result<State<f64>> {
    let kite = design.kite(tether.primitives);
    let eq = statics::equilibrium(&kite, &design.conditions(Some(wind)), r)
        .map_err(|e| anyhow!("{e}"))?;
    let (dir, tension) = if eq.pulls_down && eq.string_world.norm() > 0.0 {
        (eq.string_world.normalize(), eq.string_world.norm())
    } else {
        (Vector3::new(-1.0, 0.0, -1.0).normalize(), 0.0)
    };
    let at = tether.anchor - dir * (tether.length + tension / tether.stiffness);
    let mut s = State::at_rest(at - r.transform_vector(&tether.attachment));
    s.orientation = *r;
    Ok(s)
}

/// Simulates a flight from the file's orientation and attachment point.
pub fn fly(design: &Design, opts: &FlightOptions) -> Result<FlightReport> {
    let speed = opts.wind.unwrap_or(design.spec.wind.speed);
    let r0 = design.orientation();
    design.reject_overlaps(&r0)?;
    let attachment = crate::check::attachment_point(design, Some(speed), &r0)?;
    let wind = Wind::new(speed, opts.gust, opts.seed);
    let prims = design.primitives();
    let tether = Tether {
        primitives: &prims,
        attachment,
        anchor: Vector3::from(ANCHOR),
        length: design.spec.string.length,
        stiffness: opts.stiffness,
        damping: opts.damping,
        wind: &wind,
        air_density: design.spec.wind.air_density,
    };
    let body = design.body()?;
    let env = Environment {
        wind: Vector3::zeros(),
        air_density: design.spec.wind.air_density,
        ..Environment::standard()
    };
    let mut s = initial_state(design, speed, &tether, &r0)?;
    let steps = (opts.seconds / opts.dt).ceil() as usize;
    let every = ((opts.sample / opts.dt).round() as usize).max(1);
    let mut trace = Vec::new();
    let mut crash_time = None;
    let mut min_height = f64::INFINITY;
    for i in 0..=steps {
        let t = i as f64 * opts.dt;
        min_height = min_height.min(s.position.z);
        if !s.is_finite() || s.position.z < GROUND_CLEARANCE {
            crash_time = Some(t);
            trace.push(sample(t, &s, &tether, &wind));
            break;
        }
        if i % every == 0 {
            trace.push(sample(t, &s, &tether, &wind));
        }
        if i < steps {
            s = rk4_step(&body, &env, &tether, t, opts.dt, &s);
        }
    }
    Ok(summarise(design, opts, crash_time, min_height, trace))
}

fn sample(t: f64, s: &State<f64>, tether: &Tether<'_>, wind: &Wind) -> Sample {
    let (roll, pitch, yaw) = s.orientation.euler_angles();
    let at = s.position + s.orientation.transform_vector(&tether.attachment) - tether.anchor;
    let horizontal = (at.x * at.x + at.y * at.y).sqrt();
    Sample {
        t,
        position: s.position.into(),
        attitude_deg: [roll, pitch, yaw].map(f64::to_degrees),
        spin: s.angular_velocity.norm(),
        tension: tether.string_force(s).norm(),
        elevation_deg: at.z.atan2(horizontal).to_degrees(),
        wind: wind.at(t).into(),
    }
}

fn summarise(
    design: &Design,
    opts: &FlightOptions,
    crash_time: Option<f64>,
    min_height: f64,
    trace: Vec<Sample>,
) -> FlightReport {
    let half: Vec<&Sample> = trace.iter().filter(|s| s.t >= opts.seconds / 2.0).collect();
    let n = half.len().max(1) as f64;
    let mean_elevation = half.iter().map(|s| s.elevation_deg).sum::<f64>() / n;
    let min_elevation = half
        .iter()
        .map(|s| s.elevation_deg)
        .fold(f64::INFINITY, f64::min);
    let max_spin = half.iter().map(|s| s.spin).fold(0.0, f64::max);
    let mean_tension = trace.iter().map(|s| s.tension).sum::<f64>() / trace.len().max(1) as f64;
    let max_tension = trace.iter().map(|s| s.tension).fold(0.0, f64::max);
    let outcome = if crash_time.is_some() {
        Outcome::Crashes
    } else if min_elevation > MIN_ELEVATION_DEG && max_spin < MAX_SPIN {
        Outcome::Flies
    } else {
        Outcome::Unsettled
    };
    FlightReport {
        name: design.spec.name.clone(),
        outcome,
        crash_time,
        seconds: trace.last().map_or(0.0, |s| s.t),
        gust: opts.gust,
        seed: opts.seed,
        min_height,
        mean_elevation_deg: mean_elevation,
        min_elevation_deg: if half.is_empty() {
            f64::NAN
        } else {
            min_elevation
        },
        max_spin,
        mean_tension,
        max_tension,
        trace,
    }
}

/// The trace as CSV text.
pub fn trace_csv(report: &FlightReport) -> String {
    let mut out = String::from(
        "t,x,y,z,roll_deg,pitch_deg,yaw_deg,spin,tension,elevation_deg,wind_x,wind_y,wind_z\n",
    );
    for s in &report.trace {
        let [x, y, z] = s.position;
        let [r, p, w] = s.attitude_deg;
        let [a, b, c] = s.wind;
        out += &format!(
            "{:.3},{x:.4},{y:.4},{z:.4},{r:.2},{p:.2},{w:.2},{:.4},{:.4},{:.2},{a:.3},{b:.3},{c:.3}\n",
            s.t, s.spin, s.tension, s.elevation_deg
        );
    }
    out
}

/// Human-readable summary.
pub fn render(r: &FlightReport) -> String {
    let outcome = match r.crash_time {
        Some(t) => format!("CRASHES at {t:.2} s"),
        None => format!("{:?}", r.outcome).to_lowercase(),
    };
    format!(
        "kite {:?}: {outcome} ({:.1} s simulated, gust {} m/s, seed {})\n  second half: mean line elevation {:.1} deg, lowest {:.1} deg, largest |Omega| {:.2} rad/s\n  lowest height {:.2} m; tension mean {:.2} N, max {:.2} N",
        r.name, r.seconds, r.gust, r.seed, r.mean_elevation_deg, r.min_elevation_deg, r.max_spin, r.min_height, r.mean_tension, r.max_tension
    )
}
