//! The equilibrium a kite on its line settles to in steady wind: the one
//! the verdict judges and the flight is launched from.
//!
//! Newton ([`crate::equilibrium`]) finds the equilibrium nearest the
//! file's attitude, but that may be a saddle: a kite with a divergent
//! direction there (a positive real eigenvalue of the state matrix) does
//! not stay, it turns away and may come to rest at another, stable
//! equilibrium nearby — where it then flies. Judging the saddle called
//! such kites unstable although they fly (box-three-cell with the string
//! 3-10 cm further up: `statically_unstable`, growth +0.6 to +4.7/s, yet
//! settled at 30-40° line elevation in every gusty flight). So when the
//! nearest equilibrium has a growing mode, the kite is let go from it,
//! nudged both ways along that mode, in the steady (gust-free) flight
//! model for [`SETTLE_SECONDS`]; where it comes to rest (Newton from the
//! end state, converging to a different state whose modes all decay) is
//! the kite's equilibrium. A kite that does not come to rest (it crashes
//! or keeps oscillating: a limit cycle round the unstable equilibrium)
//! keeps the nearest equilibrium, and its verdict names the failing test.

use crate::equilibrium::{equilibrium, Equilibrium};
use crate::flight_step::Flight;
use crate::linearise::{eigenvector, perturb, state_matrix, StateMatrix, Tangent};

/// Steady flight time allowed to settle from a saddle, s.
pub const SETTLE_SECONDS: f64 = 20.0;
/// RK4 step of the settling flight, s: the stiffest motion is the line
/// stretch at √(k/M) ≈ 50 rad/s, so ω dt = 0.25, well inside RK4's
/// stability limit (2.8) and accurate enough to say where it comes to rest.
const SETTLE_STEP: f64 = 5e-3;
/// Size of the nudge along the growing mode (largest tangent component:
/// m or rad).
const NUDGE: f64 = 0.02;

/// Largest real part of the linearised modes at `eq`, 1/s.
pub fn growth_rate(flight: &Flight, eq: &Equilibrium) -> f64 {
    state_matrix(flight, &eq.state)
        .complex_eigenvalues()
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The equilibrium `flight` (steady wind, at its start state) settles to:
/// the nearest one when it is stable, else a stable one reached from it.
pub fn settled_equilibrium(flight: &Flight) -> Option<Equilibrium> {
    let near = equilibrium(flight)?;
    if growth_rate(flight, &near) < 0.0 {
        return Some(near);
    }
    let a = state_matrix(flight, &near.state);
    let v = growing_mode(&a)?;
    for sign in [1.0, -1.0] {
        let mut f = flight.clone().with_step(SETTLE_STEP);
        f.release_at(perturb(&near.state, &(v * sign)));
        f.advance_to(f.time() + SETTLE_SECONDS);
        if f.crashed() {
            continue;
        }
        if let Some(eq) = equilibrium(&f) {
            let moved = (eq.state.position - near.state.position).norm() > 1e-3
                || eq.state.orientation.angle_to(&near.state.orientation) > 1e-3;
            if moved && growth_rate(flight, &eq) < 0.0 {
                let turn = flight.state().orientation.angle_to(&eq.state.orientation);
                return Some(Equilibrium {
                    turn_deg: turn.to_degrees(),
                    ..eq
                });
            }
        }
    }
    Some(near)
}

/// The real part of the fastest-growing mode's eigenvector (for a complex
/// pair, the oscillation's phase-0 shape), scaled so its largest
/// component is [`NUDGE`].
fn growing_mode(a: &StateMatrix) -> Option<Tangent> {
    let eig = a.complex_eigenvalues();
    let l = eig.iter().copied().max_by(|x, y| x.re.total_cmp(&y.re))?;
    let v = eigenvector(a, l).map(|c| c.re);
    let scale = v.amax();
    (scale > 0.0).then(|| v * (NUDGE / scale))
}
