//! The force and torque pair every model returns (a leaf: the air model,
//! the named effects and the equations of motion all use it).

use crate::math::Real;
use nalgebra::Vector3;

/// A force (N) and torque (N m) pair, both in the body frame unless stated.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Wrench<T: Real> {
    /// Force, N.
    pub force: Vector3<T>,
    /// Torque about the centre of mass, N m.
    pub torque: Vector3<T>,
}

impl<T: Real> Wrench<T> {
    /// The zero wrench.
    pub fn zero() -> Self {
        Self {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
        }
    }
}
