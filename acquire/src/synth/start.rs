//! Initial states of synthetic takes: the paper's two kinds of motion (§6,
//! "two types of motion are captured"): drops from about 6 m (K1, linear
//! velocity dominant) and throws by hand at 1 m with a rotating motion
//! (K2, angular velocity dominant), world frame (z up), SI units.

use crate::error::{Error, Result};
use crate::rng::Rng;
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::State;

/// The largest release speed `--throw-speed` accepts, m/s: a hard
/// overarm throw of a light object by hand.
pub const MAX_THROW_SPEED: f64 = 15.0;

/// Elevation of a throw's release velocity above the horizon, degrees:
/// "thrown in the air" (§6), upward and sideways.
const THROW_ELEVATION_DEG: (f64, f64) = (45.0, 90.0);

/// A throw's release speed range, m/s (the world-frame speed of the body's
/// centre when it leaves the hand at 1 m, uniform in `[min, max]`), its
/// direction 45-90° above the horizon at any azimuth.
///
/// Why: a light body quickly slows to its terminal speed (the plate's
/// drag length `m / (½ρ C A)` is about 0.5 m broadside), so drops fly each
/// body-frame direction at nearly one speed, and a force linear in the
/// air speed is then nearly `|V|²` times a direction's constant, which
/// the SH force coefficients absorb (eq. 6; BENCHMARKS.md issue 15, stop
/// 17). Throws released at several speeds sweep each direction (the body
/// spins at 12-20 rad/s) over a range of speeds while they slow down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThrowSpeed {
    /// Slowest release, m/s.
    pub min: f64,
    /// Fastest release, m/s.
    pub max: f64,
}

impl ThrowSpeed {
    /// A range `0 <= min <= max <= MAX_THROW_SPEED`, both finite.
    pub fn new(min: f64, max: f64) -> Result<Self> {
        if !(min.is_finite() && max.is_finite() && 0.0 <= min && min <= max) {
            return Err(Error::Data(format!(
                "throw speed: need 0 <= MIN <= MAX (m/s), found {min}, {max}"
            )));
        }
        if max > MAX_THROW_SPEED {
            return Err(Error::Data(format!(
                "throw speed: MAX {max} m/s is above {MAX_THROW_SPEED} m/s (a hard throw by hand)"
            )));
        }
        Ok(Self { min, max })
    }

    /// A release velocity, world frame, m/s.
    fn velocity(&self, rng: &mut Rng) -> Vector3<f64> {
        let speed = rng.range(self.min, self.max);
        let (lo, hi) = THROW_ELEVATION_DEG;
        let elevation = rng.range(lo, hi).to_radians();
        let azimuth = rng.range(0.0, std::f64::consts::TAU);
        let h = elevation.cos();
        Vector3::new(h * azimuth.cos(), h * azimuth.sin(), elevation.sin()) * speed
    }
}

/// A random start: drops from about 6 m, throws from 1 m spinning (at
/// 12-20 rad/s; released at 3-4 m/s upward, ±0.5 m/s sideways, unless a
/// `throw` speed range is given).
pub fn random_start(rng: &mut Rng, spin: bool, throw: Option<&ThrowSpeed>) -> State<f64> {
    let q =
        UnitQuaternion::from_scaled_axis(rng.direction() * rng.range(0.0, std::f64::consts::PI));
    if spin {
        let position = Vector3::new(
            rng.range(-0.3, 0.3),
            rng.range(-0.3, 0.3),
            rng.range(0.9, 1.1),
        );
        let velocity = match throw {
            Some(t) => t.velocity(rng),
            None => Vector3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(3.0, 4.0),
            ),
        };
        State {
            position,
            orientation: q,
            velocity,
            angular_velocity: rng.direction() * rng.range(12.0, 20.0),
        }
    } else {
        State {
            position: Vector3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.4, 0.4),
                rng.range(5.6, 6.4),
            ),
            orientation: q,
            velocity: rng.direction() * rng.range(0.0, 0.5),
            angular_velocity: rng.direction() * rng.range(0.0, 2.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_throw_leaves_the_hand_upward_within_its_speed_range() {
        let t = ThrowSpeed::new(5.0, 8.0).expect("range");
        let mut rng = Rng::new(3);
        for _ in 0..200 {
            let s = random_start(&mut rng, true, Some(&t));
            let v = s.velocity;
            assert!((5.0..=8.0).contains(&v.norm()), "speed {}", v.norm());
            let elevation = (v.z / v.norm()).asin().to_degrees();
            assert!((45.0..=90.0).contains(&elevation), "elevation {elevation}");
        }
    }

    #[test]
    fn without_a_speed_range_a_throw_is_the_default_sets_one() {
        let mut rng = Rng::new(3);
        for _ in 0..200 {
            let v = random_start(&mut rng, true, None).velocity;
            assert!((3.0..=4.0).contains(&v.z), "vz {}", v.z);
            assert!(v.x.abs() <= 0.5 && v.y.abs() <= 0.5, "sideways {v:?}");
        }
    }

    #[test]
    fn impossible_throw_speeds_are_refused() {
        assert!(ThrowSpeed::new(3.0, 2.0).is_err());
        assert!(ThrowSpeed::new(-1.0, 2.0).is_err());
        assert!(ThrowSpeed::new(1.0, f64::NAN).is_err());
        assert!(ThrowSpeed::new(1.0, MAX_THROW_SPEED + 1.0).is_err());
        assert!(ThrowSpeed::new(0.0, 0.0).is_ok());
    }
}
