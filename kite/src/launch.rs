//! The launch: where a flight starts. A flyer lets go of a kite that has
//! settled on its line, so `kite fly` (and the TUI) start the kite at rest
//! at the equilibrium of the flight model in the wind that blows at the
//! moment of release, `w(0) = U x̂ + u(0)` ([`crate::wind`]) — not at the
//! file's attitude, and not at the equilibrium in the mean wind `U x̂`.
//!
//! Why the equilibrium: started at the file's attitude, a kite whose
//! equilibrium lies tens of degrees away (a re-pitched or re-bridled
//! variant) first swings through a large transient that the linear
//! analysis does not describe, and a low-hanging kite could hit the ground
//! on that swing alone. The verdict is a statement about small motions
//! about the equilibrium; a flight started there tests exactly that
//! statement against the gusts.
//!
//! Why in the wind at `t = 0`: the gust is a stationary random process
//! (random-phase sum of sinusoids, Shinozuka & Deodatis 1991), so at the
//! release it is already `u(0) ~ N(0, diag(σ_u², σ_v², σ_w²))`, not zero.
//! A kite at rest in the mean-wind equilibrium feels that whole gust as a
//! step at `t = 0` — a change the spectrum (no energy above 5 Hz) does not
//! contain: seed 1 starts fig15-c with its string 10 cm lower 1.75 m/s
//! into a lull, and the line tension fell from 11.2 to 1.4 N in 0.5 s.
//! Resting in the wind of the release, the kite's acceleration is zero
//! at `t = 0` and from then on it sees only the gusts' own change.
//!
//! How: the equilibrium the kite settles to in the mean wind
//! (`crate::settle`, the state the verdict's static and dynamic tests are
//! taken about) is followed along the steady winds `U x̂ + λ u(0)`, λ from
//! 0 to 1 ([`crate::equilibrium::follow`]), so the kite stays on its
//! branch. When the kite has no equilibrium in `w(0)` on that branch (a
//! lull below the wind it flies in, or a gust past a fold of the branch —
//! fig15-c with its string 10 cm lower sinks from 45° at 5 m/s to 31° 1
//! m/s above it and has none beyond +1.27 m/s, and seed 10 starts 2.3 m/s
//! above), it starts at the last equilibrium reached, in the wind `U x̂ +
//! c`, and the gusts are those of the same seed given that the gust at `t
//! = 0` was `c` ([`crate::wind::Wind::conditioned`]): the flyer lets go at
//! a moment when the wind is one the kite can rest in. Either way no step.
//! A kite with no equilibrium in the mean wind (`no_equilibrium`) is
//! released at the file's attitude on a taut line, as before.

use crate::assemble::Design;
use crate::equilibrium::follow;
use crate::flight_step::{Flight, FlightOptions};
use crate::settle::settled_equilibrium;
use anyhow::Result;

/// The flight of `design` in the wind of `opts`, released at rest at its
/// equilibrium in the wind at `t = 0` (or at the file's attitude when it
/// has no equilibrium in the mean wind).
pub fn launch(design: &Design, opts: &FlightOptions) -> Result<Flight> {
    let mut flight = Flight::new(design.clone(), opts)?;
    let steady = Flight::new(
        design.clone(),
        &FlightOptions {
            gust: 0.0,
            ..opts.clone()
        },
    )?;
    if let Some(eq) = settled_equilibrium(&steady) {
        let wind = flight.wind_now();
        let (start, reached) = follow(&steady, &eq, &wind);
        if reached != wind {
            flight.condition_gust(reached - steady.wind_model().mean);
        }
        flight.release_at(start.state);
    }
    Ok(flight)
}
