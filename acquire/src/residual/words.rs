//! The analysis in words: which effect the residual points to and why
//! (held-out gain, takes, share of the residual its columns explain,
//! where the residual grows), what was rejected and why.

use crate::residual::candidates::Candidate;
use crate::residual::{HeldOut, Report};
use omniad_core::effect::EffectKind;

/// Sentences describing `r`; `params` are the kept effects' parameters.
pub(crate) fn describe(r: &Report, params: &[(Candidate, Vec<f64>)]) -> Vec<String> {
    let mut out = Vec::new();
    let b = &r.baseline;
    out.push(format!(
        "The base model predicts held-out takes with force RMS {:.4} N and torque RMS {:.5} N m ({} frames, {} takes), on the states the extended model is scored on.",
        b.heldout_force_rms, b.heldout_torque_rms, r.frames, r.takes
    ));
    let f = &r.first_round_baseline;
    if f != b {
        out.push(format!(
            "On the first round's states (reconstructed without any effect; the residual read below) it predicts them with force RMS {:.4} N and torque RMS {:.5} N m.",
            f.heldout_force_rms, f.heldout_torque_rms
        ));
    }
    let explained = |name: &str| {
        r.diagnosis
            .explained
            .iter()
            .find(|e| e.0 == name)
            .map_or(0.0, |e| e.1)
    };
    if let Some(top) = r
        .diagnosis
        .explained
        .iter()
        .filter(|e| e.0 != "spin_coupling" && e.0 != "gravity_coupling")
        .max_by(|a, b| a.1.total_cmp(&b.1))
    {
        out.push(format!(
            "Of the named effects, {} explains most of that residual: {:.0} % of it.",
            top.0,
            top.1 * 100.0
        ));
    }
    for p in &r.diagnosis.profiles {
        if p.trend.abs() > 0.8 {
            out.push(format!(
                "The residual {} with {} (bin correlation {:+.2}).",
                if p.trend > 0.0 { "grows" } else { "shrinks" },
                p.quantity,
                p.trend
            ));
        }
    }
    if r.selected.is_empty() {
        out.push(
            "No candidate improves held-out takes significantly and plausibly: the residual points to no effect the model lacks.".into(),
        );
    }
    let coupled = params
        .iter()
        .any(|(c, _)| *c == Candidate::Named(EffectKind::AddedMassCoupling));
    for (name, (c, v)) in r.selected.iter().zip(params) {
        if coupled && *c == Candidate::Named(EffectKind::RotationalLift) {
            out.push(format!(
                "The added-mass coupling's tensor dips below zero further than noise does: its isotropic part, which no force or torque tells from a rotational lift, is read as the least rotational lift that leaves M_a positive semi-definite, c = {} (Magnus).",
                fmt(v)
            ));
            continue;
        }
        let tried = r
            .candidates
            .iter()
            .rfind(|t| &t.effect == name && t.rejected.is_none());
        if let Some(t) = tried {
            out.push(format!(
                "Kept {name} ({}): held-out force RMS {:.4} N with it, weighted error {:.1} % lower, better on {} of {} held-out takes; its columns explain {:.0} % of the base residual; parameters {}.",
                kind_words(*c),
                t.heldout_force_rms,
                t.gain * 100.0,
                t.takes_better,
                t.takes,
                explained(name) * 100.0,
                fmt(v)
            ));
            if *c == Candidate::Named(EffectKind::AddedMassCoupling) {
                let full = r
                    .candidates
                    .iter()
                    .find(|a| a.effect == "added_mass" && a.step == t.step);
                out.push(format!(
                    "{name}: the air pulls and turns the body as an added mass would (force -Ω × (M_a V), Munk moment -V × (M_a V)) but never resists its acceleration{}. Real air has that reaction (-M_a dV/dt); a stateless fluid model has not (MuJoCo's ellipsoid model evaluates its added mass without accelerations).",
                    full.map_or(String::new(), |a| format!(
                        ": added mass with it predicts held-out forces worse ({:.1} % against {:.1} % lower)",
                        a.gain * 100.0,
                        t.gain * 100.0
                    ))
                ));
            }
            if let Some(share) = t.beyond_cf {
                out.push(format!(
                    "{:.0} % of {name}'s force (weighted square) lies outside what the base model's C_F can take over; the rest the base fit had absorbed into C_F, so the held-out gain measures only that share while C_F's error measures the whole.",
                    share * 100.0
                ));
            }
        }
    }
    for t in r.candidates.iter().filter(|t| t.step == 0) {
        if let Some(why) = &t.rejected {
            if t.gain > 0.05 {
                out.push(format!("Rejected {}: {why}.", t.effect));
            }
        }
    }
    out.push(format!(
        "After: held-out force RMS {:.4} N, torque RMS {:.5} N m.",
        r.after.heldout_force_rms, r.after.heldout_torque_rms
    ));
    if r.selected.iter().any(|s| s == EffectKind::AddedMass.name()) {
        out.push(
            "With added mass the force's acceleration reaction is predicted, not read from the measured rate: its held-out force error is the mass times the measured minus the predicted rate (output error).".into(),
        );
    }
    if let Some(t) = &r.truth_model {
        out.push(truth_words(t, &r.baseline, &r.after));
    }
    out
}

/// The generating model's score beside before and after.
fn truth_words(t: &HeldOut, before: &HeldOut, after: &HeldOut) -> String {
    let (t, b, a) = (
        t.heldout_force_rms,
        before.heldout_force_rms,
        after.heldout_force_rms,
    );
    format!(
        "The generating model itself (truth/model.omni, held as it is) has force RMS {t:.4} N on the same frames: {:.2} of the base model's (the extended model: {:.2}). The states were reconstructed with the fitted model in the filter's process model and lean toward it, so a fitted model can score below the truth: {:.2} is the ratio the exactly right model gets on these frames, not a bound.",
        t / b,
        a / b,
        t / b,
    )
}

fn kind_words(c: Candidate) -> &'static str {
    match c {
        Candidate::Named(k) => match k {
            EffectKind::AddedMass | EffectKind::AddedMassCoupling => "M_a, kg",
            EffectKind::RotationalLift => "c",
            EffectKind::PropellerThrust => "K",
            EffectKind::Buoyancy => "V_b, m³",
            EffectKind::LinearDrag => "k",
        },
        Candidate::Wind => "w, world m/s",
        Candidate::SpinCoupling => "K_ijk",
        Candidate::GravityCoupling => "G_ij",
    }
}

fn fmt(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().take(9).map(|x| format!("{x:.4e}")).collect();
    format!("[{}]", s.join(", "))
}
