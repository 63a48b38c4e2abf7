//! The equilibrium a kite on its line settles to in steady wind: the one
//! the verdict judges and the flight is launched from — and, when it has
//! none it can rest at, the bounded motion it ends in.
//!
//! Newton ([`crate::equilibrium`]) finds the equilibrium nearest the
//! file's attitude, but that may be unstable: a kite with a growing mode
//! there does not stay, it turns away and may come to rest at another,
//! stable equilibrium nearby — where it then flies. Judging the saddle called
//! such kites unstable although they fly (box-three-cell with the string
//! 3-10 cm further up: `statically_unstable`, growth +0.6 to +4.7/s, yet
//! settled at 30-40° line elevation in every gusty flight). So when the
//! nearest equilibrium has a growing mode, the kite is let go from it,
//! nudged both ways along that mode, in the steady (gust-free) flight
//! model, long enough for the nudge to grow to the size of the motion
//! ([`run_seconds`]) and then for the span the flight judges. Where it
//! comes to rest (Newton from the end state, converging to a different
//! state whose modes all decay) is the kite's equilibrium. A kite that does
//! not come to rest keeps the nearest equilibrium, and the motion it ended
//! in ([`crate::limit_cycle`]: a limit cycle, or a crash) is reported with
//! it, the worse of the two nudges.

use crate::equilibrium::{equilibrium, Equilibrium};
use crate::flight_step::Flight;
use crate::limit_cycle::{judged_seconds, LimitCycle, Recorder};
use crate::linearise::{eigenvector, perturb, state_matrix, StateMatrix, Tangent};

/// RK4 step of the settling flight, s: the stiffest motion is the line
/// stretch at √(k/M) ≈ 50 rad/s, so ω dt = 0.25, well inside RK4's
/// stability limit (2.8) and accurate enough to say where it comes to rest.
pub(crate) const SETTLE_STEP: f64 = 5e-3;
/// Size of the nudge along the growing mode (largest tangent component:
/// m or rad).
const NUDGE: f64 = 0.02;
/// Time allowed after the nudge has grown to the size of the motion, for
/// the growth to stop (or the kite to come to rest), s.
const SATURATE_SECONDS: f64 = 10.0;
/// Longest growth time allowed, s: a mode growing more slowly than
/// `ln(1/NUDGE)/LONGEST_GROWTH` ≈ 0.04/s barely moves the kite within a
/// `kite fly` run; its judged span then starts after this time.
const LONGEST_GROWTH: f64 = 90.0;

/// Where a kite on its line settles in steady wind.
#[derive(Clone, Debug)]
pub struct Settled {
    /// The equilibrium: stable, or the nearest one when the kite does not
    /// come to rest anywhere.
    pub equilibrium: Equilibrium,
    /// The motion a kite that does not come to rest ends in; `None` when
    /// it rests at [`Settled::equilibrium`].
    pub cycle: Option<LimitCycle>,
}

/// Largest real part of the linearised modes at `eq`, 1/s.
pub fn growth_rate(flight: &Flight, eq: &Equilibrium) -> f64 {
    state_matrix(flight, &eq.state)
        .complex_eigenvalues()
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The time a mode growing at `sigma` (1/s) takes to grow from the nudge
/// to the size of the motion (`e^{σt} NUDGE = 1`), plus
/// [`SATURATE_SECONDS`]; after it the motion is judged for
/// [`judged_seconds`].
pub fn run_seconds(sigma: f64) -> f64 {
    ((1.0 / NUDGE).ln() / sigma.max(f64::MIN_POSITIVE)).min(LONGEST_GROWTH) + SATURATE_SECONDS
}

/// The equilibrium `flight` (steady wind, at its start state) settles to.
pub fn settled_equilibrium(flight: &Flight) -> Option<Equilibrium> {
    settle(flight).map(|s| s.equilibrium)
}

/// Where `flight` (steady wind, at its start state) settles: the nearest
/// equilibrium when it is stable, else a stable one reached from it, else
/// the nearest one with the motion the kite ends in.
pub fn settle(flight: &Flight) -> Option<Settled> {
    let near = equilibrium(flight)?;
    let a = state_matrix(flight, &near.state);
    let Some((sigma, v)) = growing_mode(&a).filter(|(sigma, _)| *sigma >= 0.0) else {
        return Some(Settled {
            equilibrium: near,
            cycle: None,
        });
    };
    let grow = run_seconds(sigma);
    let mut cycle: Option<LimitCycle> = None;
    for sign in [1.0, -1.0] {
        let mut f = flight.clone().with_step(SETTLE_STEP);
        f.release_at(perturb(&near.state, &(v * sign)));
        let start = f.time();
        let mut rec = Recorder::from(start + grow);
        while f.time() < start + grow + judged_seconds() && !f.crashed() {
            f.step();
            rec.record(&f);
        }
        if let Some(eq) = rest(flight, &f, &near) {
            return Some(Settled {
                equilibrium: eq,
                cycle: None,
            });
        }
        let c = rec.finish(&f, f.time() - start);
        cycle = Some(match cycle {
            Some(o) => o.worse(c),
            None => c,
        });
    }
    Some(Settled {
        equilibrium: near,
        cycle,
    })
}

/// A stable equilibrium other than `near` that the run `f` came to rest at.
fn rest(flight: &Flight, f: &Flight, near: &Equilibrium) -> Option<Equilibrium> {
    if f.crashed() {
        return None;
    }
    let eq = equilibrium(f)?;
    let moved = (eq.state.position - near.state.position).norm() > 1e-3
        || eq.state.orientation.angle_to(&near.state.orientation) > 1e-3;
    (moved && growth_rate(flight, &eq) < 0.0).then(|| {
        let turn = flight.state().orientation.angle_to(&eq.state.orientation);
        Equilibrium {
            turn_deg: turn.to_degrees(),
            ..eq
        }
    })
}

/// The fastest-growing mode: its growth rate (1/s) and the real part of
/// its eigenvector (for a complex pair, the oscillation's phase-0 shape),
/// scaled so its largest component is [`NUDGE`].
fn growing_mode(a: &StateMatrix) -> Option<(f64, Tangent)> {
    let eig = a.complex_eigenvalues();
    let l = eig.iter().copied().max_by(|x, y| x.re.total_cmp(&y.re))?;
    let v = eigenvector(a, l).map(|c| c.re);
    let scale = v.amax();
    (scale > 0.0).then(|| (l.re, v * (NUDGE / scale)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flight_step::FlightOptions;
    use crate::spec::StringSpec;
    use crate::{check, Design, Library};
    use omniad_core::rigid_body::State;

    /// box-three-cell pitched 5° nose-up, its string where the file has it
    /// (a variant of issue 17's robustness check with a growing pitch
    /// oscillation).
    fn pitched() -> Flight {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let lib = Library::load(&root.join("data/primitives")).expect("library");
        let mut d = Design::load(&root.join("data/kites/box-three-cell.toml"), &lib).expect("kite");
        let offset = check::check(&d, None).expect("check").attachment_offset;
        d.spec.orientation[1] += 5.0;
        d.spec.string = StringSpec {
            gamma: None,
            offset: Some(offset),
            length: d.spec.string.length,
        };
        let opts = FlightOptions {
            gust: 0.0,
            ..FlightOptions::default()
        };
        Flight::new(d, &opts).expect("flight")
    }

    /// Size of the deviation from `eq` (tangent coordinates, m, rad, m/s,
    /// rad/s).
    fn deviation(eq: &State<f64>, s: &State<f64>) -> f64 {
        let mut t = Tangent::zeros();
        t.fixed_rows_mut::<3>(0)
            .copy_from(&(s.position - eq.position));
        t.fixed_rows_mut::<3>(3)
            .copy_from(&(eq.orientation.inverse() * s.orientation).scaled_axis());
        t.fixed_rows_mut::<3>(6).copy_from(&s.velocity);
        t.fixed_rows_mut::<3>(9).copy_from(&s.angular_velocity);
        t.norm()
    }

    #[test]
    fn the_flight_grows_at_the_linearised_rate() {
        // One owner: the linearisation differentiates the equations the
        // flight integrates, so a small disturbance along the growing mode
        // grows in the nonlinear flight at the mode's rate.
        let flight = pitched();
        let near = equilibrium(&flight).expect("equilibrium");
        let a = state_matrix(&flight, &near.state);
        let (sigma, v) = growing_mode(&a).expect("modes");
        assert!(sigma > 0.05, "a growing mode: sigma {sigma}");
        let mut f = flight.clone().with_step(SETTLE_STEP);
        f.release_at(perturb(&near.state, &(v * 1e-3)));
        // The mode oscillates (period about 2 s): compare the largest
        // deviation over the first and the last 3 s (the envelope).
        let (window, span) = (3.0, 15.0);
        let peak = |f: &mut Flight, until: f64| {
            let mut m: f64 = 0.0;
            while f.time() < until {
                f.step();
                m = m.max(deviation(&near.state, f.state()));
            }
            m
        };
        let first = peak(&mut f, window);
        f.advance_to(span - window);
        let last = peak(&mut f, span);
        let measured = (last / first).ln() / (span - window);
        assert!(
            (measured - sigma).abs() < 0.01 * sigma.max(1.0),
            "flight grows at {measured:+.4}/s, linearisation {sigma:+.4}/s"
        );
    }

    #[test]
    fn a_saturating_mode_ends_on_a_limit_cycle_inside_the_limits() {
        let s = settle(&pitched()).expect("equilibrium");
        let c = s.cycle.expect("no rest: a cycle");
        assert!(c.inside_limits && !c.crashed, "{c:?}");
        assert!(c.elevation_deg[1] - c.elevation_deg[0] > 0.1, "{c:?}");
    }
}
