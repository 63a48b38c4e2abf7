//! The simplified-aerodynamics comparison model (Wu & Popović 2003,
//! "Realistic modeling of bird flight animations"; the OmniAD paper's
//! Fig. 12, dark green): every surface element is a small wing with lift
//! and drag coefficients that depend only on its angle of attack, forces
//! at the element (so, as Wejchert & Haumann's, no centre-of-pressure
//! shift and no torque from translation of a symmetric shape).
//!
//! Per element (area `dA`, outward normal `n`, body frame; `u` its
//! velocity relative to the air, `û = u/|u|`, angle of attack
//! `α = asin |û·n|` in [0, 90°]):
//! * drag `-½ρ dA C_D(α) |u| u`, against the motion;
//! * lift `½ρ dA C_L(α) |u|² l̂`, `l̂` the unit vector perpendicular to
//!   `u` in the plane of `u` and `n` on the side opposite `u·n`
//!   (`l̂ ∝ -sign(u·n) (n - (n·û) û)`), so lift and drag together push
//!   the face back as a plate's normal force does.
//!
//! Wu & Popović tabulate empirical `C_L(α)`, `C_D(α)` for feathers; we use
//! the flat-plate curves of the same kind fitted by Wang, Birch &
//! Dickinson (2004, J. Exp. Biol. 207, eq. 2-3), `C_L = 1.2 sin 2α`,
//! `C_D = 1.4 - cos 2α` (0.4 edge-on, 2.4 broadside; Re ~ 10²-10³). A
//! one-sided face (a box) feels air only when it moves into it (`u·n > 0`).

use super::shape::{Element, Shape};
use crate::aero::Wrench;
use crate::rigid_body::{Environment, Forces, State};
use nalgebra::Vector3;

/// `C_L(α)` of Wang et al. (2004), from `sin α`, `cos α`.
pub fn lift_coefficient(sin_a: f64, cos_a: f64) -> f64 {
    1.2 * 2.0 * sin_a * cos_a
}

/// `C_D(α)` of Wang et al. (2004), from `sin α` (`1.4 - cos 2α`).
pub fn drag_coefficient(sin_a: f64) -> f64 {
    1.4 - (1.0 - 2.0 * sin_a * sin_a)
}

/// Per-element angle-of-attack lift and drag for one shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Simplified {
    /// The surface.
    pub shape: Shape,
    /// ρ and wind.
    pub environment: Environment<f64>,
}

/// The force (N, body frame) on one element moving at `u` (m/s, body
/// frame, relative to the air) in air of density `rho`.
pub fn element_force(e: &Element, u: &Vector3<f64>, rho: f64) -> Vector3<f64> {
    let speed = u.norm();
    if !(speed > 0.0) {
        return Vector3::zeros();
    }
    let un = u.dot(&e.normal) / speed;
    if !e.two_sided && un <= 0.0 {
        return Vector3::zeros();
    }
    let sin_a = un.abs().min(1.0);
    let cos_a = libm::sqrt(1.0 - sin_a * sin_a);
    let q = 0.5 * rho * e.area * speed;
    let drag = -u * (q * drag_coefficient(sin_a));
    let across = e.normal - u * (un / speed);
    let len = across.norm();
    let lift = if len > 1e-12 {
        across * (-un.signum() * q * speed * lift_coefficient(sin_a, cos_a) / len)
    } else {
        Vector3::zeros()
    };
    drag + lift
}

impl Forces<f64> for Simplified {
    fn wrench(&self, _t: f64, state: &State<f64>) -> Wrench<f64> {
        let v = state.air_velocity_body(&self.environment.wind);
        let rho = self.environment.air_density;
        let (force, torque) = self
            .shape
            .element_wrench(&v, &state.angular_velocity, |e, u| element_force(e, u, rho));
        Wrench { force, torque }
    }
}
