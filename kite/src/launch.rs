//! The launch: where a flight starts. A flyer lets go of a kite that has
//! settled on its line, so `kite fly` (and the TUI) start the kite at rest
//! at the equilibrium of the flight model in the mean wind that it settles
//! to (`crate::settle`) — the very state the verdict's static and
//! dynamic tests are taken about — not at the file's attitude.
//!
//! Why: started at the file's attitude, a kite whose equilibrium lies tens
//! of degrees away (a re-pitched or re-bridled variant) first swings
//! through a large transient that the linear analysis does not describe,
//! and a low-hanging kite could hit the ground on that swing alone. The
//! verdict is a statement about small motions about the equilibrium; a
//! flight started there tests exactly that statement against the gusts.
//! A kite with no equilibrium (`no_equilibrium`) is released at the file's
//! attitude on a taut line, as before.

use crate::assemble::Design;
use crate::flight_step::{Flight, FlightOptions};
use crate::settle::settled_equilibrium;
use anyhow::Result;

/// The flight of `design` in the wind of `opts`, released at rest at its
/// equilibrium in the mean wind (or at the file's attitude when there is
/// none).
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
        flight.release_at(eq.state);
    }
    Ok(flight)
}
