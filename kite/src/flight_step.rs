//! The tethered-flight stepper: one kite on its line in gusty wind,
//! advanced one RK4 step (eqs. 1-2, from the core) at a time. `kite fly`
//! ([`crate::flight::fly`]) runs it for a fixed time; the TUI advances it
//! frame by frame, so both fly the same kite with the same physics.

use crate::assemble::Design;
use crate::tether::{Line, Tether};
use crate::wind::Wind;
use anyhow::{anyhow, Result};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::integrate::rk4_step;
use omniad_core::kite::statics;
use omniad_core::rigid_body::Forces;
use omniad_core::rigid_body::{state_rate, Environment, State, StateRate};
use omniad_core::RigidBody;
use serde::Serialize;

/// Crash height of the centre of mass, m.
pub const GROUND_CLEARANCE: f64 = 0.3;
/// Lowest line elevation counted as flying, degrees.
pub const MIN_ELEVATION_DEG: f64 = 15.0;
/// Highest angular speed of a settled kite, rad/s. A kite held on its
/// line turns with the wind's direction: in the default gusts
/// (`G` = 1 m/s at 5 m/s, [`crate::wind`]) the crosswind turns the
/// apparent wind at 0.34 rad/s rms, peaks near 1 rad/s. Turning faster
/// than twice those peaks for any time in the second half is
/// self-excited motion — a growing mode that saturated into rolling or
/// looping (the bundled classic box kite's roll-yaw flutter turns at
/// 2-5 rad/s with ±50° roll) — not flight. (It was 10 rad/s, which
/// counted such loops as flying.)
pub const MAX_SPIN: f64 = 2.0;

/// The flight's judgement of an aloft kite over the span it judges: the
/// line stayed above [`MIN_ELEVATION_DEG`] and `|Ω|` below [`MAX_SPIN`]
/// (`kite fly`'s outcome; the verdict's limit-cycle and strong-gust runs
/// judge by the same rule).
pub fn within_limits(min_elevation_deg: f64, max_spin: f64) -> bool {
    min_elevation_deg > MIN_ELEVATION_DEG && max_spin < MAX_SPIN
}
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

/// A flight in progress. Time is `steps × dt` (not a running sum), so a
/// run is the same whoever steps it.
#[derive(Clone, Debug)]
pub struct Flight {
    design: Design,
    line: Line,
    wind: Wind,
    seed: u64,
    body: RigidBody<f64>,
    env: Environment<f64>,
    state: State<f64>,
    dt: f64,
    steps: u64,
}

impl Flight {
    /// The kite of `design` at its file orientation, on a taut line along
    /// the static string direction, in the wind of `opts` (speed, gust,
    /// seed, line stiffness and damping, step `dt`). Errors when
    /// primitives overlap along the wind or there is no equilibrium.
    pub fn new(design: Design, opts: &FlightOptions) -> Result<Self> {
        let speed = opts.wind.unwrap_or(design.spec.wind.speed);
        let r0 = design.orientation();
        design.reject_overlaps(&r0)?;
        let line = Line {
            attachment: crate::attachment::attachment_point(&design, Some(speed), &r0)?,
            anchor: Vector3::from(ANCHOR),
            length: design.spec.string.length,
            stiffness: opts.stiffness,
            damping: opts.damping,
        };
        let body = design.body()?;
        let env = Environment {
            wind: Vector3::zeros(),
            air_density: design.spec.wind.air_density,
            ..Environment::standard()
        };
        let state = initial_state(&design, speed, &line, &r0)?;
        Ok(Self {
            wind: Wind::new(speed, opts.gust, opts.seed),
            seed: opts.seed,
            design,
            line,
            body,
            env,
            state,
            dt: opts.dt,
            steps: 0,
        })
    }

    /// The flight model's state derivative (eqs. 1-2 with the tether's
    /// wrench) at `state` and time `t`: what [`Flight::step`] integrates,
    /// exposed so that the linearisation differentiates this very
    /// function.
    pub fn rate(&self, t: f64, state: &State<f64>) -> StateRate<f64> {
        self.with_tether(|tether| {
            state_rate(
                &self.body,
                &self.env.gravity,
                state,
                &tether.wrench(t, state),
            )
        })
    }

    /// [`Flight::rate`] in the steady wind `wind` (world frame, m/s)
    /// instead of the flight's: the gust input of the linearisation
    /// ([`crate::gusts`]).
    pub fn rate_in_wind(&self, state: &State<f64>, wind: &Vector3<f64>) -> StateRate<f64> {
        let steady = Wind::steady(*wind);
        self.with_wind(&steady, |tether| {
            state_rate(
                &self.body,
                &self.env.gravity,
                state,
                &tether.wrench(0.0, state),
            )
        })
    }

    /// Runs `f` with the forces on the kite (air and line) now.
    fn with_tether<R>(&self, f: impl FnOnce(&Tether) -> R) -> R {
        self.with_wind(&self.wind, f)
    }

    /// Runs `f` with the forces on the kite in the wind field `wind`.
    fn with_wind<R>(&self, wind: &Wind, f: impl FnOnce(&Tether) -> R) -> R {
        let prims = self.design.primitives();
        f(&Tether {
            primitives: &prims,
            line: &self.line,
            wind,
            air_density: self.design.spec.wind.air_density,
        })
    }

    /// The mean wind, world frame, m/s, and the gust spectrum
    /// ([`Wind::spectrum`]) of this flight's gust strength.
    pub fn wind_model(&self) -> &Wind {
        &self.wind
    }

    /// Restarts the flight at `state` (time unchanged): the launch
    /// ([`crate::launch`]) releases the kite at its equilibrium.
    pub(crate) fn release_at(&mut self, state: State<f64>) {
        self.state = state;
    }

    /// The gusts from now on given that the gust at `t = 0` was `gust0`
    /// (world frame, m/s; [`Wind::conditioned`]): the launch's wind when
    /// the kite has no equilibrium in the wind blowing at `t = 0`.
    pub(crate) fn condition_gust(&mut self, gust0: Vector3<f64>) {
        self.wind = self.wind.clone().conditioned(gust0);
    }

    /// The same flight stepped at `dt` (s) from now on.
    pub(crate) fn with_step(mut self, dt: f64) -> Self {
        let t = self.time();
        self.dt = dt;
        self.steps = (t / dt).round() as u64;
        self
    }

    /// The rigid body (mass, inertia).
    pub fn body(&self) -> &RigidBody<f64> {
        &self.body
    }

    /// Advances one RK4 step of `dt`.
    pub fn step(&mut self) {
        let t = self.time();
        self.state = self
            .with_tether(|tether| rk4_step(&self.body, &self.env, tether, t, self.dt, &self.state));
        self.steps += 1;
    }

    /// Steps until the time reaches `t` (s) or the kite crashes.
    pub fn advance_to(&mut self, t: f64) {
        while self.time() < t && !self.crashed() {
            self.step();
        }
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.dt
    }

    /// The kite's state (world frame, z up, ground at `z = 0`).
    pub fn state(&self) -> &State<f64> {
        &self.state
    }

    /// The line (attachment, anchor, length).
    pub fn line(&self) -> &Line {
        &self.line
    }

    /// Wind now, world frame, m/s.
    pub fn wind_now(&self) -> Vector3<f64> {
        self.wind.at(self.time())
    }

    /// Changes the mean wind and the gust strength (m/s) from now on,
    /// keeping the turbulence seed.
    pub fn set_wind(&mut self, speed: f64, gust: f64) {
        self.wind = Wind::new(speed, gust, self.seed);
    }

    /// A steady wind `v` (world frame, m/s) from now on, without gusts:
    /// the discrete gusts of [`crate::strong_gust`] are flown through it.
    pub(crate) fn set_steady_wind(&mut self, v: Vector3<f64>) {
        self.wind = Wind::steady(v);
    }

    /// Whether the centre of mass came within [`GROUND_CLEARANCE`] of the
    /// ground, or the state diverged.
    pub fn crashed(&self) -> bool {
        !self.state.is_finite() || self.state.position.z < GROUND_CLEARANCE
    }

    /// The trace sample now.
    pub fn sample(&self) -> Sample {
        let (s, t) = (&self.state, self.time());
        let (roll, pitch, yaw) = s.orientation.euler_angles();
        Sample {
            t,
            position: s.position.into(),
            attitude_deg: [roll, pitch, yaw].map(f64::to_degrees),
            spin: s.angular_velocity.norm(),
            tension: self.line.force(s).norm(),
            elevation_deg: self.line.elevation_deg(s),
            wind: self.wind.at(t).into(),
        }
    }
}

/// Initial state: at orientation `r`, on a taut line along the static
/// string direction (or at 45° when the string would pull upward).
fn initial_state(
    design: &Design,
    wind: f64,
    line: &Line,
    r: &UnitQuaternion<f64>,
) -> Result<State<f64>> {
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let eq = statics::equilibrium(&kite, &design.conditions(Some(wind)), r)
        .map_err(|e| anyhow!("{e}"))?;
    let (dir, tension) = if eq.pulls_down && eq.string_world.norm() > 0.0 {
        (eq.string_world.normalize(), eq.string_world.norm())
    } else {
        (Vector3::new(-1.0, 0.0, -1.0).normalize(), 0.0)
    };
    let at = line.anchor - dir * (line.length + tension / line.stiffness);
    let mut s = State::at_rest(at - r.transform_vector(&line.attachment));
    s.orientation = *r;
    Ok(s)
}
