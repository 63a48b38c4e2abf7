//! Diagnostic: which part of the reconstructed frames carries the C_F
//! error — the forces or the velocities (E, |V|)? Fits mixtures of the
//! last iteration's frames and the true states' frames (same frames, same
//! flags), tries dropping the take ends, reconstructs the set again with the
//! final model and with the model fitted to the true states (and refits
//! each reconstruction), and removes each take's speed scale:
//! `omniad lab mixfit SET`.
use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::fit::torque::TorqueFrames;
use crate::pipeline;
use crate::reconstruct::forces::{ForceStats, Sample};
use crate::reconstruct::run::Silent;
use crate::synth::truth::{
    fitted_directions, force_error, read_coefficients, torque_directions, torque_error,
};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// The mixed-frames study of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth(dir)?;
    let (set, cfg, fit, tframes) = (w.set, w.cfg, w.fit, w.truth_frames);
    let tmap = by_frame(&tframes);
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let base = zero_model(&set.object, cfg.degree)?;
    let dirs = fitted_directions(&tframes);
    let tdirs = torque_directions(&tframes, TorqueFrames::Stable);
    let report = |out: &mut dyn Write, label: &str, frames: &[Sample]| -> LabResult {
        let m = pipeline::fit_samples(&base, frames, &set, &cfg)?;
        let (e, n) = force_error(&m, &truth, &dirs, 20, 15f64.to_radians());
        let (et, nt) = torque_error(&m, &truth, &tdirs);
        say!(
            out,
            "{label}: C_F {:.2} % over {n}, C_T {:.2} % over {nt}",
            e * 100.0,
            et * 100.0
        );
        Ok(())
    };
    report(out, "reconstructed", &fit.samples)?;
    report(out, "truth", &tframes)?;
    let mix = |f: fn(&Sample, &Sample) -> Sample| paired(&fit.samples, &tmap, f);
    report(out, "rec force, true V/Ω", &mix(their_velocities))?;
    report(out, "true force, rec V/Ω", &mix(their_forces))?;
    report(
        out,
        "rec all, true flags",
        &mix(|s, t| Sample {
            use_force: t.use_force,
            use_torque: t.use_torque,
            ..*s
        }),
    )?;
    report(
        out,
        "rec all, every frame in the torque fit",
        &mix(|s, _| Sample {
            use_torque: s.use_force,
            ..*s
        }),
    )?;
    report(
        out,
        "true all, every frame in the torque fit",
        &tframes
            .iter()
            .map(|t| Sample {
                use_torque: t.use_force,
                ..*t
            })
            .collect::<Vec<_>>(),
    )?;
    report(
        out,
        "true all, rec flags/cov",
        &mix(|s, t| their_forces(&their_velocities(s, t), t)),
    )?;
    let lens: HashMap<usize, usize> = set
        .takes
        .iter()
        .enumerate()
        .map(|(i, t)| (i, t.epochs.len()))
        .collect();
    for (lo, hi) in [(1usize, 10usize), (0, 9), (1, 9), (2, 8)] {
        let f: Vec<Sample> = fit
            .samples
            .iter()
            .filter(|s| {
                let n = lens.get(&s.take).copied().unwrap_or(1).max(1);
                let b = s.index * 10 / n;
                b >= lo && b < hi
            })
            .copied()
            .collect();
        report(out, &format!("tenths {lo}..{hi}"), &f)?;
    }
    // Reconstruction with the model fitted to the true states.
    let model_t = pipeline::fit_samples(&base, &tframes, &set, &cfg)?;
    let noise = pipeline::final_noise(&set, &fit, &cfg)?;
    let mut recs = Vec::new();
    let n = model_t.coeff_count();
    let mut final_alpha = model_t.clone();
    let mut true_alpha = fit.model.clone();
    for i in 0..3 {
        for k in 0..n {
            final_alpha.set_alpha(i, k, fit.model.alpha(i, k).unwrap_or(0.0))?;
            true_alpha.set_alpha(i, k, model_t.alpha(i, k).unwrap_or(0.0))?;
        }
    }
    for (label, m) in [
        ("final model", &fit.model),
        ("true-state model", &model_t),
        ("final alpha, true-state beta/D", &final_alpha),
        ("true-state alpha, final beta/D", &true_alpha),
    ] {
        let rec = crate::reconstruct::run::refine(
            &set,
            m,
            noise,
            &cfg.filter,
            &fit.reconstruction,
            &Silent,
        )?;
        let mut total = crate::synth::truth::StateError::default();
        for (take, s) in set.takes.iter().zip(&rec) {
            let t = crate::input::state_csv::read_states(
                &dir.join("truth").join(format!("{}.csv", take.name)),
            )?;
            total.add(&crate::synth::truth::state_error(s, &t));
        }
        let mut st = ForceStats::default();
        let frames = crate::reconstruct::run::samples(&set, &rec, &mut st);
        let refit = pipeline::fit_samples(&base, &frames, &set, &cfg)?;
        let (e, _) = force_error(&refit, &truth, &dirs, 20, 15f64.to_radians());
        say!(
            out,
            "reconstructed with the {label}: {:.2} cm, {:.2} deg; refit C_F {:.2} %",
            total.position_rms() * 100.0,
            total.angle_rms().to_degrees(),
            e * 100.0
        );
        recs.push(frames);
    }
    // Which part of those two reconstructions carries the model's pull.
    if let [with_final, with_true, ..] = recs.as_slice() {
        let key = by_frame(with_true);
        report(
            out,
            "final-model forces, true-state-model V/Ω",
            &paired(with_final, &key, their_velocities),
        )?;
        report(
            out,
            "true-state-model forces, final-model V/Ω",
            &paired(with_final, &key, |s, t| Sample {
                force_cov: t.force_cov,
                ..their_forces(s, t)
            }),
        )?;
    }
    // Per-take speed scale of the reconstruction.
    let mut ratio: HashMap<usize, (f64, f64)> = HashMap::new();
    for s in &fit.samples {
        if let Some(t) = tmap.get(&(s.take, s.index)) {
            let e = ratio.entry(s.take).or_default();
            e.0 += s.velocity.dot(&t.velocity);
            e.1 += t.velocity.norm_squared();
        }
    }
    let mut takes: Vec<_> = ratio.iter().map(|(k, (a, b))| (*k, a / b)).collect();
    takes.sort_by_key(|t| t.0);
    for (k, r) in &takes {
        say!(out, "take {k}: speed scale {r:.4}");
    }
    let scaled: Vec<Sample> = fit
        .samples
        .iter()
        .map(|s| {
            let r = takes.iter().find(|t| t.0 == s.take).map_or(1.0, |t| t.1);
            Sample {
                velocity: s.velocity / r,
                ..*s
            }
        })
        .collect();
    report(out, "rec, per-take speed scale removed", &scaled)?;
    // Errors by time since take start.
    let mut buckets = [(0.0f64, 0.0f64, 0usize); 10];
    for s in &fit.samples {
        if let (Some(t), Some(&n)) = (tmap.get(&(s.take, s.index)), lens.get(&s.take)) {
            let b = (s.index * 10 / n.max(1)).min(9);
            buckets[b].0 += (s.force - t.force).norm_squared();
            buckets[b].1 += (s.velocity - t.velocity).norm_squared();
            buckets[b].2 += 1;
        }
    }
    for (i, (f, v, n)) in buckets.iter().enumerate() {
        say!(
            out,
            "tenth {i}: force err {:.4} N, vel err {:.4} m/s ({n})",
            (f / *n as f64).sqrt(),
            (v / *n as f64).sqrt()
        );
    }
    Ok(())
}

/// Frames by (take, epoch).
fn by_frame(frames: &[Sample]) -> HashMap<(usize, usize), Sample> {
    frames.iter().map(|s| ((s.take, s.index), *s)).collect()
}

/// `f(frame, its twin in other)` for every frame of `base` with a twin.
fn paired(
    base: &[Sample],
    other: &HashMap<(usize, usize), Sample>,
    f: fn(&Sample, &Sample) -> Sample,
) -> Vec<Sample> {
    base.iter()
        .filter_map(|s| other.get(&(s.take, s.index)).map(|t| f(s, t)))
        .collect()
}

/// `s` with `t`'s velocities (and so its directions E).
fn their_velocities(s: &Sample, t: &Sample) -> Sample {
    Sample {
        velocity: t.velocity,
        angular_velocity: t.angular_velocity,
        gravity_body: t.gravity_body,
        ..*s
    }
}

/// `s` with `t`'s force and torque (and `s`'s covariance of them).
fn their_forces(s: &Sample, t: &Sample) -> Sample {
    Sample {
        force: t.force,
        torque: t.torque,
        ..*s
    }
}
