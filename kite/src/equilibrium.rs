//! The equilibrium of the tethered kite in steady wind: the position and
//! attitude at which the flight model ([`Flight::rate`]) is at rest
//! (`v = 0`, `Ω = 0`, `v̇ = 0`, `Ω̇ = 0`). Unlike §7's static balance,
//! which holds the attitude at the file's R and asks what string force
//! balances the kite there, here the kite hangs on its line from the
//! file's attachment point and turns until the torque about its centre of
//! mass vanishes: the state the flight settles to, and the one the modes
//! of [`crate::modes`] are taken about.
//!
//! Damped Newton on the six unknowns `(δy, δθ)` with the Jacobian from
//! [`crate::linearise`] (the lower-left block of the state matrix), started
//! from the flight's initial state.
//!
//! [`follow`]: the equilibrium followed from one steady wind to another
//! (natural-parameter continuation: Newton from the last one, in steps of
//! at most [`CONTINUATION_STEP`], halved where Newton fails), so the kite
//! stays on its branch — the same side of the wind, the same attitude
//! family; where the branch ends (a fold: Newton fails at every step
//! down to a sixteenth of it), the last equilibrium reached. The launch
//! ([`crate::launch`]) rests the kite in the wind at `t = 0` with it; the
//! discrete gusts ([`crate::strong_gust`]) ask whether the kite still has
//! an equilibrium in their peak wind.

use crate::flight_step::Flight;
use crate::linearise::{perturb, state_matrix, tangent_rate, Tangent};
use nalgebra::{SMatrix, SVector, Vector3};
use omniad_core::rigid_body::State;

/// Newton iterations before giving up.
const ITERATIONS: usize = 60;
/// Largest attitude change per iteration, rad.
const MAX_TURN: f64 = 0.3;
/// Largest position change per iteration, m.
const MAX_MOVE: f64 = 2.0;
/// Converged when the unbalanced force is below this fraction of the
/// weight and the unbalanced torque below it times weight × radius of
/// gyration.
const TOLERANCE: f64 = 1e-9;

/// Largest change of the steady wind between two continuation steps of
/// [`follow`], m/s: a tenth of the default gusts' 2.5σ range keeps each
/// Newton start within a few degrees of its solution.
pub const CONTINUATION_STEP: f64 = 0.25;
/// Smallest continuation step, as a fraction of [`CONTINUATION_STEP`],
/// before the branch is taken to end.
const SMALLEST_STEP: f64 = 1.0 / 16.0;

/// An equilibrium of the flight model.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// The state at rest (v = 0, Ω = 0).
    pub state: State<f64>,
    /// Line tension there, N.
    pub tension: f64,
    /// Line elevation seen from the anchor, degrees.
    pub elevation_deg: f64,
    /// Attitude change from the file's orientation, degrees.
    pub turn_deg: f64,
}

/// Residual scaled to force units: `(M v̇, I Ω̇ / r_g)`, N.
fn residual(flight: &Flight, s: &State<f64>, r_g: f64) -> SVector<f64, 6> {
    let rate = tangent_rate(flight, s, &Tangent::zeros());
    let b = flight.body();
    let f = rate.fixed_rows::<3>(6) * b.mass;
    let t = b.inertia * rate.fixed_rows::<3>(9) / r_g;
    SVector::<f64, 6>::from_iterator(f.iter().chain(t.iter()).copied())
}

/// Solves for the equilibrium from the flight's current state; `None` when
/// Newton does not converge (no equilibrium near the file's attitude), or
/// it lies with a slack line or below the ground.
pub fn equilibrium(flight: &Flight) -> Option<Equilibrium> {
    let b = flight.body();
    let r_g = (b.inertia.trace() / b.mass).sqrt().max(1e-3);
    let weight = b.mass * 9.81;
    let start = *flight.state();
    let mut s = relax_stretch(
        flight,
        State {
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            ..start
        },
    );
    let mut r = residual(flight, &s, r_g);
    let mut mu = 1e-3;
    for _ in 0..ITERATIONS {
        if r.norm() < TOLERANCE * weight {
            return finish(flight, s, &start);
        }
        let a = state_matrix(flight, &s);
        let mut j = SMatrix::<f64, 6, 6>::zeros();
        for row in 0..3 {
            for col in 0..6 {
                j[(row, col)] = a[(6 + row, col)] * b.mass;
            }
        }
        let scaled = b.inertia * a.fixed_view::<3, 6>(9, 0) / r_g;
        j.fixed_view_mut::<3, 6>(3, 0).copy_from(&scaled);
        let jtj = j.transpose() * j;
        let g = j.transpose() * r;
        let mut accepted = false;
        for _ in 0..12 {
            let mut m = jtj;
            for k in 0..6 {
                m[(k, k)] += mu * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = m.lu().solve(&(-g)) else {
                mu *= 10.0;
                continue;
            };
            let limit = (step.fixed_rows::<3>(0).norm() / MAX_MOVE)
                .max(step.fixed_rows::<3>(3).norm() / MAX_TURN)
                .max(1.0);
            let mut x = Tangent::zeros();
            x.fixed_rows_mut::<6>(0).copy_from(&(step / limit));
            let trial = relax_stretch(flight, perturb(&s, &x));
            let rt = residual(flight, &trial, r_g);
            if rt.norm() < r.norm() {
                s = trial;
                r = rt;
                mu = (mu / 3.0).max(1e-9);
                accepted = true;
                break;
            }
            mu *= 4.0;
        }
        if !accepted {
            break;
        }
        if !r.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    (r.norm() < TOLERANCE * weight * 1e3)
        .then_some(())
        .and_then(|_| finish(flight, s, &start))
}

/// The equilibrium of `steady` (a gust-free flight) in the steady wind
/// `wind` (world frame, m/s), followed from `from`, its equilibrium in
/// the flight's own steady wind, along the winds between the two (module
/// doc); with the wind it is in: `wind`, or the last one reached where
/// the branch ends.
pub fn follow(
    steady: &Flight,
    from: &Equilibrium,
    wind: &Vector3<f64>,
) -> (Equilibrium, Vector3<f64>) {
    let start = steady.wind_model().mean;
    let change = wind - start;
    let full = (CONTINUATION_STEP / change.norm().max(f64::MIN_POSITIVE)).min(1.0);
    let mut f = steady.clone();
    let (mut at, mut done, mut step) = (from.clone(), 0.0, full);
    while done < 1.0 && step >= full * SMALLEST_STEP {
        let next = (done + step).min(1.0);
        let w = if next < 1.0 {
            start + change * next
        } else {
            *wind
        };
        f.set_steady_wind(w);
        f.release_at(at.state);
        match equilibrium(&f) {
            Some(e) => {
                (at, done) = (e, next);
                step = (step * 2.0).min(full);
            }
            None => step /= 2.0,
        }
    }
    let reached = if done < 1.0 {
        start + change * done
    } else {
        *wind
    };
    (at, reached)
}

/// Moves the kite along its line until the line's tension balances the
/// other forces along it. The line is stiff (`k` ≫ the kite's other
/// stiffnesses), so the attitude's second-order effect on the stretch
/// (`|P| δθ²/2`) would otherwise swamp the linear model of each step.
fn relax_stretch(flight: &Flight, mut s: State<f64>) -> State<f64> {
    let line = flight.line();
    for _ in 0..3 {
        let at = s.position + s.orientation.transform_vector(&line.attachment);
        let u = (line.anchor - at).normalize();
        let net = flight.rate(0.0, &s).velocity * flight.body().mass;
        s.position += u * (net.dot(&u) / line.stiffness);
    }
    s
}

fn finish(flight: &Flight, s: State<f64>, start: &State<f64>) -> Option<Equilibrium> {
    let line = flight.line();
    let tension = line.force(&s).norm();
    if !(tension > 0.0) || s.position.z < crate::flight_step::GROUND_CLEARANCE {
        return None;
    }
    Some(Equilibrium {
        state: s,
        tension,
        elevation_deg: line.elevation_deg(&s),
        turn_deg: start.orientation.angle_to(&s.orientation).to_degrees(),
    })
}
