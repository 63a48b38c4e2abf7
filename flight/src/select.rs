//! Greedy forward selection of effects by leave-one-cycle-out error on the
//! training cycles: at each step every remaining candidate is added to the
//! current design in turn; the best is kept when it lowers the held-out
//! mean squared force error by at least [`MIN_GAIN`] and its parameters
//! are physically plausible. The test cycles are not seen here.

use crate::fit::{Design, Problem};
use crate::kite::KiteProperties;
use crate::sample::Sample;
use crate::terms::Term;
use serde::Serialize;

/// Smallest relative reduction of the held-out mean squared error for
/// which an effect is kept (2 %).
pub const MIN_GAIN: f64 = 0.02;

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
        Err(format!("{what} = {value:.3} outside [{lo}, {hi}]"))
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
    for step in 0.. {
        let mut scored = Vec::new();
        for t in &remaining {
            progress(&format!("step {step}: {}", t.name()));
            let mut d = design.clone();
            d.terms.push(*t);
            let p = Problem::new(d, train);
            let (l, mse) = p.choose_smoothing();
            let param = scalar_param(&p, l);
            let rejected = param.and_then(|v| plausible(t, v, kite).err());
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
            .filter(|c| c.4.is_none() && c.2 < best * (1.0 - MIN_GAIN))
            .min_by(|a, b| a.2.total_cmp(&b.2));
        let Some((t, l, mse, ..)) = pick.cloned() else {
            break;
        };
        design.terms.push(t);
        remaining.retain(|r| r.name() != t.name());
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
