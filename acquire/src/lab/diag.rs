//! Reconstruction diagnostics on a synthetic set: per-take error in the
//! camera frame (mean and RMS per axis), reconstructing with the generating
//! model of the project's synthetic plate or box, a zero model, or the
//! pipeline's fitted model:
//! `omniad lab diag SET --model plate|box|zero|fit [--walk-scale S]
//! [--white-scale S] [--bias-scale S]`.
//! `--take NAME` prints that take's errors over time; `--mirror-window N` sets
//! `FilterConfig::mirror_window` (0: no mirror-branch tests).

use super::Knobs;
use super::{say, LabResult};
use crate::input::recording::RecordingSet;
use crate::input::state_csv::read_states;
use crate::pipeline;
use crate::reconstruct::filter::FilterConfig;
use crate::reconstruct::run::Silent;
use crate::synth::{truth_model, ObjectSpec, SynthObject};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::io::Write;
use std::path::Path;

/// The diagnostics of the set in `dir` (with `truth/`) reconstructed
/// with `model` (`plate`, `box`, `zero` or `fit`), the unexplained
/// wrench's walk, the white noise and the initial bias scaled by `walk`,
/// `white` and `bias`.
pub fn run(
    dir: &Path,
    model_name: &str,
    [scale, acc, bias]: [f64; 3],
    knobs: &Knobs,
    out: &mut dyn Write,
) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let model = match Some(model_name) {
        Some("plate") => truth_model(&ObjectSpec::of(SynthObject::Plate), 8)?,
        Some("box") => truth_model(&ObjectSpec::of(SynthObject::Box), 8)?,
        _ => crate::fit::model::zero_model(&set.object, 8)?,
    };
    let mut noise = crate::reconstruct::noise::initial_noise(&set);
    noise.force_walk *= scale;
    noise.torque_walk *= scale;
    noise.accel *= acc;
    noise.angular_accel *= acc;
    let mut fc = FilterConfig::default();
    if let Some(r) = knobs.relinearise {
        fc.relinearise = r;
    }
    if let Some(w) = knobs.mirror_window {
        fc.mirror_window = w;
    }
    let rec = if model_name == "fit" {
        let mut cfg = pipeline::FitConfig::default();
        if let Some(w) = knobs.mirror_window {
            cfg.filter.mirror_window = w;
        }
        if let Some(r) = knobs.relinearise {
            cfg.filter.relinearise = r;
        }
        let fit = pipeline::fit(&set, &cfg, &Silent)?;
        if let Some(r) = knobs.relinearise_final {
            cfg.filter.relinearise = r;
        }
        let mut noise = pipeline::final_noise(&set, &fit, &cfg)?;
        say!(out, "final noise {noise:?}");
        noise.force_walk *= scale;
        noise.torque_walk *= scale;
        noise.accel *= acc;
        noise.angular_accel *= acc;
        crate::reconstruct::run::refine(
            &set,
            &fit.model,
            noise,
            &cfg.filter,
            &fit.reconstruction,
            &Silent,
        )?
    } else if (bias - 1.0).abs() < 1e-12 {
        crate::reconstruct::run::reconstruct(&set, &model, noise, &fc, &Silent)?
    } else {
        let body = omniad_core::RigidBody::new(set.object.mass, set.object.inertia)
            .map_err(|e| format!("{e}"))?;
        let g = set.world.gravity.norm();
        let f = set.object.mass * g;
        let mut config = FilterConfig {
            initial_bias: [f * bias, 0.5 * f * set.object.reference_length * bias],
            ..FilterConfig::default()
        };
        config.pixel_noise = set.camera.as_ref().map(|c| c.pixel_noise).unwrap_or(1.0);
        let filter = crate::reconstruct::filter::Filter {
            process: crate::reconstruct::process::Process {
                body,
                environment: crate::reconstruct::run::environment(&set),
                model: &model,
                accel_noise: noise.accel,
                angular_accel_noise: noise.angular_accel,
                force_walk: noise.force_walk,
                torque_walk: noise.torque_walk,
                bias_time: noise.bias_time,
                torque_turn: noise.torque_turn,
            },
            object: &set.object,
            camera: set.camera.as_ref(),
            config,
        };
        set.takes
            .iter()
            .map(|t| {
                let (p, q) = t.initial.expect("marker take");
                filter.run(
                    &t.epochs,
                    omniad_core::State {
                        position: p,
                        orientation: q,
                        velocity: Vector3::zeros(),
                        angular_velocity: Vector3::zeros(),
                    },
                )
            })
            .collect()
    };
    let cam = set.camera.as_ref().ok_or("no camera")?;
    let (mut tp, mut ta, mut tn) = (0.0, 0.0, 0usize);
    for (take, s) in set.takes.iter().zip(&rec) {
        let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
        let mut mean = Vector3::zeros();
        let mut sq = Vector3::zeros();
        let mut ang = 0.0;
        let mut n = 0usize;
        let mut last_ang = 0.0;
        for (t, st) in s.times.iter().zip(&s.states) {
            let Some(r) = truth.iter().find(|r| (r[0] - t).abs() < 1e-3) else {
                continue;
            };
            let q = UnitQuaternion::from_quaternion(Quaternion::new(r[4], r[5], r[6], r[7]));
            let d = cam.rotation * (st.position - Vector3::new(r[1], r[2], r[3]));
            mean += d;
            sq += d.component_mul(&d);
            let a = st.orientation.angle_to(&q);
            ang += a * a;
            last_ang = a;
            if knobs.take.as_deref() == Some(take.name.as_str()) && n.is_multiple_of(3) {
                say!(
                    out,
                    "  t {t:.3} ang {:.1} d {:.3} {:.3} {:.3}",
                    a.to_degrees(),
                    d.x,
                    d.y,
                    d.z
                );
            }
            n += 1;
        }
        let nf = n.max(1) as f64;
        tp += sq.sum();
        ta += ang;
        tn += n;
        let m = mean / nf * 100.0;
        let r = (sq / nf).map(f64::sqrt) * 100.0;
        say!(out,
            "{:8} mean cam [{:6.2} {:6.2} {:6.2}] cm  rms [{:5.2} {:5.2} {:5.2}] cm  ang {:5.2} deg (end {:5.1})  {:?}",
            take.name,
            m.x,
            m.y,
            m.z,
            r.x,
            r.y,
            r.z,
            (ang / nf).sqrt().to_degrees(),
            f64::to_degrees(last_ang),
            s.stats
        );
    }
    say!(
        out,
        "total: position RMS {:.2} cm, orientation RMS {:.2} deg",
        (tp / tn as f64).sqrt() * 100.0,
        (ta / tn as f64).sqrt().to_degrees()
    );
    Ok(())
}
