//! Projection of a direction function onto OmniAD coefficients, eqs. (11)
//! and (13): `alpha^i_lm = ∫ (C_F(E)·E^i) Y_lm(E) dS` and
//! `beta^i_lm = ∫ (C_T(E)·E^i) Y_lm(E) dS`, by the product rule of
//! [`crate::quadrature::sphere_quadrature`] about the model's pole. How
//! reference models (the panel model of [`crate::reference::panel`], the
//! firmware's default kite, the terminal UI's built-in plate) become
//! coefficient models.

use crate::basis::vector_basis;
use crate::coefficients::{Coefficients, ModelError, SETS};
use crate::quadrature::sphere_quadrature;
use crate::rigid_body::{Environment, Forces, State};
use crate::sh::{self, MAX_COEFFS};
use nalgebra::Vector3;

/// Projects `f(E) = (C_F(E), C_T(E))` (body frame, non-dimensional, eqs.
/// 7-8) onto new coefficients of `degree` with the given pole and
/// reference length L (m); D, name, body and provenance are left empty.
pub fn project(
    degree: u8,
    pole: Vector3<f64>,
    reference_length: f64,
    f: impl FnMut(&Vector3<f64>) -> (Vector3<f64>, Vector3<f64>),
) -> Result<Coefficients<f64>, ModelError> {
    let mut model = Coefficients::zeros(degree, pole, reference_length)?;
    project_into(&mut model, f)?;
    Ok(model)
}

/// Writes the projection of `f` (as [`project`]) into alpha and beta of
/// `model`, at its degrees (N and N_T) and about its pole; everything else in `model`
/// is kept.
pub fn project_into(
    model: &mut Coefficients<f64>,
    mut f: impl FnMut(&Vector3<f64>) -> (Vector3<f64>, Vector3<f64>),
) -> Result<(), ModelError> {
    let pole = model.pole();
    let degree = model.basis_degree() as usize;
    let mut sums = [[0.0f64; SETS]; MAX_COEFFS];
    let mut y = [0.0; MAX_COEFFS];
    for (e, w) in sphere_quadrature(&pole) {
        let (cf, ct) = f(&e);
        let [e1, e2, e3] = vector_basis(&e, &pole);
        let proj = [
            cf.dot(&e1),
            cf.dot(&e2),
            cf.dot(&e3),
            ct.dot(&e1),
            ct.dot(&e2),
            ct.dot(&e3),
        ];
        let count = sh::evaluate(degree, &e, &mut y);
        for (row, yk) in sums.iter_mut().zip(y.iter().take(count)) {
            for (s, p) in row.iter_mut().zip(&proj) {
                *s += w * yk * p;
            }
        }
    }
    let (forces, torques) = (model.coeff_count(), model.torque_coeff_count());
    for (k, row) in sums.iter().enumerate().take(forces.max(torques)) {
        let [a1, a2, a3, b1, b2, b3] = *row;
        for (i, (a, b)) in [(a1, b1), (a2, b2), (a3, b3)].into_iter().enumerate() {
            if k < forces {
                model.set_alpha(i, k, a)?;
            }
            if k < torques {
                model.set_beta(i, k, b)?;
            }
        }
    }
    Ok(())
}

/// The steady coefficient functions of any air model `forces` (eqs. 5-8
/// read backwards), projected as [`project`]: at each direction `E` the
/// wrench (body frame) on a body moving at 1 m/s along `E` through the air
/// of `environment` (`V = E`: world velocity `E` plus the wind; `Ω = 0`;
/// the attitude the identity, so body and world frames agree), over
/// `½ρL²` (force) and `½ρL³` (torque). How a comparison model of the
/// paper's Fig. 12 looks on the coefficient sphere; Kirchhoff's steady
/// part is its Munk moment `-V × (M_a V)`. For a wrench quadratic in the
/// speed (every comparison model) the speed does not matter. Left out:
/// the damping (`Ω ≠ 0`), added mass's `-M_a dV/dt` (no function of `E`),
/// and anything the attitude adds (a gravity coupling, buoyancy) at the
/// identity attitude is included as it is there. `environment` must be the
/// one `forces` was built with; its density must be positive and finite.
pub fn project_steady<F: Forces<f64>>(
    forces: &F,
    degree: u8,
    pole: Vector3<f64>,
    reference_length: f64,
    environment: &Environment<f64>,
) -> Result<Coefficients<f64>, ModelError> {
    let rho = environment.air_density;
    if !rho.is_finite() {
        return Err(ModelError::NonFinite("air density"));
    }
    if rho <= 0.0 {
        return Err(ModelError::OutOfRange("air density (must be positive)"));
    }
    let q = 0.5 * rho * reference_length * reference_length;
    project(degree, pole, reference_length, |e| {
        let mut state = State::at_rest(Vector3::zeros());
        state.velocity = e + environment.wind;
        let w = forces.wrench(0.0, &state);
        (w.force / q, w.torque / (q * reference_length))
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn band_limited_function_is_reproduced() {
        // C_F = -E (pure isotropic drag of 1) is exactly alpha^1_00 = -sqrt(4π).
        let m = project(4, Vector3::z(), 1.0, |e| (-e, Vector3::zeros())).unwrap();
        let sqrt_4pi = libm::sqrt(4.0 * core::f64::consts::PI);
        assert!((m.alpha(0, 0).unwrap() + sqrt_4pi).abs() < 1e-10);
        let c = m.at_direction(&Vector3::new(0.2, -0.5, 0.7)).unwrap();
        let e = Vector3::new(0.2, -0.5, 0.7).normalize();
        assert!((c.force + e).norm() < 1e-9, "{:?}", c.force);
    }

    /// The steady coefficients of a wrench given as eqs. (5)-(6) of a known
    /// model are that model's (the scaling by `½ρL²`, `½ρL³` and the
    /// direction convention are right).
    #[test]
    fn steady_projection_gives_back_a_coefficient_model() {
        use crate::rigid_body::AirForces;
        let l = 0.4;
        let model = project(4, Vector3::z(), l, |e| {
            let n = Vector3::z();
            (
                -n * (0.8 * e.dot(&n)) - e * 0.1,
                Vector3::new(0.0, 0.05 * e.x, 0.0),
            )
        })
        .unwrap();
        let environment = Environment {
            air_density: 1.3,
            wind: Vector3::new(2.0, -1.0, 0.5),
            ..Environment::standard()
        };
        let forces = AirForces {
            model: &model,
            environment,
        };
        let back = project_steady(&forces, 4, Vector3::z(), l, &environment).unwrap();
        for e in [Vector3::x(), Vector3::new(0.3, -0.4, 0.8).normalize()] {
            let (a, b) = (
                model.at_direction(&e).unwrap(),
                back.at_direction(&e).unwrap(),
            );
            assert!((a.force - b.force).norm() < 1e-9, "{a:?} vs {b:?}");
            assert!((a.torque - b.torque).norm() < 1e-9, "{a:?} vs {b:?}");
        }
        for rho in [0.0, -1.0, f64::NAN] {
            let air = Environment {
                air_density: rho,
                ..environment
            };
            assert!(project_steady(&forces, 4, Vector3::z(), l, &air).is_err());
        }
    }
}
