//! Diagnostic: which frames' torque error makes the C_T error? The fit
//! is linear in the torque samples, so the C_T error of the true frames
//! with `T* + m_k (T_rec - T*)` (the reconstruction's per-frame torque error
//! `e_k` of eq. 10 switched on by a mask `m_k`) shows what each group of
//! frames, or each part of the error, contributes: `omniad lab torquesplit
//! SET`. The frames keep their true velocities and stability flags, so only
//! the torque samples differ.
use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::fit::torque::TorqueFrames;
use crate::input::recording::{RecordingSet, TakeKind};
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::forces::Sample;
use crate::rng::Rng;
use crate::synth::truth::{read_coefficients, torque_directions, torque_error};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// A true frame and its reconstructed twin.
#[derive(Clone, Copy)]
pub(super) struct Pair {
    /// The frame of the true states (eqs. 9-10 on them).
    pub(super) truth: Sample,
    /// Reconstructed minus true torque, body frame, N m.
    pub(super) error: Vector3<f64>,
    /// Position in its take, 0..1.
    pub(super) along: f64,
    /// Reconstructed minus true Ω, body frame, rad/s.
    pub(super) omega_error: Vector3<f64>,
    /// Angle between the reconstructed and the true attitude, rad.
    pub(super) attitude_error: f64,
}

/// A number of a frame pair that splits the frames in halves.
type Measure = dyn Fn(&Pair) -> f64;

/// Fits masked errors and prints their C_T error.
struct Study<'a> {
    pairs: &'a [Pair],
    set: &'a RecordingSet,
    cfg: FitConfig,
    truth: Vec<[Vector3<f64>; 3]>,
    directions: Vec<Vector3<f64>>,
}

impl Study<'_> {
    /// C_T of the true frames with `errors` added to their torques.
    fn report(&self, out: &mut dyn Write, label: &str, errors: &[Vector3<f64>]) -> LabResult {
        let frames: Vec<Sample> = self
            .pairs
            .iter()
            .zip(errors)
            .map(|(p, e)| Sample {
                torque: p.truth.torque + e,
                ..p.truth
            })
            .collect();
        let base = zero_model(&self.set.object, self.cfg.degree)?;
        let m = pipeline::fit_samples(&base, &frames, self.set, &self.cfg)?;
        let (et, nt) = torque_error(&m, &self.truth, &self.directions);
        let used: Vec<f64> = errors
            .iter()
            .zip(self.pairs)
            .filter(|(e, p)| p.truth.use_torque && e.norm() > 0.0)
            .map(|(e, _)| e.norm_squared())
            .collect();
        let rms = (used.iter().sum::<f64>() / used.len().max(1) as f64).sqrt();
        say!(
            out,
            "{label}: C_T {:.2} % over {nt}; error on {} torque frames, RMS {rms:.5} N m",
            et * 100.0,
            used.len()
        );
        Ok(())
    }

    /// The errors of the frames `keep` selects, zero elsewhere.
    fn masked(&self, keep: &dyn Fn(&Pair) -> bool) -> Vec<Vector3<f64>> {
        self.pairs
            .iter()
            .map(|p| if keep(p) { p.error } else { Vector3::zeros() })
            .collect()
    }
}

/// The torque-error decomposition of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let w = super::fitted_with_truth(dir)?;
    let (set, fit, tframes, states) = (w.set, w.fit, w.truth_frames, w.truth_states);
    let mut pairs = paired(&set, &tframes, &fit.samples);
    for p in &mut pairs {
        let at = |s: &[crate::reconstruct::filter::Smoothed]| {
            s.get(p.truth.take)
                .and_then(|x| x.states.get(p.truth.index))
                .map(|x| x.orientation)
        };
        if let (Some(r), Some(t)) = (at(&fit.reconstruction), at(&states)) {
            p.attitude_error = r.angle_to(&t);
        }
    }
    let study = Study {
        pairs: &pairs,
        set: &set,
        cfg: w.cfg,
        truth: read_coefficients(&dir.join("truth/coefficients.csv"))?,
        directions: torque_directions(&tframes, TorqueFrames::Stable),
    };
    by_group(&study, out)?;
    by_part(&study, out)?;
    model_lean(&study, &fit.model, out)
}

/// How far the torque error leans on the fitted model: the regression of
/// `e` on the model's own torque error at the true state,
/// `d = T_model(V*, Ω*) - T*` (eqs. 6, 8), over the torque-fit frames,
/// whole and fast parts (`e`, `d` minus their 15-frame means): slope
/// `Σe·d / Σd·d` and the share of `Σ|e|²` it explains. A slope near 1
/// means the smoother's `dΩ/dt` follows the model it was given rather
/// than the markers.
fn model_lean(
    study: &Study,
    model: &omniad_core::Coefficients<f64>,
    out: &mut dyn Write,
) -> LabResult {
    let rho = study.set.world.air_density;
    let errors: Vec<Vector3<f64>> = study.pairs.iter().map(|p| p.error).collect();
    let model_errors: Vec<Vector3<f64>> = study
        .pairs
        .iter()
        .map(|p| {
            let t = &p.truth;
            model.wrench(&t.velocity, &t.angular_velocity, rho).torque - t.torque
        })
        .collect();
    let fast = |v: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
        let slow = moving_mean(study.pairs, v, 7);
        v.iter().zip(&slow).map(|(a, b)| a - b).collect()
    };
    for (label, e, d) in [
        ("whole", errors.clone(), model_errors.clone()),
        ("fast parts", fast(&errors), fast(&model_errors)),
    ] {
        let (mut ed, mut dd, mut ee) = (0.0, 0.0, 0.0);
        for ((e, d), p) in e.iter().zip(&d).zip(study.pairs) {
            if p.truth.use_torque {
                ed += e.dot(d);
                dd += d.norm_squared();
                ee += e.norm_squared();
            }
        }
        say!(
            out,
            "e on the model's torque error ({label}): slope {:.3}, explains {:.1} % of |e|²",
            ed / dd,
            100.0 * ed * ed / (dd * ee)
        );
    }
    Ok(())
}

/// Every true frame with a reconstructed twin.
pub(super) fn paired(set: &RecordingSet, truth: &[Sample], rec: &[Sample]) -> Vec<Pair> {
    let rec: HashMap<(usize, usize), &Sample> =
        rec.iter().map(|s| ((s.take, s.index), s)).collect();
    truth
        .iter()
        .filter_map(|t| {
            let r = rec.get(&(t.take, t.index))?;
            let n = set.takes.get(t.take).map_or(1, |k| k.epochs.len().max(1));
            Some(Pair {
                truth: *t,
                error: r.torque - t.torque,
                along: t.index as f64 / n as f64,
                omega_error: r.angular_velocity - t.angular_velocity,
                attitude_error: 0.0,
            })
        })
        .collect()
}

/// The error of each group of frames alone: take kind, place in the take,
/// halves by |Ω|, Ω's error, the attitude's error, |V|, |T*| and |e|.
fn by_group(study: &Study, out: &mut dyn Write) -> LabResult {
    study.report(out, "truth", &study.masked(&|_| false))?;
    study.report(out, "all errors", &study.masked(&|_| true))?;
    study.report(
        out,
        "drops only",
        &study.masked(&|p| p.truth.kind == TakeKind::Drop),
    )?;
    study.report(
        out,
        "spins only",
        &study.masked(&|p| p.truth.kind == TakeKind::Spin),
    )?;
    for (lo, hi) in [(0.0, 0.1), (0.1, 0.9), (0.9, 1.1)] {
        let keep = move |p: &Pair| p.along >= lo && p.along < hi;
        study.report(
            out,
            &format!("take fraction {lo}..{hi}"),
            &study.masked(&keep),
        )?;
    }
    let halves: [(&str, &Measure); 6] = [
        ("|Ω|", &|p| p.truth.angular_velocity.norm()),
        ("|ΔΩ| (Ω's error)", &|p| p.omega_error.norm()),
        ("attitude error", &|p| p.attitude_error),
        ("|V|", &|p| p.truth.velocity.norm()),
        ("|T*|", &|p| p.truth.torque.norm()),
        ("|e|", &|p| p.error.norm()),
    ];
    for (name, f) in halves {
        let mut v: Vec<f64> = study.pairs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        let m = v.get(v.len() / 2).copied().unwrap_or(0.0);
        study.report(
            out,
            &format!("{name} below median"),
            &study.masked(&|p| f(p) < m),
        )?;
        study.report(
            out,
            &format!("{name} above median"),
            &study.masked(&|p| f(p) >= m),
        )?;
    }
    Ok(())
}

/// The error split into parts: slow (15-frame mean) and fast, shuffled
/// across frames (same sizes, no tie to the state), along and across T*,
/// the gyroscopic term's and `I dΩ/dt`'s.
fn by_part(study: &Study, out: &mut dyn Write) -> LabResult {
    let pairs = study.pairs;
    let errors: Vec<Vector3<f64>> = pairs.iter().map(|p| p.error).collect();
    let slow = moving_mean(pairs, &errors, 7);
    study.report(out, "slow part (15-frame mean)", &slow)?;
    let fast: Vec<Vector3<f64>> = errors.iter().zip(&slow).map(|(e, s)| e - s).collect();
    study.report(out, "fast part", &fast)?;
    study.report(out, "errors shuffled across frames", &shuffled(&errors, 17))?;
    let along: Vec<Vector3<f64>> = pairs
        .iter()
        .map(|p| {
            let u = p
                .truth
                .torque
                .try_normalize(0.0)
                .unwrap_or_else(Vector3::zeros);
            u * u.dot(&p.error)
        })
        .collect();
    study.report(out, "error along T*", &along)?;
    let across: Vec<Vector3<f64>> = errors.iter().zip(&along).map(|(e, a)| e - a).collect();
    study.report(out, "error across T*", &across)?;
    let gyros: Vec<Vector3<f64>> = pairs
        .iter()
        .map(|p| gyro_error(&study.set.object.inertia, p))
        .collect();
    study.report(out, "gyroscopic part", &gyros)?;
    let accel: Vec<Vector3<f64>> = errors.iter().zip(&gyros).map(|(e, g)| e - g).collect();
    study.report(out, "I dΩ/dt part", &accel)
}

/// The gyroscopic term's share of a frame's error:
/// `(Ω×IΩ)_rec − (Ω×IΩ)*` (eq. 10), N m.
fn gyro_error(inertia: &Matrix3<f64>, p: &Pair) -> Vector3<f64> {
    let gyro = |w: &Vector3<f64>| w.cross(&(inertia * w));
    let w = p.truth.angular_velocity;
    gyro(&(w + p.omega_error)) - gyro(&w)
}

/// `v` in a random order (Fisher-Yates with a fixed seed).
fn shuffled(v: &[Vector3<f64>], seed: u64) -> Vec<Vector3<f64>> {
    let mut rng = Rng::new(seed);
    let mut out = v.to_vec();
    for i in (1..out.len()).rev() {
        let j = ((rng.uniform() * (i + 1) as f64) as usize).min(i);
        out.swap(i, j);
    }
    out
}

/// Centred `2w + 1`-frame mean of `values` (one per pair) over the
/// frames of the same take within `w` epochs (fewer near gaps and ends).
pub(super) fn moving_mean(pairs: &[Pair], values: &[Vector3<f64>], w: usize) -> Vec<Vector3<f64>> {
    (0..pairs.len())
        .map(|i| {
            let Some(c) = pairs.get(i) else {
                return Vector3::zeros();
            };
            let (lo, hi) = (i.saturating_sub(w), (i + w + 1).min(pairs.len()));
            let near: Vec<Vector3<f64>> = (lo..hi)
                .filter(|&j| {
                    pairs.get(j).is_some_and(|p| {
                        p.truth.take == c.truth.take && p.truth.index.abs_diff(c.truth.index) <= w
                    })
                })
                .filter_map(|j| values.get(j).copied())
                .collect();
            near.iter().sum::<Vector3<f64>>() / near.len().max(1) as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::recording::TakeKind;

    fn pair(take: usize, index: usize) -> Pair {
        let z = Vector3::zeros();
        Pair {
            truth: Sample {
                take,
                index,
                t: 0.0,
                kind: TakeKind::Drop,
                velocity: z,
                angular_velocity: z,
                velocity_rate: z,
                force: z,
                torque: z,
                gravity_body: z,
                force_cov: Matrix3::zeros(),
                use_force: true,
                use_torque: true,
            },
            error: z,
            along: 0.0,
            omega_error: z,
            attitude_error: 0.0,
        }
    }

    #[test]
    fn moving_mean_stays_within_a_take_and_its_consecutive_frames() {
        // Take 0: epochs 1, 2, 3, 7 (a gap); take 1: epoch 4.
        let pairs = [pair(0, 1), pair(0, 2), pair(0, 3), pair(0, 7), pair(1, 4)];
        let v: Vec<Vector3<f64>> = [1.0, 2.0, 3.0, 10.0, 100.0]
            .iter()
            .map(|x| Vector3::new(*x, 0.0, 0.0))
            .collect();
        let m = moving_mean(&pairs, &v, 1);
        let xs: Vec<f64> = m.iter().map(|x| x.x).collect();
        assert_eq!(xs, vec![1.5, 2.0, 2.5, 10.0, 100.0]);
    }

    #[test]
    fn shuffling_keeps_the_values() {
        let v: Vec<Vector3<f64>> = (0..50).map(|i| Vector3::new(i as f64, 0.0, 0.0)).collect();
        let s = shuffled(&v, 3);
        assert_ne!(s, v);
        let mut xs: Vec<f64> = s.iter().map(|x| x.x).collect();
        xs.sort_by(f64::total_cmp);
        assert_eq!(xs, v.iter().map(|x| x.x).collect::<Vec<_>>());
    }
}
