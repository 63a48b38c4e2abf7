//! Fit error alone: forces (eqs. 9-10) from the TRUE states in `truth/`,
//! fitted with the pipeline's least-squares fit, C_F error against
//! `truth/coefficients.csv`:
//! `cargo run --release -p omniad-acquire --example truthfit -- SET [smoothing]`.

use omniad_acquire::reconstruct::forces::ForceStats;
use omniad_acquire::fit::model::zero_model;
use omniad_acquire::pipeline::{self, FitConfig};
use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::input::state_csv::read_states;
use omniad_acquire::synth::truth::{
    fitted_directions, force_error, read_coefficients, true_trajectories,
};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(args.get(1).ok_or("usage: truthfit SET")?);
    let set = RecordingSet::load(dir)?;
    let smoothed = true_trajectories(dir, &set)?;
    let mut cfg = FitConfig::default();
    if let Some(x) = args.get(2).and_then(|s| s.parse().ok()) {
        cfg.lsq.smoothing = x;
    }
    if let Some(r) = std::env::var("RELIN").ok().and_then(|s| s.parse().ok()) {
        cfg.filter.relinearise = r;
    }
    let mut stats = ForceStats::default();
    let frames = omniad_acquire::reconstruct::run::samples(&set, &smoothed, &mut stats);
    let base = zero_model(&set.object, cfg.degree)?;
    let model = pipeline::fit_samples(&base, &frames, &set, &cfg)?;
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let dirs = fitted_directions(&frames);
    let (err, n) = force_error(&model, &truth, &dirs, 20, 15f64.to_radians());
    println!("{stats:?}");
    println!(
        "truth-state fit: C_F rel. L2 {:.2} % over {n} directions",
        err * 100.0
    );
    // Reconstruct with the truth-fitted model at several walk scales.
    let first = omniad_acquire::reconstruct::noise::initial_noise(&set);
    for (ws, acc, ang) in [
        (0.1, 0.3, 1.0),
        (0.1, 0.1, 1.0),
        (0.03, 0.3, 1.0),
        (0.03, 0.1, 1.0),
        (0.01, 0.1, 1.0),
        (0.03, 1.0, 0.3),
    ] {
        let noise = omniad_acquire::reconstruct::noise::ProcessNoise {
            force_walk: first.force_walk * ws,
            torque_walk: first.torque_walk * ws,
            accel: first.accel * acc,
            angular_accel: first.angular_accel * ang,
            bias_time: first.bias_time,
        };
        let rec = omniad_acquire::reconstruct::run::reconstruct(&set, &model, noise, &cfg.filter, &omniad_acquire::reconstruct::run::Silent)?;
        let mut total = omniad_acquire::synth::truth::StateError::default();
        for (take, s) in set.takes.iter().zip(&rec) {
            let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
            total.add(&omniad_acquire::synth::truth::state_error(s, &truth));
        }
        let mut st = ForceStats::default();
        let rec_frames = omniad_acquire::reconstruct::run::samples(&set, &rec, &mut st);
        let refit = pipeline::fit_samples(&base, &rec_frames, &set, &cfg)?;
        let (e2, _) = force_error(&refit, &truth, &dirs, 20, 15f64.to_radians());
        println!(
            "walk x{ws} accel x{acc} ang x{ang}: position RMS {:.2} cm, orientation RMS {:.2} deg, refit C_F {:.2} %",
            total.position_rms() * 100.0,
            total.angle_rms().to_degrees(),
            e2 * 100.0
        );
    }
    Ok(())
}
