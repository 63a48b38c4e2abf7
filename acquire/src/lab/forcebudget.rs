//! The C_F error budget (issue 20 item 5): `omniad lab forcebudget SET`.
//! Each line is the C_F error (relative L2 against `truth/`, over the
//! pipeline's well-covered directions, the acceptance rule) of the force
//! fit (eqs. 5, 7; the pipeline's own fit, `pipeline::fit_samples`, with
//! its cross-validated smoothing and extensions) of one set of frames,
//! built from the pipeline's last frames and the true states' frames
//! (eqs. 9-10 on `truth/`) so that one error source enters at a time:
//!
//! 1. the representation: the truth grid's own `C_F` least-squares
//!    projected onto SH degree N (no data, no noise);
//! 2. the fit of the true states' frames (coverage and smoothing);
//! 3. the true forces plus white noise of the reconstruction's measured
//!    per-frame force RMS (noise at the measured level, uncorrelated);
//! 4. the true forces plus the reconstruction's own per-frame force errors
//!    moved to random other frames (their size and the fit's weights kept,
//!    their tie to the frame's direction and time broken);
//! 5. the reconstructed forces with the true V and Ω (force error only);
//! 6. the true forces with the reconstructed V and Ω, and with only its
//!    speed |V| or only its direction E (velocity error only);
//! 7. terms 5 and 6 with the reconstruction's world-frame force and
//!    velocity turned into the TRUE body frame (`R*ᵀ R̂`): what is left
//!    when the attitude error is taken out;
//! 8. the pipeline's frames (the pipeline's own C_F);
//! 9. the true forces averaged over 3 and 5 frames of their take (world
//!    frame): what a force resolved only that coarsely in time costs.
//!
//! A term well below the pipeline's is not where the error is made; the
//! largest one that the next does not add to is.
use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::forces::Sample;
use crate::rng::Rng;
use crate::synth::truth::{fitted_directions, force_error, read_coefficients};
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// The budget of the set in `dir` (with `truth/`), the pipeline run with
/// `knobs`' configuration (default: `omniad fit`'s).
pub fn run(dir: &Path, knobs: &super::Knobs, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth_by(dir, knobs.fit_config())?;
    let (set, cfg, fit, tframes) = (&w.set, &w.cfg, &w.fit, &w.truth_frames);
    let truth = read_coefficients(&dir.join("truth/coefficients.csv"))?;
    let dirs = fitted_directions(&fit.samples);
    let score = |m: &omniad_core::Coefficients<f64>| {
        let (e, n) = force_error(m, &truth, &dirs, 20, 15f64.to_radians());
        (e * 100.0, n)
    };
    let (e, n) = score(&fit.model);
    say!(out, "pipeline's model: C_F {e:.2} % over {n} directions");
    projection(set, tframes, &truth, &score, out)?;
    let base = zero_model(&set.object, cfg.degree)?;
    let key: HashMap<(usize, usize), &Sample> =
        tframes.iter().map(|t| ((t.take, t.index), t)).collect();
    // The pipeline's frames that have a true twin, and the twins.
    let pairs: Vec<(Sample, Sample)> = fit
        .samples
        .iter()
        .filter_map(|s| key.get(&(s.take, s.index)).map(|t| (*s, **t)))
        .collect();
    let true_states = &w.truth_states;
    let attitude = |states: &[crate::reconstruct::filter::Smoothed], s: &Sample| {
        states
            .get(s.take)
            .and_then(|x| x.states.get(s.index))
            .map(|x| x.orientation)
    };
    // Per pair: `R*ᵀ R̂`, from the reconstructed body frame to the true one.
    let turns: Vec<UnitQuaternion<f64>> = pairs
        .iter()
        .map(
            |(s, _)| match (attitude(true_states, s), attitude(&fit.reconstruction, s)) {
                (Some(t), Some(r)) => t.inverse() * r,
                _ => UnitQuaternion::identity(),
            },
        )
        .collect();
    let errors: Vec<(Vector3<f64>, nalgebra::Matrix3<f64>)> = pairs
        .iter()
        .filter(|(s, _)| s.use_force)
        .map(|(s, t)| (s.force - t.force, s.force_cov))
        .collect();
    let rms = (errors.iter().map(|e| e.0.norm_squared()).sum::<f64>() / errors.len().max(1) as f64)
        .sqrt();
    say!(
        out,
        "{} force frames: reconstructed - true force RMS {rms:.4} N ({:.1} % of M g)",
        errors.len(),
        100.0 * rms / (set.object.mass * set.world.gravity.norm())
    );
    let mut terms = budget_frames(&pairs, &turns, tframes, &errors, rms);
    for (w, label) in [
        (1, "true forces averaged over 3 frames (world frame)"),
        (2, "true forces averaged over 5 frames (world frame)"),
    ] {
        terms.push((label, averaged(tframes, true_states, w)));
    }
    for (label, frames) in &terms {
        let m = pipeline::fit_samples(&base, frames, set, cfg)?;
        let (e, n) = score(&m);
        say!(out, "{label}: C_F {e:.2} % over {n}");
    }
    Ok(())
}

/// Term 9: `frames` with each force replaced by the mean world-frame
/// force (`R F`, `R` the frame's attitude in `states`) of the frames of
/// its take within `w` epochs, turned back into its body frame: the error
/// of a reconstruction that resolves the force over `2w + 1` frames only.
fn averaged(
    frames: &[Sample],
    states: &[crate::reconstruct::filter::Smoothed],
    w: usize,
) -> Vec<Sample> {
    let turn = |s: &Sample| {
        states
            .get(s.take)
            .and_then(|x| x.states.get(s.index))
            .map_or(UnitQuaternion::identity(), |x| x.orientation)
    };
    let world: HashMap<(usize, usize), Vector3<f64>> = frames
        .iter()
        .map(|s| ((s.take, s.index), turn(s) * s.force))
        .collect();
    frames
        .iter()
        .map(|s| {
            let near: Vec<Vector3<f64>> = (s.index.saturating_sub(w)..=s.index + w)
                .filter_map(|k| world.get(&(s.take, k)).copied())
                .collect();
            let mean = near.iter().sum::<Vector3<f64>>() / near.len().max(1) as f64;
            Sample {
                force: turn(s).inverse() * mean,
                ..*s
            }
        })
        .collect()
}

/// The frame sets of terms 2-8 (see the module doc), labelled.
fn budget_frames(
    pairs: &[(Sample, Sample)],
    turns: &[UnitQuaternion<f64>],
    tframes: &[Sample],
    errors: &[(Vector3<f64>, nalgebra::Matrix3<f64>)],
    rms: f64,
) -> Vec<(&'static str, Vec<Sample>)> {
    let mut rng = Rng::new(1);
    let sigma = rms / 3f64.sqrt();
    let white: Vec<Sample> = tframes
        .iter()
        .map(|t| Sample {
            force: t.force + Vector3::new(rng.normal(), rng.normal(), rng.normal()) * sigma,
            ..*t
        })
        .collect();
    // A random permutation of the force frames' errors (Fisher-Yates).
    let mut order: Vec<usize> = (0..errors.len()).collect();
    for i in (1..order.len()).rev() {
        let j = ((rng.uniform() * (i + 1) as f64) as usize).min(i);
        order.swap(i, j);
    }
    let mut moved = Vec::with_capacity(pairs.len());
    let mut next = order.iter();
    for (s, t) in pairs {
        let mut f = Sample {
            use_force: s.use_force,
            use_torque: s.use_torque,
            ..*t
        };
        if s.use_force {
            if let Some((d, cov)) = next.next().and_then(|&k| errors.get(k)) {
                f.force += d;
                f.force_cov = *cov;
            }
        }
        moved.push(f);
    }
    let map = |f: &dyn Fn(&Sample, &Sample) -> Sample| -> Vec<Sample> {
        pairs.iter().map(|(s, t)| f(s, t)).collect()
    };
    let speed = |s: &Sample, t: &Sample| t.velocity * (s.velocity.norm() / t.velocity.norm());
    let turned = |f: &dyn Fn(&Sample, &Sample, &UnitQuaternion<f64>) -> Sample| -> Vec<Sample> {
        pairs
            .iter()
            .zip(turns)
            .map(|((s, t), q)| f(s, t, q))
            .collect()
    };
    vec![
        ("true states' frames", tframes.to_vec()),
        ("true forces + white noise at the measured RMS", white),
        (
            "true forces + the reconstruction's errors moved to random frames",
            moved,
        ),
        (
            "reconstructed forces, true V and Omega",
            map(&|s, t| Sample {
                velocity: t.velocity,
                angular_velocity: t.angular_velocity,
                gravity_body: t.gravity_body,
                ..*s
            }),
        ),
        (
            "true forces, reconstructed V and Omega",
            map(&|s, t| Sample {
                force: t.force,
                torque: t.torque,
                ..*s
            }),
        ),
        (
            "true forces and E, reconstructed |V|",
            map(&|s, t| Sample {
                velocity: speed(s, t),
                ..*t
            }),
        ),
        (
            "true forces and |V|, reconstructed E",
            map(&|s, t| Sample {
                velocity: s.velocity * (t.velocity.norm() / s.velocity.norm()),
                ..*t
            }),
        ),
        (
            "reconstructed forces in the true attitude, true V and Omega",
            turned(&|s, t, q| {
                let r = q.to_rotation_matrix();
                Sample {
                    force: q * s.force,
                    force_cov: r * s.force_cov * r.transpose(),
                    use_force: s.use_force,
                    use_torque: s.use_torque,
                    ..*t
                }
            }),
        ),
        (
            "true forces, reconstructed velocity in the true attitude",
            turned(&|s, t, q| Sample {
                velocity: q * s.velocity,
                use_force: s.use_force,
                use_torque: s.use_torque,
                ..*t
            }),
        ),
        ("the pipeline's frames", pairs.iter().map(|p| p.0).collect()),
    ]
}

/// Term 1: the truth grid's `C_F` least-squares projected onto SH degree
/// N (eq. 7's space; a negligible smoothing, no extensions), scored as
/// the fits: the error floor of a degree-N force model on this object.
fn projection(
    set: &crate::input::recording::RecordingSet,
    template: &[Sample],
    truth: &[[Vector3<f64>; 3]],
    score: &dyn Fn(&omniad_core::Coefficients<f64>) -> (f64, usize),
    out: &mut dyn Write,
) -> LabResult {
    let Some(t) = template.first() else {
        return Ok(());
    };
    let grid = super::truth_grid_frames(set, t, truth);
    for degree in [6u8, 8, 10, 12] {
        let base = zero_model(&set.object, degree)?;
        let mut cfg = FitConfig {
            degree,
            ..FitConfig::default()
        };
        cfg.lsq.cross_validate = false;
        cfg.lsq.extensions = false;
        cfg.lsq.smoothing = 1e-7;
        cfg.lsq.smoothness_order = Some(1);
        let m = pipeline::fit_samples(&base, &grid, set, &cfg)?;
        let (e, n) = score(&m);
        say!(
            out,
            "truth grid projected on degree {degree}: C_F {e:.2} % over {n}"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::lsq::tests::samples;
    use crate::input::recording::TakeKind;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};

    /// Each term takes exactly the part of the reconstruction it names.
    #[test]
    fn each_term_swaps_in_only_its_part() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 4).expect("model");
        let tframes = samples(&truth, 40, TakeKind::Drop);
        let mut rng = Rng::new(9);
        let mut noise = || Vector3::new(rng.normal(), rng.normal(), rng.normal());
        let pairs: Vec<(Sample, Sample)> = tframes
            .iter()
            .map(|t| {
                let s = Sample {
                    force: t.force + noise() * 0.1,
                    velocity: t.velocity * 1.05 + noise() * 0.2,
                    angular_velocity: t.angular_velocity + noise(),
                    force_cov: nalgebra::Matrix3::identity() * 0.01,
                    ..*t
                };
                (s, *t)
            })
            .collect();
        let errors: Vec<_> = pairs
            .iter()
            .map(|(s, t)| (s.force - t.force, s.force_cov))
            .collect();
        let turns: Vec<UnitQuaternion<f64>> = (0..pairs.len())
            .map(|k| UnitQuaternion::from_euler_angles(0.01 * k as f64, 0.2, -0.1))
            .collect();
        let terms = budget_frames(&pairs, &turns, &tframes, &errors, 0.1);
        let get = |label: &str| {
            terms
                .iter()
                .find(|(l, _)| l.starts_with(label))
                .map(|(_, f)| f.clone())
                .expect(label)
        };
        let zip = |f: &[Sample]| {
            f.iter()
                .zip(&pairs)
                .map(|(a, (s, t))| (*a, *s, *t))
                .collect::<Vec<_>>()
        };
        for (a, s, t) in zip(&get("reconstructed forces, true V")) {
            assert_eq!((a.force, a.velocity), (s.force, t.velocity));
        }
        for (a, s, t) in zip(&get("true forces, reconstructed V")) {
            assert_eq!((a.force, a.velocity), (t.force, s.velocity));
        }
        for (a, s, t) in zip(&get("true forces and E, reconstructed |V|")) {
            assert!((a.velocity.norm() - s.velocity.norm()).abs() < 1e-12);
            assert!((a.velocity.normalize() - t.velocity.normalize()).norm() < 1e-12);
        }
        for (a, s, t) in zip(&get("true forces and |V|, reconstructed E")) {
            assert!((a.velocity.norm() - t.velocity.norm()).abs() < 1e-12);
            assert!((a.velocity.normalize() - s.velocity.normalize()).norm() < 1e-12);
        }
        let rows = zip(&get("reconstructed forces in the true attitude"));
        for ((a, s, t), q) in rows.iter().zip(&turns) {
            assert!((a.force - q * s.force).norm() < 1e-12);
            assert_eq!(a.velocity, t.velocity);
        }
        let rows = zip(&get("true forces, reconstructed velocity in the true"));
        for ((a, s, t), q) in rows.iter().zip(&turns) {
            assert!((a.velocity - q * s.velocity).norm() < 1e-12);
            assert_eq!(a.force, t.force);
        }
        // The moved errors are the same errors, on other frames.
        let moved = get("true forces + the reconstruction's errors");
        let mut got: Vec<f64> = zip(&moved)
            .iter()
            .map(|(a, _, t)| (a.force - t.force).norm())
            .collect();
        let mut want: Vec<f64> = errors.iter().map(|e| e.0.norm()).collect();
        got.sort_by(f64::total_cmp);
        want.sort_by(f64::total_cmp);
        assert!(got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-12));
        let in_place = zip(&moved)
            .iter()
            .filter(|(a, s, _)| (a.force - s.force).norm() < 1e-12)
            .count();
        assert!(
            in_place < 5,
            "{in_place} of 40 errors stayed on their frame"
        );
        assert_eq!(
            get("the pipeline's frames"),
            pairs.iter().map(|p| p.0).collect::<Vec<_>>()
        );
    }
}
