//! The paper's Fig. 12: one release of a body (no initial velocity, a
//! tilted start) under each model of [`omniad_core::model`], and the
//! descriptors that tell the motions apart, measured from the trajectory.

use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::integrate::rk4_step;
use omniad_core::model::Model;
use omniad_core::{Environment, RigidBody, State};
use serde::Serialize;

/// RK4 step, s.
pub const DT: f64 = 1e-3;
/// Trajectory sample interval, s (60 Hz, a camera's).
pub const SAMPLE: f64 = 1.0 / 60.0;
/// Release height, m, and the fall measured.
pub const HEIGHT: f64 = 5.0;
/// Simulated time at most, s.
pub const MAX_TIME: f64 = 20.0;

/// The release: at rest `HEIGHT` m up, tilted 20° about body y (the chord
/// x tilts), so that gliding, if any, is in the x-z plane.
pub fn start() -> State<f64> {
    State {
        orientation: UnitQuaternion::from_scaled_axis(Vector3::y() * 20f64.to_radians()),
        ..State::at_rest(Vector3::new(0.0, 0.0, HEIGHT))
    }
}

/// Runs a release under `model` until the ground (z = 0) or `MAX_TIME`;
/// samples `(t, state)` every `SAMPLE` s (the landing included).
pub fn run(
    model: &Model<'_>,
    body: &RigidBody<f64>,
    env: &Environment<f64>,
) -> Vec<(f64, State<f64>)> {
    let mut s = start();
    let every = (SAMPLE / DT).round() as usize;
    let mut out = vec![(0.0, s)];
    let steps = (MAX_TIME / DT) as usize;
    for k in 1..=steps {
        s = rk4_step(body, env, model, (k - 1) as f64 * DT, DT, &s);
        let t = k as f64 * DT;
        let landed = s.position.z <= 0.0 || !s.is_finite();
        if k % every == 0 || landed {
            out.push((t, s));
        }
        if landed {
            break;
        }
    }
    out
}

/// What tells the motions apart (computed from the samples).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Descriptors {
    /// Horizontal distance from the release point at landing, m.
    pub glide_m: f64,
    /// Sign changes of the body normal's (body +z) vertical component: flips.
    pub flips: usize,
    /// Largest tilt of the body plane from horizontal, `acos |n_z|`, deg
    /// (0 flat, 90 edge-on).
    pub max_tilt_deg: f64,
    /// Time to fall `HEIGHT` m, s (interpolated; None if it did not land).
    pub fall_time_s: Option<f64>,
    /// Mean descent speed, `HEIGHT / fall_time`, m/s.
    pub mean_descent_m_s: Option<f64>,
}

/// The descriptors of a release trajectory.
pub fn descriptors(traj: &[(f64, State<f64>)]) -> Descriptors {
    let normal_z = |s: &State<f64>| (s.orientation * Vector3::z()).z;
    let mut flips = 0;
    let mut max_tilt: f64 = 0.0;
    for w in traj.windows(2) {
        if let [(_, a), (_, b)] = w {
            if normal_z(a).signum() != normal_z(b).signum() {
                flips += 1;
            }
        }
    }
    for (_, s) in traj {
        max_tilt = max_tilt.max(normal_z(s).abs().min(1.0).acos().to_degrees());
    }
    let fall = traj.windows(2).find_map(|w| match w {
        [(ta, a), (tb, b)] if a.position.z > 0.0 && b.position.z <= 0.0 => {
            let f = a.position.z / (a.position.z - b.position.z);
            Some(ta + f * (tb - ta))
        }
        _ => None,
    });
    let end = traj.last().map(|(_, s)| s.position).unwrap_or_default();
    Descriptors {
        glide_m: (end.xy() - start().position.xy()).norm(),
        flips,
        max_tilt_deg: max_tilt,
        fall_time_s: fall,
        mean_descent_m_s: fall.map(|t| HEIGHT / t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use omniad_core::rigid_body::NoForces;

    #[test]
    fn vacuum_falls_straight_in_the_free_fall_time() {
        let body = RigidBody::new(0.048, nalgebra::Matrix3::identity() * 1e-3).unwrap();
        let env = Environment::vacuum();
        let d = descriptors(&run(&Model::Vacuum(NoForces), &body, &env));
        let t = (2.0 * HEIGHT / 9.81f64).sqrt();
        assert!((d.fall_time_s.unwrap() - t).abs() < 1e-5, "{d:?}");
        assert!(d.glide_m < 1e-12 && d.flips == 0 && (d.max_tilt_deg - 20.0).abs() < 1e-9);
    }
}
