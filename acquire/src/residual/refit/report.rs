//! What the refit did, for the report: each round's state effects and
//! selection, takes whose reconstruction broke, and the refit in words.

use super::proposal::tentative;
use super::Round;
use crate::residual::select::MIN_GAIN;
use serde::Serialize;
use std::collections::BTreeMap;

/// One round in the report.
#[derive(Clone, Debug, Serialize)]
pub struct RefitRound {
    /// The process model's wind (world, m/s), if any.
    pub wind: Option<[f64; 3]>,
    /// The process model's named effects and their parameters (the
    /// library's order and units; added mass xx, yy, zz, xy, xz, yz, kg).
    pub effects: BTreeMap<&'static str, Vec<f64>>,
    /// The round's selection.
    pub selected: Vec<String>,
    /// Held-out force RMS of its base model and of its selection, N.
    pub heldout_force_rms: [f64; 2],
    /// Effects it held tentatively and did not keep (not a confirmation;
    /// the rounds go on while they stay significant).
    pub tentative: Vec<&'static str>,
    /// Takes whose reconstruction broke in this round (their held-out
    /// error jumped while the others settled, [`super::takes::jumps`]):
    /// left out of the round's selection and held-out figures.
    pub jumped_takes: Vec<JumpedTake>,
    /// The carried wind's increment the round did not keep, significant
    /// but rejected by its linearised judgement, that moved the wind
    /// once judged exactly on the round's frames ([`super::wind_step`];
    /// world, m/s).
    pub judged_wind_step: Option<[f64; 3]>,
}

/// A take whose held-out error jumped in a round ([`super::takes::jumps`]).
#[derive(Clone, Debug, Serialize)]
pub struct JumpedTake {
    /// The take's name.
    pub take: String,
    /// Its weighted held-out force error under the round's selection, the
    /// round before and in this round.
    pub error: [f64; 2],
    /// Its markers' misfit per degree of freedom (in units of their noise
    /// variance, [`crate::reconstruct::misfit::misfit`]), the first round it was
    /// reconstructed in and this one (`None`: not reconstructed).
    pub markers: [Option<f64>; 2],
}

/// What the refit did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Refit {
    /// Refits run (rounds after the first).
    pub refits: usize,
    /// The last round's state effects agreed with what it found (within
    /// the tolerances); false when the cap stopped the rounds or no refit
    /// confirmed the effect.
    pub converged: bool,
    /// Whether a refit's states confirmed the effects (otherwise the first
    /// round's result is reported).
    pub confirmed: bool,
    /// The refits held force effects only (no wind, no added mass),
    /// confirmed them, but predicted held-out takes less than [`MIN_GAIN`]
    /// better than the first round: the first round's result stands.
    pub no_gain: bool,
    /// The rounds converged on a round that predicted held-out forces
    /// more than [`MIN_GAIN`] worse than the confirmed round before it
    /// (the same state effects within the tolerances): that round before
    /// stands (`refit::worse_than_before`).
    pub kept_previous_round: bool,
    /// The wind found on the states reconstructed without it (world, m/s).
    pub wind_before_refilter: Option<[f64; 3]>,
    /// The wind after the refits.
    pub wind_after_refilter: Option<[f64; 3]>,
    /// The Gauss-Newton wind search on the first states (from the wind
    /// the first round kept, too, [`super::wind_search`]).
    pub wind_search: Option<super::WindSearch>,
    /// The added mass searched by the markers' likelihood when the first
    /// round left M_a in doubt: significant with nothing positive to try,
    /// or read as its coupling ([`super::likelihood_probe`]).
    pub added_mass_probe: Option<super::AddedMassProbe>,
    /// Every round, the first (no state effect) first.
    pub rounds: Vec<RefitRound>,
}

pub(super) fn summary(r: &Round) -> RefitRound {
    RefitRound {
        wind: r.effects.wind.map(|w| [w.x, w.y, w.z]),
        effects: r
            .effects
            .effects
            .iter()
            .map(|e| (e.kind.name(), e.used_params().to_vec()))
            .collect(),
        selected: r.sel.selected.iter().map(|c| c.name().to_owned()).collect(),
        heldout_force_rms: [r.sel.baseline.force_rms, r.sel.after.force_rms],
        tentative: tentative(r).iter().map(|k| k.name()).collect(),
        jumped_takes: Vec::new(),
        judged_wind_step: r.judged_step.map(|w| [w.x, w.y, w.z]),
    }
}

/// The refit in words.
pub(crate) fn describe(r: &Refit) -> Vec<String> {
    let mut out: Vec<String> = r
        .wind_search
        .iter()
        .filter(|s| s.gain > 0.0)
        .map(searched)
        .collect();
    out.extend(r.added_mass_probe.as_ref().map(probed));
    if r.rounds.len() < 2 {
        return out;
    }
    let what = r.rounds.get(1).map_or_else(String::new, |x| {
        let names = x
            .wind
            .iter()
            .map(|_| "wind")
            .chain(x.effects.keys().copied());
        names.collect::<Vec<_>>().join(", ")
    });
    out.push(format!(
        "Refit around the effect: every take was reconstructed and fitted again with the effects found ({what}) in the process model, {} time(s); {}.",
        r.refits,
        match (r.confirmed, r.converged) {
            _ if r.no_gain => format!(
                "the refitted states confirmed it but predicted held-out takes less than {:.0} % better, so the first result stands",
                MIN_GAIN * 100.0
            ),
            (false, _) => "the refitted states did not confirm it, so the first result stands".into(),
            (true, true) if r.kept_previous_round => format!(
                "the selection and the parameters settled, but the last round predicted held-out takes more than {:.0} % worse than the one before, which stands",
                MIN_GAIN * 100.0
            ),
            (true, true) => "the selection and the parameters settled".into(),
            (true, false) => "the parameters had not settled at the cap".into(),
        }
    ));
    for (i, round) in r.rounds.iter().enumerate() {
        for j in &round.jumped_takes {
            out.push(format!(
                "In refit {i}, take {}'s reconstruction broke (held-out error {:.4} -> {:.4}, its markers' misfit per degree of freedom {} first -> {}): that round was analysed without it.",
                j.take,
                j.error[0],
                j.error[1],
                j.markers[0].map_or_else(|| "unknown".into(), |m| format!("{m:.2}")),
                j.markers[1].map_or_else(|| "unknown".into(), |m| format!("{m:.2}"))
            ));
        }
    }
    if let (Some(a), Some(b)) = (r.wind_before_refilter, r.wind_after_refilter) {
        out.push(format!(
            "Wind before the refilter [{:.3}, {:.3}, {:.3}] m/s, after [{:.3}, {:.3}, {:.3}] m/s.",
            a[0], a[1], a[2], b[0], b[1], b[2]
        ));
    }
    out
}

/// The added-mass probe in words.
fn probed(p: &super::AddedMassProbe) -> String {
    let tried: Vec<String> = p
        .scales
        .iter()
        .zip(&p.log_likelihood)
        .map(|(s, l)| l.map_or_else(|| format!("{s}: failed"), |l| format!("{s}: {l:.1}")))
        .collect();
    let rival = p.rival.as_ref().map_or_else(String::new, |r| {
        format!(
            " The first round's reading ({}) scores {}.",
            r.effects.join(", "),
            r.log_likelihood.map_or_else(
                || "nothing (its refinement failed)".into(),
                |l| format!("{l:.1}")
            )
        )
    });
    let verdict = match p.chosen {
        Some(s) => format!(
            "Scale {s} predicts the markers best, so the refits start from that added mass (zz {:.2} g)",
            s * p.shape[2] * 1e3
        ),
        None => format!(
            "No scale beats none and the first round's reading by {:.1}, so the refits start as the first round proposed",
            super::likelihood_probe::MIN_LOG_LIKELIHOOD_GAIN
        ),
    };
    format!(
        "The first states cannot tell added mass from its coupling or from nothing (they were reconstructed without the acceleration reaction and absorb it). Each take was reconstructed again with multiples of the potential-flow added mass of the object's inertia-equivalent box (xx, yy, zz {:.2}, {:.2}, {:.2} g) in the process model and scored by how well it predicts the markers (innovation log-likelihood; scale: value): {}.{rival} {verdict}.",
        p.shape[0] * 1e3,
        p.shape[1] * 1e3,
        p.shape[2] * 1e3,
        tried.join(", ")
    )
}

/// The wind search in words.
fn searched(s: &super::WindSearch) -> String {
    let [x, y, z] = s.wind;
    let instead = if s.linear.is_some() {
        " instead of the first round's wind"
    } else {
        ""
    };
    let verdict = if s.accepted && s.moved() {
        format!("so the refits start from it{instead}")
    } else if s.accepted {
        "the wind the first round kept, so its proposal stands".to_owned()
    } else {
        format!(
            "not enough to start the refits from it{instead} (it needs {:.1} % and {} of {} takes better, alone and on top of {}, and more than the added mass's {:.1} %)",
            s.bar[0] * 100.0,
            crate::residual::select::sign_threshold(s.takes_better.1),
            s.takes_better.1,
            selection(&s.selection),
            s.bar[1] * 100.0
        )
    };
    format!(
        "Wind search (Gauss-Newton with C_F on the first states from [{:.1}, {:.1}, {:.1}] m/s, the best start, {} steps): [{x:.3}, {y:.3}, {z:.3}] m/s predicts held-out forces {:.1} % better than no wind ({} of {} takes) and on top of {} {:.1} % better ({} takes), {verdict}.",
        s.start[0],
        s.start[1],
        s.start[2],
        s.steps,
        s.gain * 100.0,
        s.takes_better.0,
        s.takes_better.1,
        selection(&s.selection),
        s.over_selection.0 * 100.0,
        s.over_selection.1 .0
    )
}

/// The first round's selection in words.
fn selection(names: &[&str]) -> String {
    if names.is_empty() {
        "the base model (nothing selected)".into()
    } else {
        names.join(", ")
    }
}
