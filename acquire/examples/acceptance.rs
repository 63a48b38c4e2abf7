//! Measures the issue-3 acceptance numbers on a synthetic recording set:
//! `cargo run --release -p omniad-acquire --example acceptance -- SET [method]
//! [iterations]`. Environment knobs (diagnostics only): `FLOOR` (noise
//! floor), `MIRROR_WINDOW`, `XR` (a fixed smoothing weight instead of the
//! cross-validated one), `RELIN` (`filter.relinearise`),
//! `RELIN_ITS` (`relinearised_iterations`), `EXTENSIONS=off` (the paper's
//! model only), `DEG` (SH degree), `ORDER` (`lsq.smoothness_order`),
//! `PERTAKE` (per-take errors of the last iteration too), `DUMP=FILE` (the
//! true and fitted C_F at every truth grid direction, as CSV).

use omniad_acquire::pipeline::{self, FitConfig, Method};
use omniad_acquire::reconstruct::run::Silent;
use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::input::state_csv::read_states;
use omniad_acquire::synth::truth::{
    fitted_directions, force_error, read_coefficients, state_error, StateError,
};
use std::path::Path;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(
        args.get(1)
            .ok_or("usage: acceptance SET [lsq|paper] [iterations]")?,
    );
    let method = if args.get(2).map(String::as_str) == Some("paper") {
        Method::Paper
    } else {
        Method::Lsq
    };
    let iterations = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let start = Instant::now();
    let set = RecordingSet::load(dir)?;
    let floor = std::env::var("FLOOR")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(FitConfig::default().noise_floor);
    let mut cfg = FitConfig {
        method,
        iterations,
        noise_floor: floor,
        ..FitConfig::default()
    };
    if let Some(w) = std::env::var("MIRROR_WINDOW")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        cfg.filter.mirror_window = w;
    }
    if let Some(r) = std::env::var("XR").ok().and_then(|s| s.parse().ok()) {
        cfg.lsq.smoothing = r;
        cfg.lsq.cross_validate = false;
    }
    if std::env::var("EXTENSIONS").is_ok_and(|v| v == "off") {
        cfg.lsq.extensions = false;
    }
    if let Some(r) = std::env::var("RELIN").ok().and_then(|s| s.parse().ok()) {
        cfg.filter.relinearise = r;
    }
    if let Some(r) = std::env::var("RELIN_ITS").ok().and_then(|s| s.parse().ok()) {
        cfg.relinearised_iterations = r;
    }
    if let Some(d) = std::env::var("DEG").ok().and_then(|s| s.parse().ok()) {
        cfg.degree = d;
    }
    if let Some(p) = std::env::var("ORDER").ok().and_then(|s| s.parse().ok()) {
        cfg.lsq.smoothness_order = Some(p);
    }
    let out = pipeline::fit(&set, &cfg, &Silent)?;
    let fit_time = start.elapsed().as_secs_f64();
    for (i, r) in out.iterations.iter().enumerate() {
        println!(
            "iteration {i}: residual {:.4} {:.4}  noise {:.3} {:.2}  {:?} {:?} {:.2}s",
            r.residual.0,
            r.residual.1,
            r.noise.force_walk,
            r.noise.torque_walk,
            r.filter,
            r.forces,
            r.seconds
        );
    }
    let noise = pipeline::final_noise(&set, &out, &cfg)?;
    let rec = omniad_acquire::reconstruct::run::refine(
        &set,
        &out.model,
        noise,
        &cfg.filter,
        &out.reconstruction,
        &Silent,
    )?;
    for (label, states) in [
        ("last-iteration", &out.reconstruction),
        ("final-model", &rec),
    ] {
        let mut total = StateError::default();
        for (take, s) in set.takes.iter().zip(states.iter()) {
            let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
            let e = state_error(s, &truth);
            if label == "final-model" || std::env::var("PERTAKE").is_ok() {
                println!(
                    "  {}: pos {:.2} cm, angle {:.2} deg",
                    take.name,
                    e.position_rms() * 100.0,
                    e.angle_rms().to_degrees()
                );
            }
            total.add(&e);
        }
        println!(
            "{label}: position RMS {:.2} cm, orientation RMS {:.2} deg",
            total.position_rms() * 100.0,
            total.angle_rms().to_degrees()
        );
    }
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let dirs = fitted_directions(&out.samples);
    let (err, n) = force_error(&out.model, &truth, &dirs, 20, 15f64.to_radians());
    println!(
        "C_F relative L2 error {:.2} % over {n} grid directions",
        err * 100.0
    );
    for min in [60, 150, 400] {
        let (e, n) = force_error(&out.model, &truth, &dirs, min, 15f64.to_radians());
        println!(
            "  C_F over {n} directions with >= {min} frames: {:.2} %",
            e * 100.0
        );
    }
    scale_check(&out.model, &truth, &dirs);
    if let Ok(path) = std::env::var("DUMP") {
        std::fs::write(path, directions_csv(&out.model, &truth, &dirs))?;
    }
    let ctx = omniad_acquire::fit::context::FitContext {
        air_density: set.world.air_density,
        reference_length: set.object.reference_length,
        pole: set.object.pole,
    };
    println!(
        "last fit's smoothing {:?}",
        omniad_acquire::fit::force::force_smoothing(&out.samples, &ctx, &cfg.lsq)
    );
    println!(
        "last torque fit's smoothing {:?}",
        omniad_acquire::fit::torque::torque_smoothing(&out.samples, &ctx, &cfg.lsq)
    );
    println!("D = {:?}", out.model.damping());
    println!("fit wall time {fit_time:.2} s");
    Ok(())
}

/// How much of the C_F error is one overall scale: the least-squares
/// scale of the fitted C_F onto the truth over the well-covered directions
/// and the error left after it.
fn scale_check(
    model: &omniad_core::Coefficients<f64>,
    truth: &[[nalgebra::Vector3<f64>; 3]],
    dirs: &[nalgebra::Vector3<f64>],
) {
    let near = |e: &nalgebra::Vector3<f64>| {
        let c = 15f64.to_radians().cos();
        dirs.iter().filter(|d| d.dot(e) >= c).count() >= 20
    };
    let pairs: Vec<_> = truth
        .iter()
        .filter(|[e, _, _]| near(&e.normalize()))
        .filter_map(|[e, cf, _]| model.at_direction(&e.normalize()).map(|c| (c.force, *cf)))
        .collect();
    let cc: f64 = pairs.iter().map(|(c, _)| c.norm_squared()).sum();
    let ct: f64 = pairs.iter().map(|(c, t)| c.dot(t)).sum();
    let tt: f64 = pairs.iter().map(|(_, t)| t.norm_squared()).sum();
    let s = ct / cc;
    let left: f64 = pairs.iter().map(|(c, t)| (c * s - t).norm_squared()).sum();
    println!(
        "  C_F best overall scale {s:.4}, error after it {:.2} %",
        (left / tt).sqrt() * 100.0
    );
}

/// Every truth grid direction with the true and fitted C_F and the number
/// of fitted frames within 15 degrees (the acceptance metric's count), as
/// CSV `ex,ey,ez,tx,ty,tz,fx,fy,fz,n`.
fn directions_csv(
    model: &omniad_core::Coefficients<f64>,
    truth: &[[nalgebra::Vector3<f64>; 3]],
    dirs: &[nalgebra::Vector3<f64>],
) -> String {
    let cos = 15f64.to_radians().cos();
    let mut w = String::from("ex,ey,ez,tx,ty,tz,fx,fy,fz,n\n");
    for [e, cf, _] in truth {
        let e = e.normalize();
        let n = dirs.iter().filter(|d| d.dot(&e) >= cos).count();
        if let Some(c) = model.at_direction(&e) {
            let f = c.force;
            w += &format!(
                "{},{},{},{},{},{},{},{},{},{n}\n",
                e.x, e.y, e.z, cf.x, cf.y, cf.z, f.x, f.y, f.z
            );
        }
    }
    w
}
