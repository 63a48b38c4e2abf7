//! The extended model: the base model with alpha refitted jointly with the
//! selected effects (beta and D too when an effect acts on the torque),
//! the named effects stored in the core's `Coefficients::set_effect`, the
//! generic blocks as the spin and gravity couplings. A wind is the
//! recording's, not the body's: it is reported, not stored.

use crate::error::{Error, Result};
use crate::fit::damping::{matrix, with_floor};
use crate::residual::candidates::{Candidate, CouplingSplit};
use crate::residual::problems::Problems;
use crate::residual::select::design_columns;
use nalgebra::{DVector, Matrix3, Vector3};
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::gravity_coupling::GravityCoupling;
use omniad_core::spin_coupling::SpinCoupling;
use omniad_core::Coefficients;

fn model_error(e: omniad_core::ModelError) -> Error {
    Error::Data(format!("cannot build the extended model: {e}"))
}

/// What the joint fit of a design on all takes gives.
pub struct Extended {
    /// The model.
    pub model: Coefficients<f64>,
    /// The wind, when selected (world frame, m/s).
    pub wind: Option<Vector3<f64>>,
    /// Each selected candidate's parameters.
    pub params: Vec<(Candidate, Vec<f64>)>,
}

/// Alpha (and beta, D when `refit_torque`) from the joint solutions.
fn with_coefficients(
    base: &Coefficients<f64>,
    force: &DVector<f64>,
    torque: Option<&DVector<f64>>,
    damping_floor: f64,
) -> Result<Coefficients<f64>> {
    let mut m = base.clone();
    let n = m.coeff_count();
    for i in 0..3 {
        for k in 0..n {
            m.set_alpha(i, k, force[i * n + k]).map_err(model_error)?;
        }
    }
    if let Some(t) = torque {
        let nt = m.torque_coeff_count();
        for i in 0..3 {
            for k in 0..nt {
                m.set_beta(i, k, t[i * nt + k]).map_err(model_error)?;
            }
        }
        let raw: [f64; 6] = std::array::from_fn(|j| t[3 * nt + j]);
        m.set_damping(&matrix(&with_floor(&raw, damping_floor)))
            .map_err(model_error)?;
    }
    Ok(m)
}

/// The model of `design` fitted on all takes over `base` (air of density
/// `rho`, kg/m³, object of reference length `l`, m); an added-mass
/// coupling is stored and reported as its [`CouplingSplit`] (the coupling
/// and, when it has one, the rotational lift).
pub(crate) fn extend(
    p: &Problems,
    base: &Coefficients<f64>,
    design: &[Candidate],
    consts: (f64, f64, f64),
) -> Result<Extended> {
    fitted(p, base, design, consts, None)
}

/// [`extend`] with take `take` (its index in the set) left out of every
/// solve, the torque's (beta, D) refitted whatever the design: the model
/// a held-out take is re-simulated with (`resimulate`). A take without
/// frames in a problem was never in it.
pub(crate) fn extend_without(
    p: &Problems,
    base: &Coefficients<f64>,
    design: &[Candidate],
    consts: (f64, f64, f64),
    take: usize,
) -> Result<Extended> {
    fitted(p, base, design, consts, Some(take))
}

/// [`extend`] without take `skip` (set index; `None`: on all takes).
fn fitted(
    p: &Problems,
    base: &Coefficients<f64>,
    design: &[Candidate],
    (damping_floor, rho, l): (f64, f64, f64),
    skip: Option<usize>,
) -> Result<Extended> {
    let cols = design_columns(p, design);
    let index = |ids: &[usize]| skip.and_then(|t| ids.iter().position(|&i| i == t));
    let force = p.force.solve(&cols, None, index(&p.force.take_ids)).x;
    let b = p.force.base;
    let u: Vec<f64> = (b..force.len()).map(|i| force[i]).collect();
    let torque = (skip.is_some() || design.iter().any(|c| c.has_torque()))
        .then(|| p.torque.solve(&cols, Some(&u), index(&p.torque.take_ids)).x);
    // A held baseline (`--coeffs`, [`super::fixed`]) keeps its
    // coefficients; each effect's fit is an increment on what it stores.
    let held = b == 0;
    let mut model = if held {
        base.clone()
    } else {
        with_coefficients(base, &force, torque.as_ref(), damping_floor)?
    };
    let mut params = Vec::new();
    let mut wind = None;
    let mut at = 0;
    for c in design {
        let mut v: Vec<f64> = u.get(at..at + c.width()).unwrap_or(&[]).to_vec();
        at += c.width();
        if let Some(old) = held.then(|| super::fixed::stored(base, *c)).flatten() {
            v.iter_mut().zip(old).for_each(|(x, o)| *x += o);
        }
        if *c == Candidate::Wind {
            wind = Some(Vector3::new(v[0], v[1], v[2]));
        }
        for (c, v) in read(*c, v, rho, l) {
            store(&mut model, c, &v)?;
            params.push((c, v));
        }
    }
    Ok(Extended {
        model,
        wind,
        params,
    })
}

/// The effects candidate `c` with fitted parameters `v` stands for: an
/// added-mass coupling as its [`CouplingSplit`], every other as itself.
fn read(c: Candidate, v: Vec<f64>, rho: f64, l: f64) -> Vec<(Candidate, Vec<f64>)> {
    if c != Candidate::Named(EffectKind::AddedMassCoupling) {
        return vec![(c, v)];
    }
    let split = CouplingSplit::of(&v, rho, l);
    let mut out = vec![(c, split.added_mass.to_vec())];
    if split.lift > 0.0 {
        out.push((
            Candidate::Named(EffectKind::RotationalLift),
            vec![split.lift],
        ));
    }
    out
}

/// Stores candidate `c` with parameters `v` in `m` (added mass projected
/// onto positive semi-definite tensors, as the equations of motion need).
fn store(m: &mut Coefficients<f64>, c: Candidate, v: &[f64]) -> Result<()> {
    match c {
        Candidate::Named(EffectKind::AddedMass) => {
            let six: [f64; 6] = std::array::from_fn(|i| v.get(i).copied().unwrap_or(0.0));
            let psd = omniad_core::math::nearest_psd(&omniad_core::math::symmetric_from_six(six));
            let e = Effect::new(
                EffectKind::AddedMass,
                &omniad_core::math::six_from_symmetric(&psd),
            );
            m.set_effect(e.ok_or_else(|| Error::Data("added mass: bad parameters".into()))?)
                .map_err(model_error)
        }
        Candidate::Named(kind) => {
            let e = Effect::new(kind, v)
                .ok_or_else(|| Error::Data(format!("{}: bad parameters", kind.name())))?;
            m.set_effect(e).map_err(model_error)
        }
        Candidate::Wind => Ok(()),
        Candidate::SpinCoupling => {
            let at = |i: usize| v.get(i).copied().unwrap_or(0.0);
            let k = SpinCoupling {
                k: std::array::from_fn(|i| std::array::from_fn(|jk| at(i * 9 + jk))),
            };
            m.set_spin_coupling(Some(k)).map_err(model_error)
        }
        Candidate::GravityCoupling => {
            let g = GravityCoupling {
                g: Matrix3::from_fn(|i, j| v.get(i * 3 + j).copied().unwrap_or(0.0)),
            };
            m.set_gravity_coupling(Some(g)).map_err(model_error)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::joint::{Joint, JointFrame};
    use crate::fit::smoothing::Smoothing;
    use nalgebra::DMatrix;

    /// Three takes (set indices 4, 1, 7, in that order in the problems)
    /// of a degree-0 model whose force on x is the take's index: the
    /// model fitted without a take averages the other two, whatever the
    /// take's place in the problems; a take with no frames leaves all
    /// three. Beta and D are refitted (here to zero, the torque's target).
    #[test]
    fn a_take_is_left_out_by_its_set_index() {
        let width: usize = crate::residual::candidates::ALL
            .iter()
            .map(|c| c.width())
            .sum();
        let smoothing = Smoothing {
            weight: 0.0,
            order: 2,
        };
        let (mut force, mut torque) = (Vec::new(), Vec::new());
        for take in [4, 1, 7] {
            for k in 0..10 {
                let x = k as f64 * 0.3;
                force.push(JointFrame {
                    take,
                    base: DMatrix::identity(3, 3),
                    extra: DMatrix::zeros(3, width),
                    weight: Matrix3::identity(),
                    target: Vector3::new(take as f64, 0.0, 0.0),
                });
                let base = DMatrix::from_fn(3, 9, |i, j| match j {
                    0..=2 => f64::from(u8::from(i == j)),
                    _ => (x + (i * 9 + j) as f64).sin(),
                });
                torque.push(JointFrame {
                    take,
                    base,
                    extra: DMatrix::zeros(3, width),
                    weight: Matrix3::identity(),
                    target: Vector3::zeros(),
                });
            }
        }
        let p = Problems {
            force: Joint::new(force, 0, smoothing),
            torque: Joint::new(torque, 0, smoothing),
            offsets: crate::residual::problems::offsets(),
            force_samples: Vec::new(),
            force_bases: Vec::new(),
            mass: 1.0,
            held_added_mass: Matrix3::zeros(),
        };
        let base = Coefficients::zeros(0, Vector3::z(), 0.3).expect("model");
        let consts = (0.0, 1.2, 0.3);
        let alpha_x = |take| {
            let m = extend_without(&p, &base, &[], consts, take)
                .expect("model")
                .model;
            m.alpha(0, 0).expect("alpha")
        };
        assert!((alpha_x(4) - 4.0).abs() < 1e-6, "{}", alpha_x(4));
        assert!((alpha_x(1) - 5.5).abs() < 1e-6, "{}", alpha_x(1));
        assert!((alpha_x(7) - 2.5).abs() < 1e-6, "{}", alpha_x(7));
        assert!((alpha_x(3) - 4.0).abs() < 1e-6, "{}", alpha_x(3));
        let all = extend(&p, &base, &[], consts).expect("model").model;
        assert!((all.alpha(0, 0).expect("alpha") - 4.0).abs() < 1e-6);
        let m = extend_without(&p, &base, &[], consts, 1)
            .expect("model")
            .model;
        assert!(m.damping().norm() < 1e-9, "{}", m.damping());
    }
}
