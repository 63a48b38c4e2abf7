//! Filter state and error-state arithmetic.
//!
//! The filter estimates the rigid-body [`State`] plus the part of the air's
//! force and torque that the current OmniAD model does not explain (a
//! random-walk "bias", body frame): early in the refinement (§6) the model
//! is zero and the whole aerodynamic wrench is carried by the bias.
//! Error state `δ = (δy, δθ, δv, δΩ, δF, δT)` (m, rad, m/s, rad/s, N, N m)
//! with `q ⊕ δθ = q ⊗ exp(δθ)` (δθ in the body frame).

use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};
use omniad_core::State;

/// Error-state dimension.
pub const N: usize = 18;
/// An error-state vector.
pub type Delta = SVector<f64, N>;
/// An error-state covariance or Jacobian.
pub type Cov = SMatrix<f64, N, N>;

/// Rigid-body state and unexplained wrench.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterState {
    /// Rigid-body state.
    pub body: State<f64>,
    /// Unexplained air force, body frame, N.
    pub force: Vector3<f64>,
    /// Unexplained air torque, body frame, N m.
    pub torque: Vector3<f64>,
}

impl FilterState {
    /// A state with zero bias.
    pub fn new(body: State<f64>) -> Self {
        Self {
            body,
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
        }
    }
}

fn part(d: &Delta, i: usize) -> Vector3<f64> {
    Vector3::new(d[3 * i], d[3 * i + 1], d[3 * i + 2])
}

/// `s ⊕ δ`.
pub fn boxplus(s: &FilterState, d: &Delta) -> FilterState {
    let b = &s.body;
    FilterState {
        body: State {
            position: b.position + part(d, 0),
            orientation: b.orientation * UnitQuaternion::from_scaled_axis(part(d, 1)),
            velocity: b.velocity + part(d, 2),
            angular_velocity: b.angular_velocity + part(d, 3),
        },
        force: s.force + part(d, 4),
        torque: s.torque + part(d, 5),
    }
}

/// `a ⊖ b`, so that `b ⊕ (a ⊖ b) = a`.
pub fn boxminus(a: &FilterState, b: &FilterState) -> Delta {
    let (x, y) = (&a.body, &b.body);
    let dq = (y.orientation.inverse() * x.orientation).scaled_axis();
    let parts = [
        x.position - y.position,
        dq,
        x.velocity - y.velocity,
        x.angular_velocity - y.angular_velocity,
        a.force - b.force,
        a.torque - b.torque,
    ];
    let mut d = Delta::zeros();
    for (i, p) in parts.iter().enumerate() {
        d.fixed_rows_mut::<3>(3 * i).copy_from(p);
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxminus_inverts_boxplus() {
        let s = FilterState {
            body: State {
                position: Vector3::new(1.0, 2.0, 3.0),
                orientation: UnitQuaternion::from_euler_angles(0.3, -0.2, 1.0),
                velocity: Vector3::new(0.1, 0.2, -3.0),
                angular_velocity: Vector3::new(4.0, -1.0, 0.5),
            },
            force: Vector3::new(0.1, 0.2, 0.3),
            torque: Vector3::new(-0.01, 0.0, 0.02),
        };
        let d =
            Delta::from_fn(|i, _| 0.01 * (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -1.0 });
        let back = boxminus(&boxplus(&s, &d), &s);
        assert!((back - d).norm() < 1e-12);
    }
}
