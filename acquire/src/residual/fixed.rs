//! `omniad residual --coeffs FILE`: a given model as the baseline instead
//! of a fitted one. The states (and so the measured forces of eqs. 9-10)
//! are still the refinement's reconstruction: the markers' best estimate,
//! independent of the hypothesis being tested. The given model's
//! alpha, beta, D and any effects it already stores are subtracted from
//! the joint problems' targets ([`crate::fit::joint::Joint::with_fixed_base`]),
//! so each candidate fits only its own parameters on top of the model.
//! Nothing of the baseline is fitted, so its "held-out" error is simply its
//! residual on every take; a candidate's is still leave-one-take-out.

use crate::error::{Error, Result};
use crate::input::recording::RecordingSet;
use crate::residual::candidates::{Candidate, ALL};
use crate::residual::problems::Problems;
use nalgebra::{DVector, Matrix3};
use omniad_core::effect::EffectKind;
use omniad_core::Coefficients;

/// Checks that `model` can be the baseline of `set`: the same pole and
/// reference length as the set's object (the SH directions and the
/// non-dimensionalisation of eqs. 5-8 depend on both), or why not.
pub fn check(model: &Coefficients<f64>, set: &RecordingSet) -> std::result::Result<(), String> {
    let (pole, l) = (set.object.pole.normalize(), set.object.reference_length);
    let mp = model.pole().normalize();
    if (mp - pole).norm() > 1e-6 {
        return Err(format!(
            "its pole [{:.4}, {:.4}, {:.4}] differs from the set's object pole [{:.4}, {:.4}, {:.4}]",
            mp.x, mp.y, mp.z, pole.x, pole.y, pole.z
        ));
    }
    let ml = model.reference_length();
    if (ml - l).abs() > 1e-6 * l.max(1e-9) {
        return Err(format!(
            "its reference length {ml} m differs from the set's object reference_length {l} m"
        ));
    }
    Ok(())
}

/// The parameters `model` stores for candidate `c`, in the candidate's
/// column order (`None`: not stored; a wind is never stored).
pub(crate) fn stored(model: &Coefficients<f64>, c: Candidate) -> Option<Vec<f64>> {
    match c {
        Candidate::Named(kind) => model.effect(kind).map(|e| e.used_params().to_vec()),
        Candidate::Wind => None,
        Candidate::SpinCoupling => model
            .spin_coupling()
            .map(|k| k.k.iter().flat_map(|r| r.iter().copied()).collect()),
        Candidate::GravityCoupling => model
            .gravity_coupling()
            .map(|g| (0..9).map(|i| g.g[(i / 3, i % 3)]).collect()),
    }
}

/// `model`'s force unknowns `(α¹, α², α³)` and torque unknowns `(β¹, β²,
/// β³, d11, d22, d33, d12, d13, d23)` in the joint problems' order.
fn unknowns(model: &Coefficients<f64>) -> Result<(DVector<f64>, DVector<f64>)> {
    let (n, nt) = (model.coeff_count(), model.torque_coeff_count());
    let get = |v: Option<f64>| v.ok_or_else(|| Error::Data("coefficient out of range".into()));
    let mut a = DVector::zeros(3 * n);
    let mut b = DVector::zeros(3 * nt + 6);
    for i in 0..3 {
        for k in 0..n {
            a[i * n + k] = get(model.alpha(i, k))?;
        }
        for k in 0..nt {
            b[i * nt + k] = get(model.beta(i, k))?;
        }
    }
    let six = omniad_core::math::six_from_symmetric(&model.damping());
    for (j, v) in six.into_iter().enumerate() {
        b[3 * nt + j] = v;
    }
    Ok((a, b))
}

/// Holds both problems' base unknowns at `model` (and its stored effects
/// at their values). `p` must be built at `model`'s degrees (N, N_T).
pub(crate) fn hold(p: Problems, model: &Coefficients<f64>) -> Result<Problems> {
    let (a, b) = unknowns(model)?;
    if a.len() != p.force.base || b.len() != p.torque.base {
        return Err(Error::Data(
            "the given model's degrees do not match the analysis's".into(),
        ));
    }
    let mut held = Vec::new();
    for c in ALL {
        if let Some(v) = stored(model, c) {
            held.extend(p.columns_of(c).zip(v));
        }
    }
    let held_added_mass = model
        .effect(EffectKind::AddedMass)
        .and_then(|e| e.added_mass())
        .unwrap_or_else(Matrix3::zeros);
    Ok(Problems {
        force: p.force.with_fixed_base(&a, &held),
        torque: p.torque.with_fixed_base(&b, &held),
        held_added_mass,
        ..p
    })
}
