//! The state effects a refit round points to: the wind it finds (or
//! that is still moving), the named effects it keeps, and an added mass
//! held tentatively while it stays significant.

use super::state::{added_mass_effect, psd, StateEffects};
use super::Round;
use crate::residual::candidates::Candidate;
use crate::residual::select::{self, gain_bar, sign_threshold};
use nalgebra::Vector3;
use omniad_core::effect::{Effect, EffectKind};

/// Whether a tried candidate predicts held-out takes significantly better
/// (gain at least [`MIN_GAIN`](crate::residual::select::MIN_GAIN) above its null gain, sign test passed),
/// plausible or not.
fn significant(t: &select::Tried) -> bool {
    t.gain >= gain_bar(t.null_gain) && t.takes_better.0 >= sign_threshold(t.takes_better.1)
}

/// χ²(3) at 95 %: a three-vector whose squared standardized norm is at
/// least this differs from zero at the 5 % level.
const CHI2_3_95: f64 = 7.815;

/// The wind increment of a round (its `tried` candidates) when it is
/// significant as a parameter estimate, and whether its linearised
/// held-out force and force-and-torque score improve with it.
///
/// Why: on a round that holds a wind the wind candidate is linearised about
/// it and estimates a *change* (Gauss-Newton). Whether there is a wind at
/// all was decided by the selection's held-out gain in the first round;
/// whether its estimate has settled is a question about the parameter, so
/// the test is the increment against its jackknife standard errors over
/// the held-out folds (χ² with 3 degrees of freedom at 95 %), with the
/// held-out force and the force-and-torque score not made worse. The
/// selection's bar ([`MIN_GAIN`](crate::residual::select::MIN_GAIN) above the null bound) asks how much the
/// held-out error drops, which for a change of a wind the model already
/// holds is small even when the change is many standard errors: measured
/// on box `--wind 0,0.5,0`, the rounds stopped at 0.42 m/s.
pub(super) fn significant_increment(tried: &[select::Tried]) -> Option<(Vector3<f64>, bool)> {
    let t = tried.iter().rfind(|t| t.candidate == Candidate::Wind)?;
    let dw = Vector3::new(*t.params.first()?, *t.params.get(1)?, *t.params.get(2)?);
    let chi2: f64 = dw
        .iter()
        .zip(&t.uncertainty)
        .filter(|(_, se)| **se > 0.0)
        .map(|(d, se)| (d / se).powi(2))
        .sum();
    let helps = t.gain > 0.0 && t.score_gain > 0.0;
    (chi2 >= CHI2_3_95 && dw.iter().all(|x| x.is_finite())).then_some((dw, helps))
}

/// The wind increment of round `r` when it did not keep the wind but the
/// increment is still significant ([`significant_increment`]) and helps:
/// linearised, or else judged exactly (`r.judged_step`,
/// [`super::wind_step`]): the linearised response of a large step can
/// misjudge it (measured there).
fn still_moving(r: &Round) -> Option<Vector3<f64>> {
    match significant_increment(&r.sel.tried)? {
        (dw, true) => Some(dw),
        (_, false) => r.judged_step,
    }
}

/// Whether round `r` moved the wind it held: it kept the wind's increment
/// or the increment is still significant ([`still_moving`]). Rounds do not
/// end while it does, however small the step: a step within the
/// tolerance that is many of its standard errors is the slow end of the
/// rounds' contraction, not their fixed point (box `--wind 0,0.5,0`
/// stopped at 0.42-0.46 m/s).
pub(super) fn wind_moved(r: &Round) -> bool {
    r.effects.wind.is_some()
        && (r.sel.selected.contains(&Candidate::Wind) || still_moving(r).is_some())
}

/// The state effects round `r` points to: its wind (added to the wind it
/// carried) and its selected named effects, in selection order.
pub(super) fn proposal(r: &Round, first: bool) -> StateEffects {
    let param = |c: Candidate| r.ext.params.iter().find(|(d, _)| *d == c).map(|x| &x.1);
    let wind = match (param(Candidate::Wind), r.effects.wind) {
        (Some(v), carried) => {
            let dw = Vector3::new(v[0], v[1], v[2]);
            Some(carried.unwrap_or_else(Vector3::zeros) + dw)
        }
        // A wind held but not kept again: still moving when the round's
        // increment is significant by its own uncertainty (`still_moving`).
        (None, Some(carried)) => Some(carried + still_moving(r).unwrap_or_else(Vector3::zeros)),
        (None, None) => None,
    };
    let mut effects: Vec<Effect<f64>> = r
        .sel
        .selected
        .iter()
        .enumerate()
        .filter_map(|(step, c)| match *c {
            // Added mass as estimated when it was kept (with alpha and the
            // effects kept before it): later effects fitted jointly with
            // it can share its columns (buoyancy's Rᵀg and a drop's dU/dt
            // are nearly parallel).
            Candidate::Named(EffectKind::AddedMass) => r
                .sel
                .tried
                .iter()
                .find(|t| t.candidate == *c && t.step == step)
                .and_then(|t| psd(&t.params))
                .and_then(|m| added_mass_effect(&m)),
            // The others as the extended model's joint fit has them.
            Candidate::Named(kind) => param(*c).and_then(|v| Effect::new(kind, v)),
            _ => None,
        })
        .collect();
    // The rotational lift of a kept coupling's split is in the extended
    // model, not in the selection (`extend::read`).
    effects.extend(split_parts(r).filter_map(|(c, v)| match c {
        Candidate::Named(kind) => Effect::new(*kind, v),
        _ => None,
    }));
    // A significant added mass that was not kept is tried only when no
    // named effect explains the states (generic blocks or nothing were
    // kept): next to one that does, it is a rival explanation (isotropic
    // added mass copies buoyancy, `identify.rs`), not a missing piece, and
    // a refit holding both confirms neither. It is tried on the first
    // states, and carried on while the rounds that hold it (tentatively)
    // still find it significant: the first states were reconstructed
    // without it, so their dU/dt is biased in the direction that makes it
    // implausible, and each round's states move its estimate toward its
    // own fixed point ([`tentative`]); it is confirmed only in a round
    // that keeps it.
    // Of added mass and its coupling (air without the acceleration
    // reaction), the reading whose held-out force is better is the one
    // tried; the coupling is a force, held as fitted (its rotational lift
    // included, `CouplingSplit`), since the first states' bias can make it
    // lose on the torque or fail plausibility as it makes added mass fail.
    let carrying = READINGS.iter().any(|k| r.effects.effect(*k).is_some());
    if (first || carrying) && effects.is_empty() {
        effects.extend(significant_reading(r).and_then(as_tentative));
    }
    StateEffects { wind, effects }
}

/// The two readings of M_a: added mass, and its coupling alone.
const READINGS: [EffectKind; 2] = [EffectKind::AddedMass, EffectKind::AddedMassCoupling];

/// Of round `r`'s step-0 readings of M_a ([`READINGS`]), the significant
/// one whose held-out force gains most.
fn significant_reading(r: &Round) -> Option<&select::Tried> {
    r.sel
        .tried
        .iter()
        .filter(|t| t.step == 0 && READINGS.iter().any(|k| t.candidate == Candidate::Named(*k)))
        .filter(|t| significant(t))
        .max_by(|a, b| a.gain.total_cmp(&b.gain))
}

/// A reading of M_a as the process model can hold it: added mass
/// projected onto PSD tensors (`None` when nothing positive is left), the
/// coupling as fitted.
fn as_tentative(t: &select::Tried) -> Option<Effect<f64>> {
    match t.candidate {
        Candidate::Named(EffectKind::AddedMass) => {
            psd(&t.params).and_then(|m| added_mass_effect(&m))
        }
        Candidate::Named(kind) => Effect::new(kind, &t.params),
        _ => None,
    }
}

/// A first-round reading of M_a the markers' likelihood should judge
/// ([`super::likelihood_probe`]).
pub(super) struct Doubt {
    /// The refits' start it would replace (`None`: nothing to start from).
    pub rival: Option<StateEffects>,
    /// The start's effects that are not the reading of M_a (held beside
    /// the probe's added mass).
    pub others: Vec<Effect<f64>>,
}

/// Whether the start `trial` of the refits, proposed by the first round
/// `first`, leaves the reading of M_a in doubt:
/// * M_a is significant, nothing is kept, and its best reading has
///   nothing positive to try (the first states, reconstructed without the
///   acceleration reaction, can leave added mass without a positive part);
/// * or the start holds the coupling (M_a without the acceleration
///   reaction) and no wind: the same states favour the coupling, since
///   they have absorbed the reaction that tells the two apart (plate
///   `added_mass=0.6`: the coupling kept, C_F 11 -> 19 % off).
pub(super) fn in_doubt(first: &Round, trial: &StateEffects) -> Option<Doubt> {
    let coupling = EffectKind::AddedMassCoupling;
    if trial.wind.is_none() && trial.effect(coupling).is_some() {
        let split: Vec<EffectKind> = split_parts(first)
            .filter_map(|(c, _)| match c {
                Candidate::Named(k) => Some(*k),
                _ => None,
            })
            .collect();
        let others = trial
            .effects
            .iter()
            .filter(|e| e.kind != coupling && !split.contains(&e.kind))
            .copied()
            .collect();
        return Some(Doubt {
            rival: Some(trial.clone()),
            others,
        });
    }
    let unplaced = significant_reading(first).is_some_and(|t| as_tentative(t).is_none());
    (trial.is_empty() && unplaced).then_some(Doubt {
        rival: None,
        others: Vec::new(),
    })
}

/// The named effects round `r` held in its process model but did not
/// keep (a tentative added mass, [`proposal`]): the round confirms its
/// effects only when this is empty. An effect counts as kept when the
/// round keeps it or a reading of the same term
/// ([`Candidate::excludes`]: added mass and its coupling share M_a, a
/// coupling holds a rotational lift): a round holding one reading that
/// selects the other has moved to it, and the next round holds that.
pub(super) fn tentative(r: &Round) -> Vec<EffectKind> {
    let kept = |k: EffectKind| {
        let c = Candidate::Named(k);
        r.sel.selected.iter().any(|d| *d == c || d.excludes(c))
            || split_parts(r).any(|(d, _)| *d == c)
    };
    r.effects
        .effects
        .iter()
        .map(|e| e.kind)
        .filter(|k| !kept(*k))
        .collect()
}

/// The extended model's effects that no selected candidate names: a kept
/// coupling's rotational lift ([`crate::residual::candidates::CouplingSplit`]).
fn split_parts(r: &Round) -> impl Iterator<Item = &(Candidate, Vec<f64>)> {
    r.ext
        .params
        .iter()
        .filter(|(c, _)| !r.sel.selected.contains(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wind(dw: [f64; 3], se: [f64; 3], gain: f64, score_gain: f64) -> select::Tried {
        select::Tried {
            candidate: Candidate::Wind,
            step: 0,
            force_rms: 0.05,
            torque_rms: 0.001,
            gain,
            torque_gain: 0.0,
            score_gain,
            takes_better: (9, 13),
            params: dw.to_vec(),
            uncertainty: se.to_vec(),
            rejected: Some("gain below the bar".into()),
            unexplained_without_cf: None,
            beyond_cf: None,
            null_gain: 0.0,
        }
    }

    /// A wind increment several standard errors from zero is significant
    /// although its gain is below the selection's bar, and helps when the
    /// held-out force and score improve; one within its noise, or no wind
    /// tried, is not significant.
    #[test]
    fn wind_moves_while_its_increment_is_significant() {
        let se = [0.01, 0.01, 0.02];
        let moving = [wind([0.0, 0.06, 0.01], se, 0.04, 0.02)];
        let (dw, helps) = significant_increment(&moving).expect("significant increment");
        assert!((dw.y - 0.06).abs() < 1e-12 && helps);
        assert!(significant_increment(&[wind([0.0, 0.02, 0.01], se, 0.04, 0.02)]).is_none());
        let worse_force = significant_increment(&[wind([0.0, 0.06, 0.01], se, -0.01, 0.02)]);
        assert_eq!(worse_force.map(|x| x.1), Some(false));
        let worse_score = significant_increment(&[wind([0.0, 0.06, 0.01], se, 0.04, -0.01)]);
        assert_eq!(worse_score.map(|x| x.1), Some(false));
        assert!(significant_increment(&[]).is_none());
    }
}
