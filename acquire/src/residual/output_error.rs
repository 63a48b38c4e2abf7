//! A held-out frame's force error as the error of the acceleration the
//! model predicts (output error), for a model with added mass.
//!
//! Why: the joint problems compare the measured force `F* = M Rᵀ(v̇ - g)`
//! (eq. 9) with the model's force at the frame. Added mass with its
//! acceleration reaction (`-M_a dV/dt`, Kirchhoff; Lamb 1932 §124) makes
//! that force a function of the frame's *measured* rate, so the residual
//! `r = F* - F_model` is an equation error: the rate's noise `e` enters
//! it twice, `(M I + M_a) e`, and a model with the true M_a is charged
//! for the data's noise more than the base model is. A model predicts a
//! held-out frame from its state: with added mass, eq. (1) reads
//! `(M I + M_a) dV/dt = M Rᵀg - M Ω × V + F_rest`
//! (`omniad_core::rigid_body::state_rate_with_added_mass`), and the error
//! of that prediction in force units is
//! `M (dV/dt - dV/dt_pred) = M (M I + M_a)⁻¹ r`. For a model whose force
//! does not depend on the rate the two are the same number, so only
//! designs with `added_mass` are turned.

use crate::residual::candidates::Candidate;
use crate::residual::problems::Problems;
use nalgebra::{DVector, Matrix3, Vector3};
use omniad_core::effect::{Effect, EffectKind};

/// The turn of `p`'s force residuals under the fold solution `x` of a
/// design whose extra columns are `cols` (`x`: the base unknowns, then one
/// value per column of `cols`): from the added mass the design fits (with
/// any added mass `p` holds). `None`: no added mass, the residual is
/// already the output error; also when the fitted tensor makes no
/// acceleration (`turn`), where the equation error is kept.
pub(crate) fn of_fold(p: &Problems, cols: &[usize], x: &DVector<f64>) -> Option<Matrix3<f64>> {
    let am = p.columns_of(Candidate::Named(EffectKind::AddedMass));
    let fitted = match cols.iter().position(|c| *c == am.start) {
        Some(j) => {
            let at = p.force.base + j;
            let params: Vec<f64> = (at..at + am.len())
                .map(|i| x.get(i).copied())
                .collect::<Option<_>>()?;
            Effect::new(EffectKind::AddedMass, &params)?.added_mass()?
        }
        None => Matrix3::zeros(),
    };
    let m_a = p.held_added_mass + fitted;
    if m_a == Matrix3::zeros() {
        return None;
    }
    turn(p.mass, &m_a)
}

/// `M (M I + M_a)⁻¹` for mass `mass` (kg) and added mass `added_mass`
/// (kg, body frame): it turns an equation-error force residual (N, body
/// frame) into the output error. `None` when `M I + M_a` is singular or
/// the result not finite (a model that predicts no finite acceleration).
pub(crate) fn turn(mass: f64, added_mass: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let inv = (Matrix3::identity() * mass + added_mass).try_inverse()?;
    let t = inv * mass;
    t.iter().all(|v| v.is_finite()).then_some(t)
}

/// Residual `r` in the fit's basis `basis` (columns: the basis' vectors
/// in the body frame, as `fit::force::ForceRow::basis`) turned by `t`
/// (body frame), back in the basis: `Bᵀ t B r`.
pub(crate) fn in_basis(basis: &Matrix3<f64>, t: &Matrix3<f64>, r: &Vector3<f64>) -> Vector3<f64> {
    basis.transpose() * (t * (basis * r))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame moved by the true model with added mass, its measured rate
    /// off by `e`: the equation error of the true model is
    /// `(M I + M_a) e`, its output error `M e` (the target's own noise,
    /// which the base model's residual carries as well).
    #[test]
    fn the_true_model_is_charged_only_the_targets_noise() {
        let mass = 0.04;
        let m_a = Matrix3::new(0.006, 0.0005, 0.0, 0.0005, 0.004, 0.0, 0.0, 0.0, 0.014);
        let e = Vector3::new(0.7, -1.2, 2.0);
        let equation_error = (Matrix3::identity() * mass + m_a) * e;
        let t = turn(mass, &m_a).unwrap_or_else(Matrix3::zeros);
        assert!(((t * equation_error) - e * mass).norm() < 1e-12);
        // The same in any orthonormal basis.
        let basis = nalgebra::Rotation3::from_euler_angles(0.3, -0.8, 1.1).into_inner();
        let r = basis.transpose() * equation_error;
        let back = basis * in_basis(&basis, &t, &r);
        assert!((back - e * mass).norm() < 1e-12, "{back:?}");
        // No added mass: the residual is unchanged.
        let id = turn(mass, &Matrix3::zeros()).unwrap_or_else(Matrix3::zeros);
        assert!((id - Matrix3::identity()).norm() < 1e-12);
        // An added mass that cancels the body's: no finite prediction.
        assert!(turn(mass, &(Matrix3::identity() * -mass)).is_none());
    }
}
