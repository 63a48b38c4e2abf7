//! Diagnostic: which part of the reconstructed frames carries the C_F
//! error — the forces or the velocities (E, |V|)? Fits mixtures of the
//! last iteration's frames and the true states' frames (same frames, same
//! flags), and tries dropping the take ends:
//! `cargo run --release -p omniad-acquire --example mixfit -- SET`.
use omniad_acquire::forces::{ForceStats, Sample};
use omniad_acquire::model::zero_model;
use omniad_acquire::pipeline::{self, FitConfig, Silent};
use omniad_acquire::recording::RecordingSet;
use omniad_acquire::truth::{fitted_directions, force_error, read_coefficients, true_trajectories};
use std::collections::HashMap;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(args.get(1).ok_or("usage: mixfit SET")?);
    let set = RecordingSet::load(dir)?;
    let cfg = FitConfig::default();
    let out = pipeline::fit(&set, &cfg, &Silent)?;
    let truth_states = true_trajectories(dir, &set)?;
    let mut st = ForceStats::default();
    let tframes = pipeline::samples(&set, &truth_states, &mut st);
    let tmap: HashMap<(usize, usize), Sample> =
        tframes.iter().map(|s| ((s.take, s.index), *s)).collect();
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let base = zero_model(&set.object, cfg.degree)?;
    let dirs = fitted_directions(&tframes);
    let report = |label: &str, frames: &[Sample]| -> Result<(), Box<dyn std::error::Error>> {
        let m = pipeline::fit_samples(&base, frames, &set, &cfg)?;
        let (e, n) = force_error(&m, &truth, &dirs, 20, 15f64.to_radians());
        println!("{label}: C_F {:.2} % over {n}", e * 100.0);
        Ok(())
    };
    report("reconstructed", &out.samples)?;
    report("truth", &tframes)?;
    let mix = |f: &dyn Fn(&Sample, &Sample) -> Sample| -> Vec<Sample> {
        out.samples
            .iter()
            .filter_map(|s| tmap.get(&(s.take, s.index)).map(|t| f(s, t)))
            .collect()
    };
    report(
        "rec force, true V/Ω",
        &mix(&|s, t| Sample {
            velocity: t.velocity,
            angular_velocity: t.angular_velocity,
            gravity_body: t.gravity_body,
            ..*s
        }),
    )?;
    report(
        "true force, rec V/Ω",
        &mix(&|s, t| Sample {
            force: t.force,
            torque: t.torque,
            ..*s
        }),
    )?;
    report(
        "true all, rec flags/cov",
        &mix(&|s, t| Sample {
            force: t.force,
            torque: t.torque,
            velocity: t.velocity,
            angular_velocity: t.angular_velocity,
            gravity_body: t.gravity_body,
            ..*s
        }),
    )?;
    let lens: HashMap<usize, usize> = set
        .takes
        .iter()
        .enumerate()
        .map(|(i, t)| (i, t.epochs.len()))
        .collect();
    for (lo, hi) in [(1usize, 10usize), (0, 9), (1, 9), (2, 8)] {
        let f: Vec<Sample> = out
            .samples
            .iter()
            .filter(|s| {
                let n = lens.get(&s.take).copied().unwrap_or(1).max(1);
                let b = s.index * 10 / n;
                b >= lo && b < hi
            })
            .copied()
            .collect();
        report(&format!("tenths {lo}..{hi}"), &f)?;
    }
    // Errors by time since take start.
    let mut buckets = [(0.0f64, 0.0f64, 0usize); 10];
    for s in &out.samples {
        if let (Some(t), Some(&n)) = (tmap.get(&(s.take, s.index)), lens.get(&s.take)) {
            let b = (s.index * 10 / n.max(1)).min(9);
            buckets[b].0 += (s.force - t.force).norm_squared();
            buckets[b].1 += (s.velocity - t.velocity).norm_squared();
            buckets[b].2 += 1;
        }
    }
    for (i, (f, v, n)) in buckets.iter().enumerate() {
        println!(
            "tenth {i}: force err {:.4} N, vel err {:.4} m/s ({n})",
            (f / *n as f64).sqrt(),
            (v / *n as f64).sqrt()
        );
    }
    Ok(())
}
