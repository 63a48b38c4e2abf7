//! Re-simulation of the recorded takes, each held out: from its first
//! reconstructed state, with a model fitted without it (core RK4 with the
//! model's effects; added mass through the equations of motion), scored
//! by the RMS position error against the reconstruction over the first
//! [`HORIZON`] seconds: what an effect changes in a trajectory, in metres.
//!
//! Each take is scored too: a plate that flips one way in the
//! re-simulation and the other in the recording makes one take's error
//! ten times the rest, and the set's RMS alone cannot say so.

use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::Smoothed;
use nalgebra::Vector3;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Coefficients, Environment, RigidBody, State};
use serde::Serialize;

/// Seconds of each take re-simulated.
pub const HORIZON: f64 = 0.5;

/// RK4 steps per frame interval (as `omniad synth`).
const SUBSTEPS: usize = 10;

/// Trajectory RMS position error over the first [`HORIZON`] s, m.
#[derive(Clone, Debug, Serialize)]
pub struct Resimulation {
    /// With the base model, over every take's frames.
    pub base_m: f64,
    /// With the extended model, over every take's frames.
    pub extended_m: f64,
    /// Each take re-simulated with both (takes left out, or with no
    /// frame in the horizon under either model, are absent).
    pub takes: Vec<TakeResimulation>,
}

/// One take's trajectory RMS position error over the first [`HORIZON`] s, m.
#[derive(Clone, Debug, Serialize)]
pub struct TakeResimulation {
    /// The take's name.
    pub take: String,
    /// With the base model.
    pub base_m: f64,
    /// With the extended model.
    pub extended_m: f64,
}

/// The models, the air they fly in and the reconstruction they are scored
/// against.
pub struct Run<'a> {
    /// The reconstruction, one per take of the set (empty: left out).
    pub reconstruction: &'a [Smoothed],
    /// The model each take is re-simulated with, one per take of the set
    /// (fitted without it; `None`: the take is not scored).
    pub models: &'a [Option<Coefficients<f64>>],
    /// The air's velocity, world frame, m/s.
    pub wind: Vector3<f64>,
}

/// The base and the extended run scored on every take of `set`; `None`
/// when the body is not valid or no take has a frame in the horizon.
pub fn compare(set: &RecordingSet, base: &Run, extended: &Run) -> Option<Resimulation> {
    let b = take_errors(set, base)?;
    let e = take_errors(set, extended)?;
    let base_m = rms(&b)?;
    let extended_m = rms(&e)?;
    let takes = set
        .takes
        .iter()
        .zip(b.iter().zip(&e))
        .filter_map(|(take, (b, e))| {
            Some(TakeResimulation {
                take: take.name.clone(),
                base_m: rms(std::slice::from_ref(b))?,
                extended_m: rms(std::slice::from_ref(e))?,
            })
        })
        .collect();
    Some(Resimulation {
        base_m,
        extended_m,
        takes,
    })
}

/// Squared position error summed over a take's frames, and their count.
#[derive(Clone, Copy, Default)]
struct Sums {
    squared: f64,
    frames: usize,
}

/// RMS (m) over the frames of `sums`; `None` without frames.
fn rms(sums: &[Sums]) -> Option<f64> {
    let squared: f64 = sums.iter().map(|s| s.squared).sum();
    let frames: usize = sums.iter().map(|s| s.frames).sum();
    (frames > 0).then(|| (squared / frames as f64).sqrt())
}

/// Each take's [`Sums`] of `run` (zero frames for a take left out or
/// without a model); `None` when the body is not valid.
fn take_errors(set: &RecordingSet, run: &Run) -> Option<Vec<Sums>> {
    let body = RigidBody::new(set.object.mass, set.object.inertia).ok()?;
    let env = Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind: run.wind,
    };
    let sums = run.reconstruction.iter().enumerate().map(|(t, r)| {
        let Some(Some(model)) = run.models.get(t) else {
            return Sums::default();
        };
        let forces = AirForces {
            model,
            environment: env,
        };
        take_error(&body, &env, &forces, r)
    });
    Some(sums.collect())
}

/// One take re-simulated from the first state linked over the horizon
/// ([`Smoothed::first_linked_over`]), scored on that chain's frames; the
/// frames after the state stops being finite are not counted.
fn take_error(
    body: &RigidBody<f64>,
    env: &Environment<f64>,
    forces: &AirForces<f64>,
    r: &Smoothed,
) -> Sums {
    let mut sums = Sums::default();
    let Some(k0) = r.first_linked_over(HORIZON) else {
        return sums;
    };
    let (Some(&t0), Some(&start)) = (r.times.get(k0), r.states.get(k0)) else {
        return sums;
    };
    let recorded = r.times.iter().zip(&r.states).enumerate().skip(k0 + 1);
    let recorded: Vec<_> = recorded
        .take_while(|(k, (t, _))| *t - t0 <= HORIZON && r.linked(k0, *k))
        .map(|(_, ts)| ts)
        .collect();
    let times = recorded.iter().map(|(t, _)| **t);
    for (s, (_, truth)) in states_at(body, env, forces, (t0, start), times).zip(&recorded) {
        sums.squared += (s.position - truth.position).norm_squared();
        sums.frames += 1;
    }
    sums
}

/// The states of a body started in `start` (time s, state) at each of
/// `times` (s), [`SUBSTEPS`] RK4 steps between one and the next; a time
/// at or before the last keeps its state. The states end at the first
/// that is not finite. Both the re-simulation and the null replicas
/// (`residual::null`) fly a model this way.
pub(crate) fn states_at<'a>(
    body: &'a RigidBody<f64>,
    env: &'a Environment<f64>,
    forces: &'a AirForces<'a, f64>,
    (t0, start): (f64, State<f64>),
    times: impl Iterator<Item = f64> + 'a,
) -> impl Iterator<Item = State<f64>> + 'a {
    times
        .scan((t0, start), move |(t, s), time| {
            if time > *t {
                let dt = (time - *t) / SUBSTEPS as f64;
                for _ in 0..SUBSTEPS {
                    *s = omniad_core::integrate::rk4_step(body, env, forces, *t, dt, s);
                    *t += dt;
                }
                *t = time;
            }
            Some(*s)
        })
        .take_while(State::is_finite)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 50 g body in gravity with no air, and a zero model.
    fn vacuum() -> (RigidBody<f64>, Environment<f64>, Coefficients<f64>) {
        let body = RigidBody::new(0.05, nalgebra::Matrix3::identity() * 1e-4).unwrap();
        let env = Environment {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            air_density: 0.0,
            wind: Vector3::zeros(),
        };
        (
            body,
            env,
            Coefficients::zeros(2, Vector3::z(), 0.3).unwrap(),
        )
    }

    /// A fall whose epoch 0 is cut off (at rest, the filter's prior) is
    /// re-simulated from epoch 1, exactly; from epoch 0 it would trail the
    /// recording by 3 m/s. A fall whose epochs 0-1 are a chain of their
    /// own (the branch the filter left) is re-simulated from epoch 2.
    #[test]
    fn a_take_is_re_simulated_from_a_chain_that_lasts() {
        let (body, env, model) = vacuum();
        let forces = AirForces {
            model: &model,
            environment: env,
        };
        for cut in [1, 2] {
            let r = crate::reconstruct::forces::tests::fall(40, Some(cut));
            assert_eq!(r.first_linked_over(HORIZON), Some(cut));
            let e = rms(&[take_error(&body, &env, &forces, &r)]).unwrap();
            assert!(e < 1e-9, "cut at {cut}: RMS {e} m");
        }
        let r = crate::reconstruct::forces::tests::fall(40, Some(1));
        let linked = Smoothed {
            cuts: Vec::new(),
            ..r
        };
        assert_eq!(linked.first_linked_over(HORIZON), Some(0));
        // From the prior at rest the fall would be 3 m/s behind: ~0.75 m.
        let from_rest = rms(&[take_error(&body, &env, &forces, &linked)]).unwrap();
        assert!(from_rest > 0.3, "RMS {from_rest} m");
    }

    /// A time at or before the last keeps the state; later ones are
    /// reached by [`SUBSTEPS`] RK4 steps (the fall's `z(t)` to RK4's
    /// exactness on a polynomial); a state that leaves the finite numbers
    /// ends the states.
    #[test]
    fn states_at_each_time_and_none_after_a_non_finite_one() {
        let (body, env, model) = vacuum();
        let forces = AirForces {
            model: &model,
            environment: env,
        };
        let start = State {
            position: Vector3::new(0.0, 0.0, 5.0),
            orientation: nalgebra::UnitQuaternion::identity(),
            velocity: Vector3::new(1.0, 0.0, 0.0),
            angular_velocity: Vector3::zeros(),
        };
        let times = [0.5, 1.0, 1.0, 1.5];
        let s: Vec<_> = states_at(&body, &env, &forces, (1.0, start), times.into_iter()).collect();
        assert_eq!(s.len(), 4);
        assert_eq!(
            (s[0].position, s[1].position),
            (start.position, start.position)
        );
        assert_eq!(s[2].position, start.position);
        let z = 5.0 - 0.5 * 9.81 * 0.25;
        assert!(
            (s[3].position - Vector3::new(0.5, 0.0, z)).norm() < 1e-12,
            "{}",
            s[3].position
        );
        let lost = State {
            velocity: Vector3::new(f64::NAN, 0.0, 0.0),
            ..start
        };
        let s = states_at(&body, &env, &forces, (1.0, lost), times.into_iter());
        assert_eq!(s.count(), 0);
    }
}
