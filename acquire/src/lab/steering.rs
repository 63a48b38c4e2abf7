//! Diagnostic: does the model that STEERED the last reconstruction leak
//! into its angular accelerations? `omniad lab steering SET`.
//!
//! The last iteration's frames (eq. 10) come from a smoother whose process
//! model is the previous iteration's fitted model (`pipeline::fit`). If the
//! smoothed `dΩ/dt` follows that model where the markers say little, the
//! reconstruction's torque error `e = T_rec - T*` regresses on the steering
//! model's own torque error at the true state, `d = T_steer(V*, Ω*) - T*`
//! (eqs. 6, 8), with a slope near 1. The final model is fitted to these same
//! frames, so the same regression on ITS error is partly the fit absorbing
//! `e`; the steering model was fitted to the iteration before's frames, so
//! its error is not a response to this `e`. `FitOutcome` keeps only the
//! last model: the steering model is the model of a run with one iteration
//! fewer, refitted on that run's last frames (the refinement's fit is
//! deterministic, so this is the same model).
use super::torquesplit::{moving_mean, paired, Pair};
use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::input::recording::RecordingSet;
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::run::Silent;
use nalgebra::Vector3;
use omniad_core::Coefficients;
use std::io::Write;
use std::path::Path;

/// The steering-model regression of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth(dir)?;
    let (set, cfg, fit) = (&w.set, &w.cfg, &w.fit);
    let steering = steering_model(set, cfg)?;
    let pairs = paired(set, &w.truth_frames, &fit.samples);
    say!(
        out,
        "{} frame pairs ({} torque-fit frames of the true states)",
        pairs.len(),
        pairs.iter().filter(|p| p.truth.use_torque).count()
    );
    let rho = set.world.air_density;
    for (label, model) in [("steering model", &steering), ("final model", &fit.model)] {
        let d = model_errors(&pairs, model, rho);
        lean(out, label, &pairs, &d, &|_| true)?;
        // By spin rate: quartiles of the true |Ω|.
        let mut spins: Vec<f64> = pairs
            .iter()
            .map(|p| p.truth.angular_velocity.norm())
            .collect();
        spins.sort_by(f64::total_cmp);
        let q = |f: f64| spins.get((f * spins.len() as f64) as usize).copied();
        let edges = [Some(0.0), q(0.25), q(0.5), q(0.75), Some(f64::INFINITY)];
        for pair in edges.windows(2) {
            if let [Some(lo), Some(hi)] = *pair {
                let keep = move |p: &Pair| {
                    let s = p.truth.angular_velocity.norm();
                    s >= lo && s < hi
                };
                lean(
                    out,
                    &format!("{label}, |Ω| in [{lo:.2}, {hi:.2}) rad/s"),
                    &pairs,
                    &d,
                    &keep,
                )?;
            }
        }
    }
    Ok(())
}

/// The model that steered the last reconstruction of a `cfg` run: the
/// fit of the last frames of a run with one iteration fewer.
pub(crate) fn steering_model(
    set: &RecordingSet,
    cfg: &FitConfig,
) -> Result<Coefficients<f64>, Box<dyn std::error::Error>> {
    let mut shorter = cfg.clone();
    shorter.iterations = cfg.iterations.saturating_sub(1).max(1);
    let fit = pipeline::fit(set, &shorter, &Silent)?;
    let base = zero_model(&set.object, cfg.degree)?;
    Ok(pipeline::fit_samples(&base, &fit.samples, set, cfg)?)
}

/// `T_model(V*, Ω*) - T*` per pair (eqs. 6, 8), N m, body frame.
fn model_errors(pairs: &[Pair], model: &Coefficients<f64>, rho: f64) -> Vec<Vector3<f64>> {
    pairs
        .iter()
        .map(|p| {
            let t = &p.truth;
            model.wrench(&t.velocity, &t.angular_velocity, rho).torque - t.torque
        })
        .collect()
}

/// Prints the regression of `e` on `d` over the torque-fit frames `keep`
/// selects, whole and fast parts (minus the 15-frame means): slope
/// `Σe·d / Σd·d`, the share of `Σ|e|²` it explains, and the RMS of `e`
/// and `d` (N m).
fn lean(
    out: &mut dyn Write,
    label: &str,
    pairs: &[Pair],
    d: &[Vector3<f64>],
    keep: &dyn Fn(&Pair) -> bool,
) -> LabResult {
    let e: Vec<Vector3<f64>> = pairs.iter().map(|p| p.error).collect();
    let fast = |v: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
        let slow = moving_mean(pairs, v, 7);
        v.iter().zip(&slow).map(|(a, b)| a - b).collect()
    };
    for (part, e, d) in [
        ("whole", e.clone(), d.to_vec()),
        ("fast", fast(&e), fast(d)),
    ] {
        let (mut ed, mut dd, mut ee, mut n) = (0.0, 0.0, 0.0, 0usize);
        for ((e, d), p) in e.iter().zip(&d).zip(pairs) {
            if p.truth.use_torque && keep(p) {
                ed += e.dot(d);
                dd += d.norm_squared();
                ee += e.norm_squared();
                n += 1;
            }
        }
        let m = n.max(1) as f64;
        say!(
            out,
            "{label} ({part}, {n} frames): slope {:.3}, explains {:.1} % of |e|², RMS e {:.5}, RMS d {:.5} N m",
            ed / dd,
            100.0 * ed * ed / (dd * ee),
            (ee / m).sqrt(),
            (dd / m).sqrt()
        );
    }
    Ok(())
}
