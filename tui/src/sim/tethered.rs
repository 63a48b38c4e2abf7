//! The tethered-kite scene: the kite view's design flown by the kite
//! crate's [`Flight`], the model `omniad kite fly` runs (same line,
//! anchor, wind field and RK4 step), advanced one displayed frame at a
//! time. Here only what the view adds: relaunch after a crash, the trail,
//! and the wind and gust controls.

use nalgebra::Vector3;
use omniad_kite::flight::{Flight, FlightOptions};
use omniad_kite::Design;
use std::collections::VecDeque;

/// One displayed frame, s.
const FRAME: f64 = 1.0 / 30.0;
/// Trail length, frames.
const TRAIL: usize = 90;
/// Turbulence seed (fixed: reproducible runs).
const SEED: u64 = 1;

/// The tethered kite's state.
#[derive(Clone, Debug)]
pub struct Tethered {
    /// The flight in progress.
    pub flight: Flight,
    /// Simulated time over all launches, s.
    pub time: f64,
    /// Mean wind along +x, m/s.
    pub wind: f64,
    /// Gust strength as a fraction of the mean wind (the flight's gust
    /// standard deviation is `gust × wind` m/s).
    pub gust: f64,
    /// Times the kite hit the ground and was relaunched.
    pub crashes: u32,
    /// Recent positions, world frame, m.
    pub trail: VecDeque<Vector3<f64>>,
    design: Design,
}

impl Tethered {
    /// `design` at its file orientation on its line, in its file's wind;
    /// `None` when it cannot fly (overlapping primitives, no equilibrium).
    pub fn new(design: &Design) -> Option<Self> {
        let (wind, gust) = (design.spec.wind.speed, 0.3);
        Some(Self {
            flight: launch(design, wind, gust)?,
            time: 0.0,
            wind,
            gust,
            crashes: 0,
            trail: VecDeque::new(),
            design: design.clone(),
        })
    }

    /// The kite's centre of mass, world frame, m.
    pub fn position(&self) -> Vector3<f64> {
        self.flight.state().position
    }

    /// Applies changed [`Self::wind`] and [`Self::gust`] from now on.
    pub fn retune(&mut self) {
        self.flight.set_wind(self.wind, self.gust * self.wind);
    }

    /// Advances one displayed frame; a crash relaunches the kite.
    pub fn step_frame(&mut self) {
        let t0 = self.flight.time();
        self.flight.advance_to(t0 + FRAME);
        self.time += self.flight.time() - t0;
        if self.flight.crashed() {
            self.crashes += 1;
            if let Some(f) = launch(&self.design, self.wind, self.gust) {
                self.flight = f;
            }
            self.trail.clear();
        }
        self.trail.push_back(self.position());
        while self.trail.len() > TRAIL {
            self.trail.pop_front();
        }
    }
}

fn launch(design: &Design, wind: f64, gust: f64) -> Option<Flight> {
    let opts = FlightOptions {
        wind: Some(wind),
        gust: gust * wind,
        seed: SEED,
        ..FlightOptions::default()
    };
    omniad_kite::launch::launch(design, &opts).ok()
}
