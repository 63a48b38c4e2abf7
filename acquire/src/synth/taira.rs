//! The measured plate: a synthetic plate whose lift and drag follow the
//! Taira et al. (2007) flat-plate measurements
//! ([`omniad_core::reference::taira`]) instead of the panel model, so that
//! a fit from its marker tracks can be compared with measured curves (the
//! paper's Fig. 13).
//!
//! The direction function (body frame, plate normal `n = +z`, `E` the unit
//! air-relative velocity, `α = asin |E·n|`, `t̂` the unit in-plane part of
//! `E`, A the planform area, L the reference length):
//! * force `C_F(E) = (A/L²)(-sign(E·n) C_N(α) n - C_A(α) t̂)`, with
//!   `C_N`, `C_A` from the measured `C_D`, `C_L`
//!   ([`omniad_core::reference::taira::normal_and_axial`]) — its drag
//!   `-C_F·E` and lift are the measured ones at every heading;
//! * the normal force acts at the panel model's centre of pressure,
//!   `½ h cos α` ahead of the centre along `t̂` (`h` the half-extent along
//!   `t̂`: quarter chord edge-on, mid chord broadside), the chordwise
//!   force at the centre: `C_T(E) = (A/L³)(r_cp × (-sign(E·n) C_N n))`;
//! * rotation damping D: the panel model's (eq. 12).
//!
//! Extension to the whole sphere by the plate's symmetries: the curves
//! depend on α only, so both faces (`±n`) and every in-plane heading share
//! them. The measured plate has aspect ratio 2 along the flow at Re 100;
//! the synthetic plate is 30 x 50 cm (1.67) and falls at Re ~ 10⁵: the
//! aspect ratio's and the Reynolds number's effects are not modelled.

use super::ObjectSpec;
use crate::error::{Error, Result};
use nalgebra::Vector3;
use omniad_core::reference::taira::normal_and_axial;
use omniad_core::Coefficients;

/// The object's name in `recording.toml`.
pub const NAME: &str = "plate-taira";

/// `(C_F(E), C_T(E))` of the measured plate of extents `size` (m) with
/// reference length `l` (m), for a unit body-frame direction `e`.
pub fn direction_coefficients(
    e: &Vector3<f64>,
    size: &Vector3<f64>,
    l: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let n = Vector3::z();
    let un = e.dot(&n);
    let alpha = un.abs().min(1.0).asin().to_degrees();
    let (cn, ca) = normal_and_axial(alpha);
    let area = size.x * size.y;
    let tangential = e - n * un;
    let t_len = tangential.norm();
    let normal = -n * (un.signum() * cn);
    let (mut force, mut at) = (normal, Vector3::zeros());
    if t_len > 1e-12 {
        let t = tangential / t_len;
        force -= t * ca;
        let half = 0.5 * size.x * t.x.abs() + 0.5 * size.y * t.y.abs();
        at = t * (0.5 * half * t_len);
    }
    (
        force * (area / (l * l)),
        at.cross(&normal) * (area / (l * l * l)),
    )
}

/// The generating coefficient model: the measured plate projected onto SH
/// of `degree` (eqs. 11, 13), with the panel model's damping.
pub fn truth_model(spec: &ObjectSpec, degree: u8) -> Result<Coefficients<f64>> {
    let l = spec.reference_length();
    let mut m = omniad_core::projection::project(degree, spec.pole, l, |e| {
        direction_coefficients(e, &spec.size, l)
    })
    .map_err(|e| Error::Data(format!("projection: {e}")))?;
    m.set_damping(&spec.panels().damping_tensor(l))
        .map_err(|e| Error::Data(format!("damping: {e}")))?;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drag_and_lift_of_the_direction_function_are_the_measured_ones() {
        let size = Vector3::new(0.3, 0.5, 0.02);
        let l = size.norm();
        let k = l * l / (size.x * size.y);
        for deg in [5.0f64, 20.0, 45.0, 80.0] {
            let a = deg.to_radians();
            let e = Vector3::new(a.cos(), 0.0, -a.sin());
            let (cf, _) = direction_coefficients(&e, &size, l);
            let lift_dir = (Vector3::z() + e * a.sin()).normalize();
            let (cd, cl) = omniad_core::reference::taira::drag_lift(deg);
            assert!((-cf.dot(&e) * k - cd).abs() < 1e-9, "drag at {deg}");
            assert!((cf.dot(&lift_dir) * k - cl).abs() < 1e-9, "lift at {deg}");
        }
    }
}
