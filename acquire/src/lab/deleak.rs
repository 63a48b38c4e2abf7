//! Diagnostic: the steering model's leak into `dΩ/dt`, measured by the
//! smoother itself and taken out of the torque fit: `omniad lab deleak
//! SET`. The reconstruction (eq. 10) is, to first order, linear in the
//! model torque `T_M` that steers it: `T_rec ≈ (1 - g) T* + g T_M + n`
//! (BENCHMARKS.md stop 18: slope g ≈ 0.5-0.75). Reconstructing once more
//! with the torque model scaled by `1 + ε` gives `a = g T_M` per frame
//! from the smoother alone (no truth); the de-leaked fit then fits
//! `(1 - g) T_β` to `T_rec - a`: an unbiased fit of `T*` whose frames
//! are weighed by `(1 - g)²`, what the markers say about them.
use super::{say, LabResult};
use crate::fit::context::FitContext;
use crate::fit::model::with_torque;
use crate::fit::normals::Normals;
use crate::fit::torque::{dense_rows, solve_torque, torque_smoothing, TorqueFrames};
use crate::pipeline;
use crate::reconstruct::forces::{ForceStats, Sample};
use crate::reconstruct::run::{refine_takes, samples, Silent, TakeModels};
use crate::synth::truth::{read_coefficients, torque_direction_sets, torque_error};
use nalgebra::Vector3;
use omniad_core::sh::coeff_count;
use omniad_core::Coefficients;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// The torque model's scale step ε.
const EPS: f64 = 0.2;

/// The de-leak study of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth(dir)?;
    let (set, cfg, fit) = (&w.set, &w.cfg, &w.fit);
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    // The noise the last kept iteration was reconstructed with.
    let noise = match fit.iterations.iter().rfind(|r| !r.rejected) {
        Some(r) => r.noise,
        None => pipeline::final_noise(set, fit, cfg)?,
    };
    let steer = super::steering::steering_model(set, cfg)?;
    for (label, m) in [("steering model", &steer), ("final model", &fit.model)] {
        say!(out, "reconstructed with the {label}:");
        study(&w, m, noise, &truth, out)?;
    }
    Ok(())
}

/// The standard and de-leaked torque fits of the reconstruction steered
/// by `m`.
fn study(
    w: &super::FittedWithTruth,
    m: &Coefficients<f64>,
    noise: crate::reconstruct::noise::ProcessNoise,
    truth: &[[Vector3<f64>; 3]],
    out: &mut dyn Write,
) -> LabResult {
    let (set, cfg, fit) = (&w.set, &w.cfg, &w.fit);
    let ctx = FitContext::of_set(set);
    let lsq = cfg.lsq_at_degree();
    let rho = set.world.air_density;
    let frames_of = |model: &Coefficients<f64>| -> Result<Vec<Sample>, Box<dyn std::error::Error>> {
        let models = TakeModels::shared(model);
        let rec = refine_takes(
            set,
            &models,
            noise,
            &cfg.filter,
            &[],
            &fit.take_scales,
            &Silent,
        )?;
        Ok(samples(set, &rec, &mut ForceStats::default()))
    };
    let a_frames = frames_of(m)?;
    let b_frames = frames_of(&scaled_torque(m, 1.0 + EPS)?)?;
    let b: HashMap<(usize, usize), &Sample> =
        b_frames.iter().map(|s| ((s.take, s.index), s)).collect();
    // a_k = g T_M per frame, and T_M at the frame.
    let leak: Vec<(Vector3<f64>, Vector3<f64>)> = a_frames
        .iter()
        .map(|s| {
            let tm = m.wrench(&s.velocity, &s.angular_velocity, rho).torque;
            let a = b
                .get(&(s.take, s.index))
                .map_or(Vector3::zeros(), |t| (t.torque - s.torque) / EPS);
            (a, tm)
        })
        .collect();
    let which = TorqueFrames::NoThrust;
    let sets = torque_direction_sets(&a_frames, which, &w.truth_frames);
    let score = |m: &Coefficients<f64>| -> Vec<f64> {
        sets.iter()
            .map(|d| torque_error(m, truth, d).0 * 100.0)
            .collect()
    };
    let smoothing = torque_smoothing(&a_frames, &ctx, &lsq, which);
    for (label, window, cap) in [
        ("standard fit", None, 0.0),
        (
            "de-leaked, g per frame (±7-frame window), g <= 0.9",
            Some(7usize),
            0.9,
        ),
        (
            "de-leaked, g per frame (±7-frame window), g <= 0.7",
            Some(7),
            0.7,
        ),
        (
            "de-leaked, g per frame (±2-frame window), g <= 0.9",
            Some(2),
            0.9,
        ),
        (
            "de-leaked, one g for the set, g <= 0.9",
            Some(usize::MAX),
            0.9,
        ),
    ] {
        let g = gains(&a_frames, &leak, window, cap);
        let mean = g.iter().sum::<f64>() / g.len().max(1) as f64;
        let leak = if window.is_some() {
            leak.clone()
        } else {
            vec![(Vector3::zeros(), Vector3::zeros()); leak.len()]
        };
        let total = deleaked_normals(&a_frames, &leak, &g, &ctx, lsq.degree, which);
        let (beta, d) = solve_torque(total, &lsq, smoothing, None);
        let model = with_torque(m, &beta, &d)?;
        say!(out, "{label}: mean g {mean:.3}, C_T {:.2?}", score(&model));
    }
    Ok(())
}

/// `m` with its torque part (β and D) times `k`.
fn scaled_torque(m: &Coefficients<f64>, k: f64) -> crate::Result<Coefficients<f64>> {
    let n = m.torque_coeff_count();
    let beta: [Vec<f64>; 3] =
        std::array::from_fn(|i| (0..n).map(|j| m.beta(i, j).unwrap_or(0.0) * k).collect());
    let six = crate::fit::damping::six(&(m.damping() * k));
    with_torque(m, &beta, &six)
}

/// Per-frame scalar gain `g = Σ a·T_M / Σ |T_M|²` over the frames of the
/// same take within `window` frames (`None`: zero, no de-leaking), in
/// `[0, cap]`.
fn gains(
    frames: &[Sample],
    leak: &[(Vector3<f64>, Vector3<f64>)],
    window: Option<usize>,
    cap: f64,
) -> Vec<f64> {
    let Some(w) = window else {
        return vec![0.0; frames.len()];
    };
    frames
        .iter()
        .map(|s| {
            let (mut at, mut tt) = (0.0, 0.0);
            for (f, (a, tm)) in frames.iter().zip(leak) {
                let near = w == usize::MAX || (f.take == s.take && f.index.abs_diff(s.index) <= w);
                if near {
                    at += a.dot(tm);
                    tt += tm.norm_squared();
                }
            }
            if tt > 0.0 {
                (at / tt).clamp(0.0, cap)
            } else {
                0.0
            }
        })
        .collect()
}

/// Normal equations of `(1 - g) T_β ≈ T_rec - a` over the frames `which`
/// takes (rows of `fit::torque::dense_rows`, unknowns `(β, d)`).
fn deleaked_normals(
    frames: &[Sample],
    leak: &[(Vector3<f64>, Vector3<f64>)],
    g: &[f64],
    ctx: &FitContext,
    degree: usize,
    which: TorqueFrames,
) -> Normals {
    let dim = 3 * coeff_count(degree) + 6;
    let mut n = <Normals as crate::fit::normals::Accumulate>::zeros(dim);
    for ((s, (a, _)), g) in frames.iter().zip(leak).zip(g) {
        if !which.takes(s) {
            continue;
        }
        let (rows, target, axes) = dense_rows(s, ctx, degree);
        let y = target - axes * a;
        let k = 1.0 - g;
        n.ata += rows.transpose() * &rows * (k * k);
        n.atb += rows.transpose() * y * k;
        n.btb += y.norm_squared();
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::lsq::tests::samples;
    use crate::input::recording::TakeKind;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};

    #[test]
    fn the_gain_is_the_share_of_the_model_torque_the_reconstruction_moves_by() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 4).expect("model");
        let frames = samples(&truth, 40, TakeKind::Drop);
        let leak: Vec<_> = frames
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let tm = s.torque + Vector3::new(0.01 * i as f64, 0.0, 0.001);
                (tm * 0.3, tm)
            })
            .collect();
        for window in [Some(2), Some(usize::MAX)] {
            let g = gains(&frames, &leak, window, 0.9);
            assert!(g.iter().all(|g| (g - 0.3).abs() < 1e-12), "{g:?}");
        }
        assert!(gains(&frames, &leak, Some(2), 0.2)
            .iter()
            .all(|g| *g == 0.2));
        assert!(gains(&frames, &leak, None, 0.9).iter().all(|g| *g == 0.0));
    }

    #[test]
    fn scaling_the_torque_keeps_the_force() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 4).expect("model");
        let m = scaled_torque(&truth, 1.2).expect("scaled");
        let (v, w) = (Vector3::new(0.3, -2.0, 0.5), Vector3::new(1.0, 2.0, -3.0));
        let (a, b) = (truth.wrench(&v, &w, 1.2), m.wrench(&v, &w, 1.2));
        assert_eq!(a.force, b.force);
        assert!((b.torque - a.torque * 1.2).norm() < 1e-12 * a.torque.norm().max(1.0));
    }
}
