//! Dynamic stability beyond the paper's §7: the eigen-modes of the
//! tethered kite linearised about its equilibrium ([`crate::equilibrium`],
//! [`crate::linearise`]) — the rigid body on its elastic line, the same
//! model `kite fly` integrates — reported as XFLR5 and the
//! Vortex-Step-Method tools report them: eigenvalue `λ = σ ± iω` (1/s),
//! frequency `ω/2π` (Hz), damping ratio `ζ = -σ/|λ|`, and the motion in
//! words. The kite is dynamically stable when every `σ < 0`. When a mode
//! grows, where the growth ends is measured on the nonlinear flight
//! ([`crate::limit_cycle`]); the verdict's dynamic test is that the motion
//! is [`ModesReport::bounded`]: at rest, or on a limit cycle inside the
//! flight's limits.
//!
//! The motion is named by where the mode's kinetic energy goes (from the
//! eigenvector's position and attitude parts: `M|δy_k|²` per line axis,
//! `a_kᵀ I a_k |δθ_k|²` per rotation axis, world frame at the equilibrium):
//! *line stretch* (along the line), *pendulum swing* (across the line in
//! the vertical plane: elevation), *lateral swing* (across the line,
//! horizontally), *pitch* (rotation about the horizontal axis across the
//! wind) and *roll-yaw* (rotation about the other two).

use crate::equilibrium::Equilibrium;
use crate::flight_step::{Flight, FlightOptions};
use crate::gusts::{response, GustReport};
use crate::limit_cycle::LimitCycle;
use crate::linearise::{eigenvector, input_matrix, state_matrix, CVector, StateMatrix};
use crate::settle::settle;
use crate::strong_gust::{strong_gust, StrongGust};
use crate::Design;
use anyhow::Result;
use nalgebra::{Complex, Matrix3, Vector3};
use serde::Serialize;

/// Names of the motions, in the order of [`Mode::shares`].
pub const MOTIONS: [&str; 5] = [
    "line stretch",
    "pendulum swing",
    "lateral swing",
    "pitch",
    "roll-yaw",
];

/// One eigen-mode (complex pairs are listed once, `ω >= 0`).
#[derive(Clone, Debug, Serialize)]
pub struct Mode {
    /// The motion in words (the largest kinetic-energy share, and the
    /// second when it carries more than a quarter).
    pub motion: String,
    /// σ, 1/s (positive: grows).
    pub real: f64,
    /// ω, rad/s.
    pub imag: f64,
    /// ω / 2π, Hz (0 for a real mode).
    pub frequency_hz: f64,
    /// ζ = -σ/|λ| (1 for a real decaying mode, negative when growing).
    pub damping_ratio: f64,
    /// Kinetic-energy share per motion of [`MOTIONS`].
    pub shares: [f64; 5],
    /// σ < 0.
    pub stable: bool,
}

/// The equilibrium the modes are taken about.
#[derive(Clone, Debug, Serialize)]
pub struct EquilibriumReport {
    /// Line elevation, degrees.
    pub elevation_deg: f64,
    /// Line tension, N.
    pub tension: f64,
    /// Attitude (x, y, z Euler angles), degrees.
    pub orientation_deg: [f64; 3],
    /// Turn from the file's orientation, degrees.
    pub turn_deg: f64,
}

/// The dynamic analysis.
#[derive(Clone, Debug, Serialize)]
pub struct ModesReport {
    /// The equilibrium (`None`: the model has none near the file's attitude).
    pub equilibrium: Option<EquilibriumReport>,
    /// Modes, least damped (largest σ) first.
    pub modes: Vec<Mode>,
    /// Largest σ, 1/s.
    pub max_growth_rate: f64,
    /// An equilibrium exists and every mode decays.
    pub stable: bool,
    /// Where the growing modes end when some mode grows
    /// ([`crate::limit_cycle`]): the steady-wind flight from the
    /// equilibrium nudged along the fastest one (the worse of both ways).
    pub limit_cycle: Option<LimitCycle>,
    /// The kite rests at the equilibrium (`stable`) or its growing modes
    /// saturate in a limit cycle inside the flight's limits: the dynamic
    /// test of the verdict.
    pub bounded: bool,
    /// The predicted response to `kite fly`'s gusts ([`crate::gusts`]);
    /// `None` unless the motion is `bounded` (a growth without end has no
    /// steady response).
    pub gusts: Option<GustReport>,
    /// The flight through the largest expected discrete gusts and lulls
    /// ([`crate::strong_gust`]); `None` unless the linear gust test passes.
    pub strong_gust: Option<StrongGust>,
}

impl ModesReport {
    /// No equilibrium, so no modes.
    pub fn none() -> Self {
        Self {
            equilibrium: None,
            modes: Vec::new(),
            max_growth_rate: f64::NAN,
            stable: false,
            limit_cycle: None,
            bounded: false,
            gusts: None,
            strong_gust: None,
        }
    }
}

/// The flight model in steady wind (no gusts) at the file's attitude.
pub fn steady_flight(design: &Design, wind: Option<f64>) -> Result<Flight> {
    let opts = FlightOptions {
        gust: 0.0,
        wind,
        ..FlightOptions::default()
    };
    Flight::new(design.clone(), &opts)
}

/// The equilibrium and the modes about it.
pub fn analyse(design: &Design, wind: Option<f64>) -> Result<(Option<Equilibrium>, ModesReport)> {
    let flight = steady_flight(design, wind)?;
    let Some(settled) = settle(&flight) else {
        return Ok((None, ModesReport::none()));
    };
    let (eq, cycle) = (settled.equilibrium, settled.cycle);
    let a = state_matrix(&flight, &eq.state);
    let modes = modes_of(&flight, &eq, &a);
    let max = modes
        .iter()
        .map(|m| m.real)
        .fold(f64::NEG_INFINITY, f64::max);
    let (x, y, z) = eq.state.orientation.euler_angles();
    let stable = modes.iter().all(|m| m.stable);
    let bounded = stable || cycle.as_ref().is_some_and(|c| c.inside_limits);
    let gusts = bounded.then(|| {
        let b = input_matrix(&flight, &eq.state);
        response(&flight, &eq.state, &a, &b, cycle.as_ref())
    });
    let strong_gust = match &gusts {
        Some(g) if g.ok => Some(strong_gust(
            design,
            flight.wind_model().mean.norm(),
            &eq.state,
        )?),
        _ => None,
    };
    let report = ModesReport {
        equilibrium: Some(EquilibriumReport {
            elevation_deg: eq.elevation_deg,
            tension: eq.tension,
            orientation_deg: [x, y, z].map(f64::to_degrees),
            turn_deg: eq.turn_deg,
        }),
        stable,
        limit_cycle: cycle,
        bounded,
        gusts,
        strong_gust,
        max_growth_rate: max,
        modes,
    };
    Ok((Some(eq), report))
}

fn modes_of(flight: &Flight, eq: &Equilibrium, a: &StateMatrix) -> Vec<Mode> {
    let axes = line_axes(flight, eq);
    let r = eq.state.orientation.to_rotation_matrix().into_inner();
    let inertia = r * flight.body().inertia * r.transpose();
    let mut modes: Vec<Mode> = a
        .complex_eigenvalues()
        .iter()
        .filter(|l| l.im >= 0.0)
        .map(|&l| {
            let v = eigenvector(a, l);
            let shares = shares(&v, &axes, &r, &inertia, flight.body().mass);
            let mag = l.norm().max(f64::MIN_POSITIVE);
            Mode {
                motion: name(&shares),
                real: l.re,
                imag: l.im,
                frequency_hz: l.im / (2.0 * std::f64::consts::PI),
                damping_ratio: -l.re / mag,
                shares,
                stable: l.re < 0.0,
            }
        })
        .collect();
    modes.sort_by(|x, y| y.real.total_cmp(&x.real));
    modes
}

/// World axes at the equilibrium: along the line (kite to anchor), across
/// it in the vertical plane, across it horizontally.
fn line_axes(flight: &Flight, eq: &Equilibrium) -> Matrix3<f64> {
    let line = flight.line();
    let at = eq.state.position + eq.state.orientation.transform_vector(&line.attachment);
    let along = (line.anchor - at).normalize();
    let lateral = Vector3::z().cross(&along);
    let lateral = if lateral.norm() > 1e-9 {
        lateral.normalize()
    } else {
        Vector3::y()
    };
    let vertical = along.cross(&lateral);
    Matrix3::from_columns(&[along, vertical, lateral])
}

/// Kinetic-energy shares of the motions of [`MOTIONS`].
fn shares(
    v: &CVector,
    axes: &Matrix3<f64>,
    r: &Matrix3<f64>,
    inertia: &Matrix3<f64>,
    mass: f64,
) -> [f64; 5] {
    let part = |k: usize| Vector3::new(v[k], v[k + 1], v[k + 2]);
    let y = part(0);
    let theta_body = part(3);
    let theta = r.map(|x| Complex::new(x, 0.0)) * theta_body;
    let along = |u: Vector3<f64>, w: &Vector3<Complex<f64>>| {
        (w[0] * u.x + w[1] * u.y + w[2] * u.z).norm_sqr()
    };
    let lateral = axes.column(2).into_owned();
    let mut e = [0.0; 5];
    for (k, share) in e.iter_mut().take(3).enumerate() {
        *share = mass * along(axes.column(k).into_owned(), &y);
    }
    let pitch = lateral;
    e[3] = (pitch.transpose() * inertia * pitch)[0] * along(pitch, &theta);
    for u in [axes.column(0).into_owned(), axes.column(1).into_owned()] {
        e[4] += (u.transpose() * inertia * u)[0] * along(u, &theta);
    }
    let total: f64 = e.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    e.map(|x| x / total)
}

fn name(shares: &[f64; 5]) -> String {
    let mut order: Vec<usize> = (0..5).collect();
    order.sort_by(|&a, &b| shares[b].total_cmp(&shares[a]));
    let (first, second) = (order[0], order[1]);
    if shares[second] > 0.25 {
        format!("{} + {}", MOTIONS[first], MOTIONS[second])
    } else {
        MOTIONS[first].to_string()
    }
}

/// The modes as short text lines (the TUI's list and `kite check`).
pub fn lines(r: &ModesReport) -> Vec<String> {
    r.modes
        .iter()
        .map(|m| {
            let kind = if m.imag > 0.0 {
                format!("{:.2} Hz, zeta {:+.2}", m.frequency_hz, m.damping_ratio)
            } else {
                format!("real, tau {:+.2} s", -1.0 / m.real)
            };
            format!(
                "{:<28} sigma {:+.3}/s  {kind}  {}",
                m.motion,
                m.real,
                if m.stable { "decays" } else { "GROWS" }
            )
        })
        .collect()
}

/// The equilibrium and the modes as text (`kite check`).
pub fn render(r: &ModesReport) -> String {
    let Some(e) = &r.equilibrium else {
        return "  dynamics: no equilibrium of the kite on its line\n".into();
    };
    let [x, y, z] = e.orientation_deg;
    let mut s = format!(
        "  equilibrium on the line: elevation {:.1} deg, tension {:.2} N, attitude ({x:+.1}, {y:+.1}, {z:+.1}) deg ({:.1} deg from the file's)\n  modes (linearised tethered kite), least damped first:\n",
        e.elevation_deg, e.tension, e.turn_deg
    );
    for line in lines(r) {
        s += &format!("    {line}\n");
    }
    if let Some(c) = &r.limit_cycle {
        s += &crate::limit_cycle::render(c);
    }
    if let Some(g) = &r.gusts {
        s += &crate::gusts::render(g);
    }
    if let Some(g) = &r.strong_gust {
        s += &crate::strong_gust::render(g);
    }
    s
}
