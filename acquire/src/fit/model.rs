//! Building a core [`Coefficients`] from fitted numbers, and the zero model
//! of the first refinement iteration (§6: `A_0 = 0, B_0 = 0`).

use crate::error::{Error, Result};
use crate::fit::smoothing::Smoothing;
use crate::input::recording::Object;
use omniad_core::coefficients::MassProperties;
use omniad_core::sh::{coeff_count, MAX_DEGREE};
use omniad_core::spin_coupling::SpinCoupling;
use omniad_core::Coefficients;

/// The fitted numbers (body frame, non-dimensional).
#[derive(Clone, Debug, PartialEq)]
pub struct RawModel {
    /// `alpha[i][k]`, i = basis component, k = SH index.
    pub alpha: [Vec<f64>; 3],
    /// `beta[i][k]`.
    pub beta: [Vec<f64>; 3],
    /// `[d11, d22, d33, d12, d13, d23]`.
    pub damping: [f64; 6],
    /// The spin-coupling extension, when fitted and kept.
    pub spin_coupling: Option<SpinCoupling<f64>>,
    /// The gravity-coupling extension, when fitted and kept.
    pub gravity_coupling: Option<omniad_core::gravity_coupling::GravityCoupling<f64>>,
    /// The held-out test that decided on them (when it was run).
    pub extension_test: Option<crate::fit::extensions::ExtensionTest>,
    /// The smoothness penalties of the force and torque fits (least
    /// squares only).
    pub smoothing: Option<FitSmoothing>,
}

/// The smoothness penalties a least-squares fit used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSmoothing {
    /// Of alpha (`crate::fit::force::force_smoothing`).
    pub force: Smoothing,
    /// Of beta (`crate::fit::torque::torque_smoothing`).
    pub torque: Smoothing,
}

fn model_error(e: omniad_core::ModelError) -> Error {
    Error::Data(format!("cannot build the coefficient model: {e}"))
}

/// The zero model of degree `degree` for `object`.
pub fn zero_model(object: &Object, degree: u8) -> Result<Coefficients<f64>> {
    let mut m =
        Coefficients::zeros(degree, object.pole, object.reference_length).map_err(model_error)?;
    let name: String = object
        .name
        .chars()
        .scan(0, |n, c| {
            *n += c.len_utf8();
            (*n <= omniad_core::coefficients::NAME_CAPACITY).then_some(c)
        })
        .collect();
    m.set_name(&name).map_err(model_error)?;
    // The file stores the symmetric part (the recording's reader checks
    // the inertia is symmetric to 1e-9; a recording's usual exactly
    // symmetric tensor is stored bit for bit).
    m.body = Some(MassProperties {
        mass: object.mass,
        inertia: omniad_core::math::six_from_symmetric(&object.inertia),
    });
    Ok(m)
}

/// `raw` written into a copy of `base` (degree, pole, L, name, body).
pub fn with_raw(base: &Coefficients<f64>, raw: &RawModel) -> Result<Coefficients<f64>> {
    let mut m = with_torque(base, &raw.beta, &raw.damping)?;
    for i in 0..3 {
        for (k, v) in raw.alpha[i].iter().enumerate().take(m.coeff_count()) {
            m.set_alpha(i, k, *v).map_err(model_error)?;
        }
    }
    m.set_spin_coupling(raw.spin_coupling)
        .map_err(model_error)?;
    m.set_gravity_coupling(raw.gravity_coupling)
        .map_err(model_error)?;
    Ok(m)
}

/// A copy of `base` with the torque part of eqs. (6), (8) replaced:
/// `beta[i][k]` (basis component i, SH index k; the torque degree N_T is
/// the one whose `(N_T+1)²` is the blocks' length) and D as
/// `[d11, d22, d33, d12, d13, d23]`.
pub fn with_torque(
    base: &Coefficients<f64>,
    beta: &[Vec<f64>; 3],
    damping: &[f64; 6],
) -> Result<Coefficients<f64>> {
    let count = beta[0].len();
    let degree = (0..=MAX_DEGREE)
        .find(|&d| coeff_count(d) == count)
        .filter(|_| beta.iter().all(|b| b.len() == count))
        .ok_or_else(|| {
            Error::Data(format!(
                "torque blocks of {:?} coefficients are no SH degree's",
                beta.each_ref().map(Vec::len)
            ))
        })?;
    let mut m = base
        .with_torque_degree(u8::try_from(degree).unwrap_or(u8::MAX))
        .map_err(model_error)?;
    for (i, block) in beta.iter().enumerate() {
        for (k, v) in block.iter().enumerate() {
            m.set_beta(i, k, *v).map_err(model_error)?;
        }
    }
    m.set_damping(&crate::fit::damping::matrix(damping))
        .map_err(model_error)?;
    Ok(m)
}
