//! Where a growing mode ends: the bounded motion (limit cycle) of a kite
//! whose equilibrium is linearly unstable, measured on the nonlinear
//! steady-wind flight ([`crate::settle`] runs it) and judged by the
//! flight's own limits ([`MIN_ELEVATION_DEG`], [`MAX_SPIN`],
//! [`GROUND_CLEARANCE`]).
//!
//! Why: a growing mode of the linearisation ([`crate::modes`]) says a small
//! disturbance grows, not how far. Measured (BENCHMARKS, issue 17, "slow
//! growth"): released on its growing mode, box-three-cell pitched +5° grows
//! at +0.160/s in the nonlinear flight (the linearisation predicts
//! +0.162/s: the analysis is right), then the growth stops — the air
//! wrench is not linear in the attitude — in a pitch-pendulum oscillation
//! of ±1.3° line elevation and |Ω| ≤ 0.19 rad/s, which flies in every
//! gusty flight; the classic box kite's roll-yaw flutter saturates too, but
//! at 2.5-4.5 rad/s, and crashes. A kite resting on a small limit cycle
//! inside the flight's limits flies (the cycle is an attractor: orbitally
//! stable), so the verdict judges where the growth ends, not that it
//! starts. The linear analysis cannot size the saturation amplitude
//! (it is set by the nonlinear terms); the flight model is run instead.
//!
//! The motion is judged over the last [`JUDGED_SECONDS`] of the run: the
//! span the flight judges (the second half of `kite fly`'s default 60 s).

use crate::flight_step::{
    within_limits, Flight, FlightOptions, GROUND_CLEARANCE, MAX_SPIN, MIN_ELEVATION_DEG,
};
use serde::Serialize;

/// The span over which the bounded motion is judged, s (the second half
/// of `kite fly`'s default run).
pub(crate) fn judged_seconds() -> f64 {
    FlightOptions::default().seconds / 2.0
}

/// The bounded motion a growing mode ends in, in steady wind.
#[derive(Clone, Debug, Serialize)]
pub struct LimitCycle {
    /// Steady-wind flight time from the nudged equilibrium, s.
    pub seconds: f64,
    /// The run hit the ground (or diverged) before its end.
    pub crashed: bool,
    /// Lowest and highest line elevation over the judged span, degrees.
    pub elevation_deg: [f64; 2],
    /// Largest |Ω| over the judged span, rad/s.
    pub max_spin: f64,
    /// Lowest centre-of-mass height over the judged span, m.
    pub min_height: f64,
    /// The motion stays inside the flight's limits (aloft, line above
    /// [`MIN_ELEVATION_DEG`], |Ω| below [`MAX_SPIN`]).
    pub inside_limits: bool,
}

/// Accumulates the motion of a run over its judged span.
#[derive(Clone, Debug)]
pub(crate) struct Recorder {
    from: f64,
    elevation: [f64; 2],
    max_spin: f64,
    min_height: f64,
}

impl Recorder {
    /// Records from time `from` (s) on.
    pub(crate) fn from(from: f64) -> Self {
        Self {
            from,
            elevation: [f64::INFINITY, f64::NEG_INFINITY],
            max_spin: 0.0,
            min_height: f64::INFINITY,
        }
    }

    /// Takes the flight's state now into account.
    pub(crate) fn record(&mut self, f: &Flight) {
        if f.time() < self.from {
            return;
        }
        let s = f.state();
        let e = f.line().elevation_deg(s);
        self.elevation = [self.elevation[0].min(e), self.elevation[1].max(e)];
        self.max_spin = self.max_spin.max(s.angular_velocity.norm());
        self.min_height = self.min_height.min(s.position.z);
    }

    /// The cycle of a run that ended at `f`.
    pub(crate) fn finish(&self, f: &Flight, seconds: f64) -> LimitCycle {
        let crashed = f.crashed() || f.time() + 1e-9 < self.from;
        let inside = !crashed
            && within_limits(self.elevation[0], self.max_spin)
            && self.min_height > GROUND_CLEARANCE;
        LimitCycle {
            seconds,
            crashed,
            elevation_deg: self.elevation,
            max_spin: self.max_spin,
            min_height: self.min_height,
            inside_limits: inside,
        }
    }
}

impl LimitCycle {
    /// The worse of two runs (the gusts push a kite both ways along its
    /// mode, so it must stay inside the limits on both).
    pub(crate) fn worse(self, other: Self) -> Self {
        Self {
            seconds: self.seconds.max(other.seconds),
            crashed: self.crashed || other.crashed,
            elevation_deg: [
                self.elevation_deg[0].min(other.elevation_deg[0]),
                self.elevation_deg[1].max(other.elevation_deg[1]),
            ],
            max_spin: self.max_spin.max(other.max_spin),
            min_height: self.min_height.min(other.min_height),
            inside_limits: self.inside_limits && other.inside_limits,
        }
    }
}

/// The cycle as one text line (`kite check`).
pub fn render(c: &LimitCycle) -> String {
    if c.crashed {
        return format!(
            "  growing mode, steady wind ({:.0} s from the equilibrium): hits the ground\n",
            c.seconds
        );
    }
    format!(
        "  growing mode, steady wind ({:.0} s from the equilibrium): saturates at line elevation {:.1}-{:.1} deg (limit {:.0}), |Omega| <= {:.2} rad/s (limit {:.1}): {}\n",
        c.seconds,
        c.elevation_deg[0],
        c.elevation_deg[1],
        MIN_ELEVATION_DEG,
        c.max_spin,
        MAX_SPIN,
        if c.inside_limits {
            "a limit cycle inside the flight's limits"
        } else {
            "outside the flight's limits"
        }
    )
}
