//! Greedy forward selection of effects by leave-one-cycle-out error on the
//! training cycles: at each step every remaining candidate is added to the
//! current design in turn; the best is kept when it passes the
//! acquisition's rule (a held-out gain of at least [`MIN_GAIN`], better on
//! significantly many cycles by the sign test — `omniad residual`'s rule)
//! and its parameters are physically plausible. The test cycles are not
//! seen here.

use crate::fit::{Design, Problem};
use crate::kite::KiteProperties;
use crate::sample::Sample;
use crate::terms::Term;
use serde::Serialize;

pub use omniad_acquire::residual::select::{sign_threshold, MIN_GAIN};

/// One candidate's score at the step it was tried.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tried {
    /// Effect name.
    pub effect: String,
    /// Selection step (0: tried against the base model alone).
    pub step: usize,
    /// Leave-one-cycle-out RMS force error of the design with it, N.
    pub cv_force_rms: f64,
    /// Its scalar parameter where it has one (fitted on all training
    /// cycles).
    pub param: Option<f64>,
    /// Why it was not kept, if it was not.
    pub rejected: Option<String>,
}

/// The result of the selection.
#[derive(Clone, Debug)]
pub struct Selection {
    /// The final design (base plus the kept effects).
    pub design: Design,
    /// Its smoothing weight.
    pub smoothing: f64,
    /// Every candidate as tried, in order.
    pub tried: Vec<Tried>,
    /// Leave-one-cycle-out RMS of the base model, N.
    pub base_cv_rms: f64,
}

/// Physical plausibility of an effect's fitted scalar, or why not.
pub fn plausible(term: &Term, value: f64, kite: &KiteProperties) -> Result<(), String> {
    let (lo, hi, what) = match term {
        Term::TetherDrag(_) => (0.0, 1.5, "tether drag share c (a cylinder has C_d ≈ 1.2)"),
        Term::KiteInertia => (
            -0.5 * kite.mass,
            3.0 * kite.mass,
            "inertia correction Δm, kg",
        ),
        Term::KcuSwing => (0.0, 30.0 * kite.kcu_mass, "m_kcu r, kg m"),
        _ => return Ok(()),
    };
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(format!("{what} = {value:.3} outside [{lo:.3}, {hi:.3}]"))
    }
}

/// Runs the selection over `candidates` on the training cycles.
pub fn select(
    base: Design,
    candidates: &[Term],
    train: &[(u32, Vec<Sample>)],
    kite: &KiteProperties,
    mut progress: impl FnMut(&str),
) -> Selection {
    let problem = Problem::new(base.clone(), train);
    let (mut smoothing, mut best) = problem.choose_smoothing();
    let base_cv_rms = best.sqrt();
    let mut design = base;
    let mut remaining: Vec<Term> = candidates.to_vec();
    let mut tried = Vec::new();
    let mut current = problem;
    for step in 0.. {
        let mut scored = Vec::new();
        for t in &remaining {
            progress(&format!("step {step}: {}", t.name()));
            let mut d = design.clone();
            d.terms.push(*t);
            let p = Problem::new(d, train);
            let (l, mse) = p.choose_smoothing();
            let param = scalar_param(&p, l);
            let rejected = param
                .and_then(|v| plausible(t, v, kite).err())
                .or_else(|| significance(&current, smoothing, &p, l, best, mse).err());
            scored.push((*t, l, mse, param, rejected));
        }
        for (t, _, mse, param, rejected) in &scored {
            tried.push(Tried {
                effect: t.name(),
                step,
                cv_force_rms: mse.sqrt(),
                param: *param,
                rejected: rejected.clone(),
            });
        }
        let pick = scored
            .iter()
            .filter(|c| c.4.is_none())
            .min_by(|a, b| a.2.total_cmp(&b.2));
        let Some((t, l, mse, ..)) = pick.cloned() else {
            break;
        };
        design.terms.push(t);
        remaining.retain(|r| r.name() != t.name());
        current = Problem::new(design.clone(), train);
        smoothing = l;
        best = mse;
        if remaining.is_empty() {
            break;
        }
    }
    Selection {
        design,
        smoothing,
        tried,
        base_cv_rms,
    }
}

/// The acquisition's rule for keeping an effect (`omniad residual`'s, one
/// rule for recordings and flights): the held-out mean squared error falls
/// by at least [`MIN_GAIN`] and the held-out error is lower on
/// significantly many cycles (the one-sided sign test of
/// [`sign_threshold`]): a gain made by a few cycles is not a property of
/// the air.
fn significance(
    before: &Problem,
    before_lambda: f64,
    after: &Problem,
    after_lambda: f64,
    before_mse: f64,
    after_mse: f64,
) -> Result<(), String> {
    let gain = 1.0 - after_mse / before_mse;
    if gain.is_nan() || gain < MIN_GAIN {
        return Err(format!(
            "held-out gain {:.1} % below {:.0} %",
            100.0 * gain,
            100.0 * MIN_GAIN
        ));
    }
    let (Some(b), Some(a)) = (before.held_out(before_lambda), after.held_out(after_lambda)) else {
        return Err("too few training cycles to hold one out".into());
    };
    let better = b.iter().zip(&a).filter(|(x, y)| y.0 < x.0).count();
    let need = sign_threshold(b.len());
    if better < need {
        return Err(format!(
            "better on {better} of {} cycles (sign test needs {need})",
            b.len()
        ));
    }
    Ok(())
}

/// The last term's single parameter, when it is a scalar effect.
fn scalar_param(p: &Problem, lambda: f64) -> Option<f64> {
    let last = p.design.terms.len().checked_sub(1)?;
    let t = p.design.terms.get(last)?;
    if t.is_sh() {
        return None;
    }
    let theta = p.fit(lambda)?;
    theta.get(p.design.columns_of(last).start).copied()
}
