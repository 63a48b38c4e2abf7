//! Diagnostic: is the torque fit's regularisation right for its noise?
//! `omniad lab torquereg SET`. Refits the final torque (β and D, eqs. 6,
//! 8, on the frames the final fit takes) of the pipeline's last frames,
//! of the true states' frames and of the true torques plus white noise of
//! the reconstruction's RMS error, with every smoothing weight and order
//! of a grid, lower SH degrees of the torque, and D fixed (zero, or the
//! true states' fit's), and scores each on the C_T rule's direction sets:
//! how far the cross-validated choice is from the best a grid can do.
use super::{say, LabResult};
use crate::fit::context::FitContext;
use crate::fit::model::with_torque;
use crate::fit::smoothing::Smoothing;
use crate::fit::torque::{
    fit_torque_with_prior, solve_torque, torque_normals, torque_smoothing, TorqueFrames,
};
use crate::fit::torque_prior::{beta_of, pin_prior, prior_map, with_prior};
use crate::reconstruct::forces::Sample;
use crate::rng::Rng;
use crate::synth::truth::{read_coefficients, torque_direction_sets, torque_error};
use nalgebra::Vector3;
use omniad_core::sh::coeff_count;
use omniad_core::Coefficients;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// The regularisation study of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth(dir)?;
    let (set, cfg, fit) = (&w.set, &w.cfg, &w.fit);
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let ctx = FitContext::of_set(set);
    let lsq = cfg.lsq_at_degree();
    let which = fit.torque_frames;
    let sets = torque_direction_sets(&fit.samples, which, &w.truth_frames);
    let noisy = with_noise(&fit.samples, &w.truth_frames, which);
    let score = |m: &Coefficients<f64>| -> Vec<f64> {
        sets.iter()
            .map(|d| torque_error(m, &truth, d).0 * 100.0)
            .collect()
    };
    let (_, truth_d) = solve_with(&w.truth_frames, &ctx, &lsq, which, None, None);
    for (label, frames) in [
        ("reconstructed", &fit.samples),
        ("true", &w.truth_frames),
        ("true + white noise", &noisy),
    ] {
        let cv = torque_smoothing(frames, &ctx, &lsq, which);
        let (beta, d) = solve_with(frames, &ctx, &lsq, which, Some(cv), None);
        let m = with_torque(&fit.model, &beta, &d)?;
        say!(
            out,
            "{label}, cross-validated {cv:?}: C_T {:.2?}",
            score(&m)
        );
        let mut best = (f64::INFINITY, String::new());
        for order in [1u32, 2, 3, 4] {
            let mut line = format!("  order {order}:");
            for weight in [1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1, 3e-1, 1.0] {
                let s = Smoothing { weight, order };
                let (beta, d) = solve_with(frames, &ctx, &lsq, which, Some(s), None);
                let sc = score(&with_torque(&fit.model, &beta, &d)?);
                let c = sc.first().copied().unwrap_or(f64::NAN);
                line += &format!(" {weight:.0e}:{c:.2}");
                if c < best.0 {
                    best = (c, format!("{s:?} {sc:.2?}"));
                }
            }
            say!(out, "{line}");
        }
        say!(out, "  best on the grid: {}", best.1);
        for degree in [4usize, 5, 6, 7] {
            let low = crate::fit::config::LsqConfig {
                degree,
                ..lsq.clone()
            };
            let cv = torque_smoothing(frames, &ctx, &low, which);
            let (beta, d) = solve_with(frames, &ctx, &low, which, Some(cv), None);
            let beta = pad(beta, lsq.degree);
            let m = with_torque(&fit.model, &beta, &d)?;
            say!(
                out,
                "  torque degree {degree} ({cv:?}): C_T {:.2?}",
                score(&m)
            );
        }
        let high = crate::fit::config::LsqConfig {
            degree: 10,
            ..lsq.clone()
        };
        let base10 = crate::fit::model::zero_model(&set.object, 10)?;
        let (beta, d, sm) = crate::fit::torque::fit_torque(frames, &ctx, &high, which);
        let m = with_torque(&base10, &beta, &d)?;
        say!(out, "  torque degree 10 ({sm:?}): C_T {:.2?}", score(&m));
        let (beta, d, sm) = fit_torque_with_prior(frames, &ctx, &high, which, &fit.model, 3);
        let m = with_torque(&base10, &beta, &d)?;
        say!(
            out,
            "  torque degree 10 with the prior of degree 3 ({sm:?}): C_T {:.2?}",
            score(&m)
        );
        for k in [1usize, 3, 5] {
            let (beta, d, sm) = fit_torque_with_prior(frames, &ctx, &lsq, which, &fit.model, k);
            let m = with_torque(&fit.model, &beta, &d)?;
            say!(
                out,
                "  centre-of-pressure prior, degree {k} ({sm:?}): C_T {:.2?}",
                score(&m)
            );
            let (beta, d) = prior_alone(frames, &ctx, &lsq, which, &fit.model, k);
            let m = with_torque(&fit.model, &beta, &d)?;
            say!(
                out,
                "    the prior alone (no correction): C_T {:.2?}",
                score(&m)
            );
        }
        for (dl, dv) in [("zero", [0.0; 6]), ("the true states' fit's", truth_d)] {
            let (beta, d) = solve_with(frames, &ctx, &lsq, which, Some(cv), Some(dv));
            let m = with_torque(&fit.model, &beta, &d)?;
            say!(out, "  D fixed at {dl}: C_T {:.2?}", score(&m));
        }
    }
    say!(out, "D true-state fit {truth_d:.5?}");
    projection(set, &w.truth_frames, &truth, &sets, out)
}

/// The truth grid's own `C_T` least-squares projected onto SH degree N
/// (eq. 8's space, no data noise, no D): the error floor of a degree-N
/// torque model on this object, scored as the fits above.
fn projection(
    set: &crate::input::recording::RecordingSet,
    template: &[Sample],
    truth: &[[Vector3<f64>; 3]],
    sets: &[Vec<Vector3<f64>>; 3],
    out: &mut dyn Write,
) -> LabResult {
    let Some(t) = template.first() else {
        return Ok(());
    };
    let ctx = FitContext::of_set(set);
    let grid = super::truth_grid_frames(set, t, truth);
    for degree in [6u8, 8, 10, 12] {
        let base = crate::fit::model::zero_model(&set.object, degree)?;
        let lsq = crate::fit::config::LsqConfig {
            degree: usize::from(degree),
            ..Default::default()
        };
        let s = Smoothing {
            weight: 1e-7,
            order: 1,
        };
        let (beta, d) = solve_with(
            &grid,
            &ctx,
            &lsq,
            TorqueFrames::Stable,
            Some(s),
            Some([0.0; 6]),
        );
        let m = with_torque(&base, &beta, &d)?;
        let sc: Vec<f64> = sets
            .iter()
            .map(|dirs| torque_error(&m, truth, dirs).0 * 100.0)
            .collect();
        say!(out, "truth grid projected on degree {degree}: C_T {sc:.2?}");
    }
    Ok(())
}

/// The torque fit of `frames` (as `fit::torque::fit_torque`) with the
/// smoothing `smoothing` (cross-validated when `None`) and, when given, D
/// fixed at `fixed`.
fn solve_with(
    frames: &[Sample],
    ctx: &FitContext,
    lsq: &crate::fit::config::LsqConfig,
    which: TorqueFrames,
    smoothing: Option<Smoothing>,
    fixed: Option<[f64; 6]>,
) -> ([Vec<f64>; 3], [f64; 6]) {
    let smoothing = smoothing.unwrap_or_else(|| torque_smoothing(frames, ctx, lsq, which));
    let (_, total) = torque_normals(frames, ctx, lsq.degree, which);
    solve_torque(total, lsq, smoothing, fixed)
}

/// The torque fit with `β = P ρ` alone (no correction; `ρ̂(E) × C_F(E)`
/// of degree `k`, [`crate::fit::torque_prior`]) and D, by least squares.
fn prior_alone(
    frames: &[Sample],
    ctx: &FitContext,
    lsq: &crate::fit::config::LsqConfig,
    which: TorqueFrames,
    model: &Coefficients<f64>,
    k: usize,
) -> ([Vec<f64>; 3], [f64; 6]) {
    let (_, total) = torque_normals(frames, ctx, lsq.degree, which);
    let p = prior_map(model, ctx, lsq.degree, k);
    let mut nt = with_prior(&total, &p);
    pin_prior(&mut nt, p.ncols());
    let n3 = p.nrows();
    let keep: Vec<usize> = (n3..nt.ata.nrows()).collect();
    let x = crate::fit::normals::solve(
        &nt.ata.select_rows(&keep).select_columns(&keep),
        &nt.atb.select_rows(&keep),
    );
    let d: [f64; 6] = std::array::from_fn(|i| x[i]);
    let mut full = nalgebra::DVector::zeros(nt.ata.nrows());
    full.rows_mut(n3, x.len()).copy_from(&x);
    let beta = beta_of(&full, &p);
    let n = coeff_count(lsq.degree);
    (
        std::array::from_fn(|i| beta.rows(i * n, n).as_slice().to_vec()),
        crate::fit::damping::with_floor(&d, lsq.damping_floor),
    )
}

/// β blocks of a lower degree padded with zeros to `degree`'s count.
fn pad(beta: [Vec<f64>; 3], degree: usize) -> [Vec<f64>; 3] {
    beta.map(|mut b| {
        b.resize(coeff_count(degree), 0.0);
        b
    })
}

/// The true frames with white torque noise of the RMS of the
/// reconstruction's per-frame torque error over the frames `which` takes.
fn with_noise(rec: &[Sample], truth: &[Sample], which: TorqueFrames) -> Vec<Sample> {
    let key: HashMap<(usize, usize), &Sample> =
        truth.iter().map(|t| ((t.take, t.index), t)).collect();
    let diffs: Vec<f64> = rec
        .iter()
        .filter(|s| which.takes(s))
        .filter_map(|s| {
            key.get(&(s.take, s.index))
                .map(|t| (s.torque - t.torque).norm_squared())
        })
        .collect();
    let rms = (diffs.iter().sum::<f64>() / diffs.len().max(1) as f64).sqrt();
    let sigma = rms / 3f64.sqrt();
    let mut rng = Rng::new(2);
    truth
        .iter()
        .map(|s| Sample {
            torque: s.torque + Vector3::new(rng.normal(), rng.normal(), rng.normal()) * sigma,
            ..*s
        })
        .collect()
}
