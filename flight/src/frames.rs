//! Reference frames of the flight data (README of the data set):
//! - NED: north-east-down, earth-fixed, origin at the ground station;
//! - FRD: forward-right-down, fixed to the kite (the IMU on its centre
//!   strut). This is the OmniAD body frame of the fitted kite model, as in
//!   the firmware's default model (`firmware-sim/pipeline/src/kite.rs`).
//!
//! Attitude is the 3-2-1 (yaw ψ, pitch θ, roll φ) Euler sequence from NED
//! to FRD, so body -> NED is `R = Rz(ψ) Ry(θ) Rx(φ)`.

use nalgebra::{Rotation3, Vector3};

/// Standard gravity in NED (down), m/s².
pub const GRAVITY_NED: Vector3<f64> = Vector3::new(0.0, 0.0, 9.81);

/// Body (FRD) -> NED rotation from the logged Euler angles, degrees.
pub fn frd_to_ned(roll_deg: f64, pitch_deg: f64, yaw_deg: f64) -> Rotation3<f64> {
    Rotation3::from_euler_angles(
        roll_deg.to_radians(),
        pitch_deg.to_radians(),
        yaw_deg.to_radians(),
    )
}

/// A NED vector in the project's world frame (east, north, up; z up).
pub fn ned_to_enu(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.y, v.x, -v.z)
}

/// The kite's position in NED from the logged position (north, east of
/// the ground station and height above it), m.
pub fn position_ned(north: f64, east: f64, height: f64) -> Vector3<f64> {
    Vector3::new(north, east, -height)
}

/// The body (FRD) velocity relative to the air from the Pitot airspeed
/// (m/s) and the vane's angle of attack (degrees, `α = atan(w/u)` in the
/// symmetry plane), with no sideslip (the flight did not measure it) —
/// the same inputs as the firmware's `air_inputs`.
pub fn air_velocity_frd(airspeed: f64, alpha_deg: f64) -> Vector3<f64> {
    let (s, c) = alpha_deg.to_radians().sin_cos();
    Vector3::new(airspeed * c, 0.0, airspeed * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vector3<f64>, b: Vector3<f64>) -> bool {
        (a - b).norm() < 1e-12
    }

    #[test]
    fn euler_321_maps_the_nose_as_the_readme_says() {
        let x = Vector3::x();
        assert!(
            close(frd_to_ned(0.0, 0.0, 90.0) * x, Vector3::y()),
            "yaw 90: east"
        );
        assert!(
            close(frd_to_ned(0.0, 90.0, 0.0) * x, -Vector3::z()),
            "pitch 90: up"
        );
        let y = Vector3::y();
        assert!(
            close(frd_to_ned(90.0, 0.0, 0.0) * y, Vector3::z()),
            "roll 90: right wing down"
        );
        // The order: yaw last. Pitch 90 then yaw 90 still points the nose up.
        assert!(close(frd_to_ned(0.0, 90.0, 90.0) * x, -Vector3::z()));
        assert!(close(
            frd_to_ned(0.0, 45.0, 90.0) * x,
            Vector3::new(0.0, 1.0, -1.0).normalize()
        ));
    }

    #[test]
    fn ned_and_enu_agree_on_up_and_north() {
        assert_eq!(
            ned_to_enu(&Vector3::new(1.0, 2.0, 3.0)),
            Vector3::new(2.0, 1.0, -3.0)
        );
        assert_eq!(
            position_ned(10.0, 5.0, 200.0),
            Vector3::new(10.0, 5.0, -200.0)
        );
    }

    #[test]
    fn positive_angle_of_attack_means_air_from_below() {
        let v = air_velocity_frd(20.0, 10.0);
        assert!(v.x > 0.0 && v.z > 0.0 && v.y == 0.0);
        assert!((v.norm() - 20.0).abs() < 1e-12);
    }
}
