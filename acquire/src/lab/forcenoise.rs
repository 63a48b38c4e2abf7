//! Is the fitted C_F error force noise or force bias? Runs the pipeline,
//! compares its last frames' forces (eqs. 9-10 from the reconstruction)
//! with the same frames' forces from the TRUE states (per-frame RMS
//! difference and its mean in the body frame), then fits the true forces
//! plus white noise of that RMS and reports the C_F error of both fits:
//! `omniad lab forcenoise SET`.

use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::fit::torque::TorqueFrames;
use crate::input::recording::RecordingSet;
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::forces::ForceStats;
use crate::reconstruct::run::Silent;
use crate::rng::Rng;
use crate::synth::truth::{
    fitted_directions, force_error, read_coefficients, torque_error, true_trajectories,
};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// The force-noise study of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let cfg = FitConfig::default();
    let fit = pipeline::fit(&set, &cfg, &Silent)?;
    let smoothed = true_trajectories(dir, &set)?;
    let mut stats = ForceStats::default();
    let true_frames = crate::reconstruct::run::samples(&set, &smoothed, &mut stats);
    let by_key: HashMap<(usize, usize), usize> = true_frames
        .iter()
        .enumerate()
        .map(|(i, s)| ((s.take, s.index), i))
        .collect();
    let (mut sum, mut sq, mut n) = (Vector3::zeros(), 0.0, 0usize);
    let mut diffs: Vec<(usize, Vector3<f64>, Vector3<f64>)> = Vec::new();
    let mut covs: Vec<(Vector3<f64>, nalgebra::Matrix3<f64>)> = Vec::new();
    for s in fit.samples.iter().filter(|s| s.use_force) {
        let Some(t) = by_key
            .get(&(s.take, s.index))
            .and_then(|&i| true_frames.get(i))
        else {
            continue;
        };
        let d = s.force - t.force;
        sum += d;
        sq += d.norm_squared();
        n += 1;
        diffs.push((s.take, d, t.velocity));
        covs.push((d, s.force_cov));
    }
    low_pass_report(&diffs, out)?;
    calibration_report(&covs, out)?;
    let weight = set.object.mass * set.world.gravity.norm();
    let rms = (sq / n.max(1) as f64).sqrt();
    say!(
        out,
        "{n} frames: force difference RMS {:.3} N ({:.1} % of M g), mean {:?} N",
        rms,
        100.0 * rms / weight,
        (sum / n.max(1) as f64).as_slice()
    );
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let dirs = fitted_directions(&fit.samples);
    let (err, k) = force_error(&fit.model, &truth, &dirs, 20, 15f64.to_radians());
    say!(
        out,
        "pipeline fit: C_F {:.2} % over {k} directions",
        err * 100.0
    );
    let mut rng = Rng::new(1);
    let sigma = rms / 3f64.sqrt();
    let noisy: Vec<_> = true_frames
        .iter()
        .map(|s| {
            let mut s = *s;
            s.force += Vector3::new(rng.normal(), rng.normal(), rng.normal()) * sigma;
            s
        })
        .collect();
    let base = zero_model(&set.object, cfg.degree)?;
    for (label, frames) in [("true forces", &true_frames), ("true + noise", &noisy)] {
        let model = pipeline::fit_samples(&base, frames, &set, &cfg)?;
        let (err, k) = force_error(&model, &truth, &dirs, 20, 15f64.to_radians());
        say!(out, "{label}: C_F {:.2} % over {k} directions", err * 100.0);
    }
    torque_report(
        &fit.samples,
        &true_frames,
        &by_key,
        &base,
        &set,
        &cfg,
        &truth,
        out,
    )
}

/// The same study for the torque (eq. 10): per-frame torque difference
/// RMS and its 15-frame mean over the torque-fit frames, then the C_T
/// error of the true torques plus white noise of that RMS, against the
/// pipeline's: noise alone explains the pipeline's C_T error when the two
/// agree; a pipeline error well above it is correlated (bias).
#[allow(clippy::too_many_arguments)]
fn torque_report(
    rec: &[crate::reconstruct::forces::Sample],
    true_frames: &[crate::reconstruct::forces::Sample],
    by_key: &HashMap<(usize, usize), usize>,
    base: &omniad_core::Coefficients<f64>,
    set: &RecordingSet,
    cfg: &FitConfig,
    truth: &[[Vector3<f64>; 3]],
    out: &mut dyn Write,
) -> LabResult {
    use crate::synth::truth::torque_directions;
    let mut diffs = Vec::new();
    let mut slope = (0.0, 0.0);
    for s in rec.iter().filter(|s| s.use_torque) {
        if let Some(t) = by_key
            .get(&(s.take, s.index))
            .and_then(|&i| true_frames.get(i))
        {
            diffs.push((s.take, s.torque - t.torque, t.velocity));
            slope.0 += s.torque.dot(&t.torque);
            slope.1 += t.torque.norm_squared();
        }
    }
    say!(
        out,
        "reconstructed torque against true: slope {:.3}",
        slope.0 / slope.1
    );
    let n = diffs.len().max(1) as f64;
    let rms = (diffs.iter().map(|d| d.1.norm_squared()).sum::<f64>() / n).sqrt();
    let true_rms = (true_frames
        .iter()
        .filter(|t| t.use_torque)
        .map(|t| t.torque.norm_squared())
        .sum::<f64>()
        / true_frames.iter().filter(|t| t.use_torque).count().max(1) as f64)
        .sqrt();
    say!(
        out,
        "{} torque frames: torque difference RMS {rms:.5} N m (true torque RMS {true_rms:.5} N m)",
        diffs.len()
    );
    say!(out, "torque difference (N m, in place of N):");
    low_pass_report(&diffs, out)?;
    let dirs = torque_directions(true_frames, TorqueFrames::Stable);
    let mut rng = Rng::new(2);
    let sigma = rms / 3f64.sqrt();
    let noisy: Vec<_> = true_frames
        .iter()
        .map(|s| {
            let mut s = *s;
            s.torque += Vector3::new(rng.normal(), rng.normal(), rng.normal()) * sigma;
            s
        })
        .collect();
    for (label, frames) in [
        ("pipeline frames", rec),
        ("true torques", true_frames),
        ("true + noise", &noisy),
    ] {
        let model = pipeline::fit_samples(base, frames, set, cfg)?;
        let (err, k) = torque_error(&model, truth, &dirs);
        say!(out, "{label}: C_T {:.2} % over {k} directions", err * 100.0);
    }
    Ok(())
}

/// RMS of the force difference along the true air velocity and across it,
/// and of its 15-frame moving average (the time-correlated part).
fn low_pass_report(
    diffs: &[(usize, Vector3<f64>, Vector3<f64>)],
    out: &mut dyn Write,
) -> LabResult {
    let (mut along, mut across, mut low, mut n, mut m) = (0.0, 0.0, 0.0, 0usize, 0usize);
    for (i, (take, d, v)) in diffs.iter().enumerate() {
        let u = v.normalize();
        along += d.dot(&u).powi(2);
        across += (d - u * d.dot(&u)).norm_squared();
        n += 1;
        let w = diffs
            .get(i.saturating_sub(7)..(i + 8).min(diffs.len()))
            .unwrap_or(&[]);
        if w.len() == 15 && w.iter().all(|x| x.0 == *take) {
            let mean: Vector3<f64> = w.iter().map(|x| x.1).sum::<Vector3<f64>>() / 15.0;
            low += mean.norm_squared();
            m += 1;
        }
    }
    say!(
        out,
        "difference RMS along V {:.4} N, across V {:.4} N, 15-frame mean {:.4} N",
        (along / n.max(1) as f64).sqrt(),
        (across / n.max(1) as f64).sqrt(),
        (low / m.max(1) as f64).sqrt()
    );
    Ok(())
}

/// Does the smoother's force covariance describe the force differences?
/// RMS difference along each frame's most and least uncertain direction
/// against the predicted sigmas, and RMS |difference| by quartile of
/// predicted trace.
fn calibration_report(
    covs: &[(Vector3<f64>, nalgebra::Matrix3<f64>)],
    out: &mut dyn Write,
) -> LabResult {
    let (mut big, mut big_pred, mut small, mut small_pred) = (0.0, 0.0, 0.0, 0.0);
    let mut by_trace: Vec<(f64, f64)> = Vec::new();
    for (d, c) in covs {
        let e = c.symmetric_eigen();
        let (imax, imin) = (e.eigenvalues.imax(), e.eigenvalues.imin());
        big += d.dot(&e.eigenvectors.column(imax)).powi(2);
        big_pred += e.eigenvalues[imax];
        small += d.dot(&e.eigenvectors.column(imin)).powi(2);
        small_pred += e.eigenvalues[imin].max(0.0);
        by_trace.push((c.trace(), d.norm_squared()));
    }
    let n = covs.len().max(1) as f64;
    say!(out,
        "most uncertain direction: RMS {:.4} N predicted {:.4} N; least: RMS {:.4} N predicted {:.4} N",
        (big / n).sqrt(),
        (big_pred / n).sqrt(),
        (small / n).sqrt(),
        (small_pred / n).sqrt()
    );
    by_trace.sort_by(|a, b| a.0.total_cmp(&b.0));
    let q = by_trace.len() / 4;
    for (i, chunk) in by_trace.chunks(q.max(1)).take(4).enumerate() {
        let m = chunk.len().max(1) as f64;
        say!(
            out,
            "trace quartile {i}: predicted RMS {:.4} N, actual RMS {:.4} N",
            (chunk.iter().map(|x| x.0).sum::<f64>() / m).sqrt(),
            (chunk.iter().map(|x| x.1).sum::<f64>() / m).sqrt()
        );
    }
    Ok(())
}
