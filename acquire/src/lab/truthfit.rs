//! Fit error alone: forces (eqs. 9-10) from the TRUE states in `truth/`,
//! fitted with the pipeline's least-squares fit, C_F error against
//! `truth/coefficients.csv`:
//! `omniad lab truthfit SET [--fallback-smoothing W]`.

use super::Knobs;
use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::fit::torque::TorqueFrames;
use crate::input::recording::RecordingSet;
use crate::input::state_csv::read_states;
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::forces::ForceStats;
use crate::synth::truth::{
    fitted_directions, force_error, read_coefficients, torque_directions, torque_error,
    true_trajectories,
};
use std::io::Write;
use std::path::Path;

/// The fit from the true states of the set in `dir` (with `truth/`);
/// `fallback_smoothing` is the smoothing weight used where
/// cross-validation cannot choose one.
pub fn run(
    dir: &Path,
    fallback_smoothing: Option<f64>,
    knobs: &Knobs,
    out: &mut dyn Write,
) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let smoothed = true_trajectories(dir, &set)?;
    let mut cfg = FitConfig::default();
    if let Some(x) = fallback_smoothing {
        cfg.lsq.smoothing = x;
    }
    if let Some(r) = knobs.relinearise {
        cfg.filter.relinearise = r;
    }
    let mut stats = ForceStats::default();
    let frames = crate::reconstruct::run::samples(&set, &smoothed, &mut stats);
    let base = zero_model(&set.object, cfg.degree)?;
    let model = pipeline::fit_samples(&base, &frames, &set, &cfg)?;
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let dirs = fitted_directions(&frames);
    let (err, n) = force_error(&model, &truth, &dirs, 20, 15f64.to_radians());
    say!(out, "{stats:?}");
    say!(
        out,
        "truth-state fit: C_F rel. L2 {:.2} % over {n} directions",
        err * 100.0
    );
    let tdirs = torque_directions(&frames, TorqueFrames::Stable);
    let (terr, tn) = torque_error(&model, &truth, &tdirs);
    say!(
        out,
        "truth-state fit: C_T rel. L2 {:.2} % over {tn} directions",
        terr * 100.0
    );
    // Reconstruct with the truth-fitted model at several walk scales.
    let ctx = crate::fit::context::FitContext::of_set(&set);
    let first = crate::reconstruct::noise::initial_noise(&set);
    for (ws, acc, ang) in [
        (0.1, 0.3, 1.0),
        (0.1, 0.1, 1.0),
        (0.03, 0.3, 1.0),
        (0.03, 0.1, 1.0),
        (0.01, 0.1, 1.0),
        (0.03, 1.0, 0.3),
    ] {
        let noise = crate::reconstruct::noise::ProcessNoise {
            force_walk: first.force_walk * ws,
            torque_walk: first.torque_walk * ws,
            accel: first.accel * acc,
            angular_accel: first.angular_accel * ang,
            bias_time: first.bias_time,
            torque_turn: first.torque_turn,
        };
        let rec = crate::reconstruct::run::reconstruct(
            &set,
            &model,
            noise,
            &cfg.filter,
            &crate::reconstruct::run::Silent,
        )?;
        let mut total = crate::synth::truth::StateError::default();
        for (take, s) in set.takes.iter().zip(&rec) {
            let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
            total.add(&crate::synth::truth::state_error(s, &truth));
        }
        let mut st = ForceStats::default();
        let rec_frames = crate::reconstruct::run::samples(&set, &rec, &mut st);
        let refit = pipeline::fit_samples(&base, &rec_frames, &set, &cfg)?;
        let (e2, _) = force_error(&refit, &truth, &dirs, 20, 15f64.to_radians());
        let fin = crate::fit::torque::refit_final_torque(
            &refit,
            &rec_frames,
            &ctx,
            &cfg.lsq_at_degree(),
        )?;
        let (t2, _) = torque_error(&fin, &truth, &tdirs);
        say!(out,
            "walk x{ws} accel x{acc} ang x{ang}: position RMS {:.2} cm, orientation RMS {:.2} deg, refit C_F {:.2} %, final C_T {:.2} %",
            total.position_rms() * 100.0,
            total.angle_rms().to_degrees(),
            e2 * 100.0,
            t2 * 100.0
        );
    }
    Ok(())
}
