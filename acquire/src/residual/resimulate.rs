//! Re-simulation of the recorded takes from their first reconstructed
//! state with a model (core RK4 with the model's effects; added mass
//! through the equations of motion), scored by the RMS position error
//! against the reconstruction over the first [`HORIZON`] seconds: what an
//! effect changes in a trajectory, in metres.

use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::Smoothed;
use nalgebra::Vector3;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Coefficients, Environment, RigidBody};

/// Seconds of each take re-simulated.
pub const HORIZON: f64 = 0.5;

/// RK4 steps per frame interval.
const SUBSTEPS: usize = 10;

/// RMS position error (m) over every take's first [`HORIZON`] s of
/// `model` in air moving at `wind` (world, m/s), against `rec`; `None`
/// when the body is not valid.
pub fn position_rms(
    set: &RecordingSet,
    rec: &[Smoothed],
    model: &Coefficients<f64>,
    wind: Vector3<f64>,
) -> Option<f64> {
    let body = RigidBody::new(set.object.mass, set.object.inertia).ok()?;
    let env = Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind,
    };
    let forces = AirForces {
        model,
        environment: env,
    };
    let (mut sum, mut n) = (0.0, 0usize);
    for r in rec {
        let (Some(&t0), Some(&start)) = (r.times.first(), r.states.first()) else {
            continue;
        };
        let mut s = start;
        let mut t = t0;
        for (time, truth) in r.times.iter().zip(&r.states).skip(1) {
            if time - t0 > HORIZON {
                break;
            }
            let dt = (time - t) / SUBSTEPS as f64;
            for _ in 0..SUBSTEPS {
                s = omniad_core::integrate::rk4_step(&body, &env, &forces, t, dt, &s);
                t += dt;
            }
            t = *time;
            if !s.is_finite() {
                break;
            }
            sum += (s.position - truth.position).norm_squared();
            n += 1;
        }
    }
    (n > 0).then(|| (sum / n as f64).sqrt())
}
