//! Trim (beyond the paper): the orientation R at which a kite with a fixed
//! attachment point P hangs in balance, `T_kite(R) = 0` (eq. 15 with the
//! string tension from linear equilibrium, eq. 14).
//!
//! Solved by Levenberg-Marquardt on `Θ` (`R ← R exp[Θ]ₓ`) with the
//! Jacobian of [`super::stability::jacobian`]; steps are limited to
//! [`TrimOptions::max_step`] rad so the solver follows the torque field
//! instead of jumping across it.

use super::stability::jacobian;
use super::statics::kite_torque;
use super::{Conditions, Kite, KiteError};
use crate::lanes::LaneScalar;
use crate::math::{lit, norm, Real};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimOptions<T: Real> {
    /// Most iterations.
    pub max_iterations: usize,
    /// Converged when `|T_kite|` is below this, N m.
    pub tolerance: T,
    /// Largest rotation per iteration, rad.
    pub max_step: T,
}

impl<T: Real> Default for TrimOptions<T> {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: lit(1e-7),
            max_step: lit(0.2),
        }
    }
}

/// Result of a trim search from one start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trim<T: Real> {
    /// The best orientation found (R, body -> world).
    pub orientation: UnitQuaternion<T>,
    /// `T_kite` there, body frame, N m.
    pub torque: Vector3<T>,
    /// Iterations used.
    pub iterations: usize,
    /// `|T_kite| < tolerance`.
    pub converged: bool,
}

/// Searches for `T_kite(R) = 0` from `start` with the string attached at
/// `attachment` (body frame, m). Returns the best orientation found and
/// whether it balances; a non-converged result means no trim was found
/// from this start (not necessarily that none exists).
pub fn trim<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    start: &UnitQuaternion<T>,
    attachment: &Vector3<T>,
    options: &TrimOptions<T>,
) -> Result<Trim<T>, KiteError> {
    let mut r = *start;
    let mut torque = kite_torque(kite, conditions, &r, attachment)?;
    let mut damping = lit::<T>(1e-3);
    let mut iterations = 0;
    while iterations < options.max_iterations && !(norm(&torque) < options.tolerance) {
        iterations += 1;
        let j = jacobian(kite, conditions, &r, attachment)?;
        let scale = j.norm().max(lit(1e-12));
        let Some(step) = lm_step(&j, &torque, damping * scale * scale) else {
            damping *= lit(10.0);
            continue;
        };
        let step = clamp(step, options.max_step);
        let candidate = r * UnitQuaternion::from_scaled_axis(step);
        let t_new = kite_torque(kite, conditions, &candidate, attachment)?;
        if norm(&t_new) < norm(&torque) {
            r = candidate;
            torque = t_new;
            damping = (damping * lit(0.3)).max(lit(1e-9));
        } else {
            damping *= lit(10.0);
            if damping > lit(1e8) {
                break;
            }
        }
    }
    Ok(Trim {
        orientation: r,
        torque,
        iterations,
        converged: norm(&torque) < options.tolerance,
    })
}

/// The Levenberg-Marquardt step `-(JᵀJ + λI)⁻¹ Jᵀ T`.
fn lm_step<T: Real>(j: &Matrix3<T>, torque: &Vector3<T>, lambda: T) -> Option<Vector3<T>> {
    let jt = j.transpose();
    let a = jt * j + Matrix3::identity() * lambda;
    let step = -(a.try_inverse()? * (jt * torque));
    step.iter().all(|x| x.finite()).then_some(step)
}

/// `v` shortened to at most `max` in length.
fn clamp<T: Real>(v: Vector3<T>, max: T) -> Vector3<T> {
    let n = norm(&v);
    if n > max {
        v * (max / n)
    } else {
        v
    }
}
