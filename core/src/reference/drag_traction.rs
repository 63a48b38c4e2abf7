//! The drag-and-traction comparison model (Wejchert & Haumann 1991,
//! "Animation aerodynamics"; the OmniAD paper's Fig. 12, green): every
//! surface element feels the air independently, a pressure drag along its
//! normal proportional to its area and to the square of the normal
//! component of its air-relative velocity, and a tangential traction
//! (friction) against the in-plane component. No lift and no centre of
//! pressure: translation alone gives no torque on a symmetric shape (the
//! paper: "ignores lift force and torque"); rotation is damped because
//! each element moves with its own velocity `V + Ω × r`.
//!
//! Per element (area `dA`, outward normal `n`, body frame, `u` its
//! velocity relative to the air, `u_n = u·n`, `u_t = u - u_n n`):
//! `dF = -½ρ C_N dA |u_n| u_n n - ½ρ C_f dA |u_t| u_t` (N), at the
//! element; a one-sided face (a box) feels the normal part only when it
//! moves into the air (`u_n > 0`). `C_N` and `C_f` are the panel model's
//! broadside and skin-friction coefficients ([`super::panel`]), so the two
//! agree for a plate falling flat.

use super::panel::{FRICTION_COEFFICIENT, NORMAL_COEFFICIENT_90};
use super::shape::{Element, Shape};
use crate::aero::Wrench;
use crate::rigid_body::{Environment, Forces, State};
use nalgebra::Vector3;

/// Per-element drag and traction for one shape in one environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DragTraction {
    /// The surface.
    pub shape: Shape,
    /// ρ and wind.
    pub environment: Environment<f64>,
}

/// The force (N, body frame) on one element moving at `u` (m/s, body
/// frame, relative to the air) in air of density `rho`.
pub fn element_force(e: &Element, u: &Vector3<f64>, rho: f64) -> Vector3<f64> {
    let un = u.dot(&e.normal);
    let ut = u - e.normal * un;
    let q = 0.5 * rho * e.area;
    let pressure = if e.two_sided || un > 0.0 {
        -e.normal * (q * NORMAL_COEFFICIENT_90 * un.abs() * un)
    } else {
        Vector3::zeros()
    };
    pressure - ut * (q * FRICTION_COEFFICIENT * ut.norm())
}

impl Forces<f64> for DragTraction {
    fn wrench(&self, _t: f64, state: &State<f64>) -> Wrench<f64> {
        let v = state.air_velocity_body(&self.environment.wind);
        let rho = self.environment.air_density;
        let (force, torque) = self
            .shape
            .element_wrench(&v, &state.angular_velocity, |e, u| element_force(e, u, rho));
        Wrench { force, torque }
    }
}
