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
//! Outcome (two-valued, as issue 17 specifies): **flies** when it stays
//! aloft for the whole run and settles over the second half (line
//! elevation above [`MIN_ELEVATION_DEG`], `|Ω|` below [`MAX_SPIN`]:
//! turning with the gusts, not looping); else **crashes**, and
//! [`FlightReport::reason`] says why: it hit the ground (or the state
//! diverged) at a time, or it stayed aloft but did not settle (looping,
//! rolling or lying low — a kite no flyer would call flying). Statistics
//! are over the second half of the time actually flown (up to the crash,
//! if any).
//!
//! Assumptions and their sources:
//! * Tether: straight, massless, no line drag, no sag; elastic with
//!   `k` = 200 N/m and `c` = 2 N s/m (a 20 m braided line of a few kN
//!   axial stiffness EA gives k = EA/ℓ of 10²-10³ N/m; c gives the
//!   line-stretch mode, √(k/M) ≈ 50 rad/s, a damping ratio near 0.25).
//!   Line drag and mass matter for long lines (the Vortex-Step-Method /
//!   KiteGen tether models lump them on the kite); at 20 m and a few
//!   grams of line they are neglected here.
//! * Air: quasi-steady OmniAD coefficients per primitive (eqs. 14-15), no
//!   interference between primitives (§7 forbids overlaps along the wind),
//!   no added mass.
//! * Gusts: [`crate::wind`], a Dryden-shaped spectrum (MIL-F-8785C form)
//!   with Λ = 30 m, spatially uniform over the kite (it is ≪ Λ).
//! * Start: at rest at the equilibrium of the flight model in the wind
//!   blowing at `t = 0`, the mean wind plus the gust's value then
//!   ([`crate::launch`]: as a flyer releases a kite that has settled on
//!   its line; the gust is a stationary process, Shinozuka & Deodatis
//!   1991, so it is not zero at the release, and a kite at rest in the
//!   mean wind would feel it as a step the spectrum does not contain),
//!   followed from the mean-wind equilibrium the verdict analyses; a kite
//!   without one starts at the file's attitude on a taut line along the
//!   static string direction. Ground strikes count from `t = 0`.

use crate::assemble::Design;
use anyhow::Result;
use serde::Serialize;

pub use crate::flight_step::{
    Flight, FlightOptions, Sample, ANCHOR, GROUND_CLEARANCE, MAX_SPIN, MIN_ELEVATION_DEG,
};
pub use crate::tether::{Line, Tether};

/// Outcome of a flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Outcome {
    /// Aloft throughout with bounded motion.
    Flies,
    /// Hit the ground or diverged, or aloft but looping, spinning or lying
    /// low ([`FlightReport::reason`] says which).
    Crashes,
}

impl Outcome {
    /// `flies` or `crashes`, as in `kite fly --json`'s `outcome`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Flies => "flies",
            Self::Crashes => "crashes",
        }
    }
}

/// Flight summary.
#[derive(Clone, Debug, Serialize)]
pub struct FlightReport {
    /// Kite name.
    pub name: String,
    /// Outcome.
    pub outcome: Outcome,
    /// Why, in words: `"settled: ..."`, `"hit the ground at 12.3 s"`,
    /// `"unsettled: turning at 3.1 rad/s rms, rolling ±45°"`.
    pub reason: String,
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
    /// Mean line elevation over the second half of the time flown
    /// (to the crash, if it crashed), degrees.
    pub mean_elevation_deg: f64,
    /// Lowest line elevation over the same span, degrees.
    pub min_elevation_deg: f64,
    /// Largest |Ω| over the same span, rad/s.
    pub max_spin: f64,
    /// RMS |Ω| over the same span, rad/s.
    pub rms_spin: f64,
    /// Half the roll range over the same span, degrees.
    pub roll_amplitude_deg: f64,
    /// Mean and largest line tension, N.
    pub mean_tension: f64,
    /// Largest line tension, N.
    pub max_tension: f64,
    /// Trace.
    #[serde(skip)]
    pub trace: Vec<Sample>,
}

/// Simulates a flight with the file's attachment point, launched at the
/// equilibrium ([`crate::launch`]): [`Flight`] stepped for `opts.seconds`,
/// sampled every `opts.sample`.
pub fn fly(design: &Design, opts: &FlightOptions) -> Result<FlightReport> {
    let mut flight = crate::launch::launch(design, opts)?;
    let steps = (opts.seconds / opts.dt).ceil() as usize;
    let every = ((opts.sample / opts.dt).round() as usize).max(1);
    let mut trace = Vec::new();
    let mut crash_time = None;
    let mut min_height = f64::INFINITY;
    for i in 0..=steps {
        min_height = min_height.min(flight.state().position.z);
        if blew_up(flight.state()) {
            // A numerical blow-up is not a physical crash: say so.
            anyhow::bail!(
                "numerical blow-up at t = {:.3} s: speed {:.3e} m/s, spin {:.3e} rad/s \
                 (integration step too large for this kite and line?)",
                flight.time(),
                flight.state().velocity.norm(),
                flight.state().angular_velocity.norm()
            );
        }
        if flight.crashed() {
            crash_time = Some(flight.time());
            trace.push(flight.sample());
            break;
        }
        if i % every == 0 {
            trace.push(flight.sample());
        }
        if i < steps {
            flight.step();
        }
    }
    Ok(summarise(design, opts, crash_time, min_height, trace))
}

/// Speeds no tethered kite reaches (m/s; a kite in wind U moves at most a
/// few times U), and spin rates no kite frame survives (rad/s): beyond
/// them the state is numerical, not physical.
const BLOW_UP_SPEED: f64 = 200.0;
const BLOW_UP_SPIN: f64 = 500.0;

/// Whether the state is a numerical blow-up rather than a flight.
fn blew_up(s: &omniad_core::State<f64>) -> bool {
    !s.is_finite() || s.velocity.norm() > BLOW_UP_SPEED || s.angular_velocity.norm() > BLOW_UP_SPIN
}

fn summarise(
    design: &Design,
    opts: &FlightOptions,
    crash_time: Option<f64>,
    min_height: f64,
    trace: Vec<Sample>,
) -> FlightReport {
    // The second half of the time actually flown (all of it when the kite
    // crashed before the halfway point of the requested run).
    let end = trace.last().map_or(0.0, |s| s.t);
    let half: Vec<&Sample> = trace.iter().filter(|s| s.t >= end / 2.0).collect();
    let n = half.len().max(1) as f64;
    let mean_elevation = half.iter().map(|s| s.elevation_deg).sum::<f64>() / n;
    let min_elevation = half
        .iter()
        .map(|s| s.elevation_deg)
        .fold(f64::INFINITY, f64::min);
    let max_spin = half.iter().map(|s| s.spin).fold(0.0, f64::max);
    let rms_spin = (half.iter().map(|s| s.spin * s.spin).sum::<f64>() / n).sqrt();
    let roll_amplitude = roll_amplitude(half.iter().map(|s| s.attitude_deg[0]));
    let mean_tension = trace.iter().map(|s| s.tension).sum::<f64>() / trace.len().max(1) as f64;
    let max_tension = trace.iter().map(|s| s.tension).fold(0.0, f64::max);
    let settled = crate::flight_step::within_limits(min_elevation, max_spin);
    let (outcome, reason) = match crash_time {
        Some(t) => (Outcome::Crashes, format!("hit the ground at {t:.1} s")),
        None if settled => (
            Outcome::Flies,
            format!(
                "settled: line elevation >= {min_elevation:.0}°, turning <= {max_spin:.1} rad/s"
            ),
        ),
        None => (
            Outcome::Crashes,
            unsettled_reason(min_elevation, rms_spin, max_spin, roll_amplitude),
        ),
    };
    FlightReport {
        name: design.spec.name.clone(),
        outcome,
        reason,
        crash_time,
        seconds: trace.last().map_or(0.0, |s| s.t),
        gust: opts.gust,
        seed: opts.seed,
        min_height,
        mean_elevation_deg: mean_elevation,
        min_elevation_deg: min_elevation,
        max_spin,
        rms_spin,
        roll_amplitude_deg: roll_amplitude,
        mean_tension,
        max_tension,
        trace,
    }
}

/// Half the range of the roll angle (degrees, the trace's Euler roll in
/// (-180°, 180°]) followed continuously from sample to sample: a kite
/// resting rolled near 180° swings across the ±180° cut, which as read
/// would be a range of 360°. 0 for no samples.
fn roll_amplitude(rolls: impl Iterator<Item = f64>) -> f64 {
    let mut rolls = rolls.filter(|r| r.is_finite());
    let Some(first) = rolls.next() else {
        return 0.0;
    };
    let (mut last, mut unwrapped) = (first, first);
    let (mut low, mut high) = (first, first);
    for r in rolls {
        unwrapped += (r - last + 540.0).rem_euclid(360.0) - 180.0;
        last = r;
        low = low.min(unwrapped);
        high = high.max(unwrapped);
    }
    (high - low) / 2.0
}

/// Why an aloft kite did not count as flying: what it did over the second
/// half (turning, rolling, lying low).
fn unsettled_reason(min_elevation: f64, rms_spin: f64, max_spin: f64, roll: f64) -> String {
    let mut parts = Vec::new();
    if !(max_spin < MAX_SPIN) {
        parts.push(format!(
            "turning at {rms_spin:.1} rad/s rms (peak {max_spin:.1}), rolling ±{roll:.0}°"
        ));
    }
    if !(min_elevation > MIN_ELEVATION_DEG) {
        parts.push(format!(
            "line down to {min_elevation:.0}° elevation (below {MIN_ELEVATION_DEG:.0}°)"
        ));
    }
    format!("unsettled: {}", parts.join(", "))
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
    let outcome = match r.outcome {
        Outcome::Flies => format!("flies ({})", r.reason),
        Outcome::Crashes => format!("CRASHES ({})", r.reason),
    };
    format!(
        "kite {:?}: {outcome} ({:.1} s simulated, gust {} m/s, seed {})\n  second half: mean line elevation {:.1} deg, lowest {:.1} deg, largest |Omega| {:.2} rad/s\n  lowest height {:.2} m; tension mean {:.2} N, max {:.2} N",
        r.name, r.seconds, r.gust, r.seed, r.mean_elevation_deg, r.min_elevation_deg, r.max_spin, r.min_height, r.mean_tension, r.max_tension
    )
}

#[cfg(test)]
mod tests {
    use super::roll_amplitude;

    /// A roll swinging ±10° reads 10°; one resting near 180° across the
    /// ±180° cut reads its own small swing, not 180°; a whole turn reads
    /// 180°.
    #[test]
    fn the_roll_is_followed_across_the_cut() {
        let swing = [-10.0, 0.0, 10.0, 0.0, -10.0];
        assert!((roll_amplitude(swing.into_iter()) - 10.0).abs() < 1e-12);
        let inverted = [175.0, 179.0, -178.0, -174.0, 178.0];
        let a = roll_amplitude(inverted.into_iter());
        assert!((a - 5.5).abs() < 1e-9, "{a}");
        let turn = [0.0, 90.0, 180.0, -90.0, 0.0];
        assert!((roll_amplitude(turn.into_iter()) - 180.0).abs() < 1e-9);
        assert_eq!(roll_amplitude(std::iter::empty()), 0.0);
    }
}
