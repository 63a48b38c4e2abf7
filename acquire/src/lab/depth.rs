//! Depth diagnostics on a synthetic set: per take, the reprojection
//! residuals of the TRUE states, per-frame 6-DOF pose fits (Gauss-Newton
//! from the truth) and their line-of-sight error and Cramér-Rao bound:
//! `omniad lab depth SET`.

use super::{say, LabResult};
use crate::input::recording::RecordingSet;
use crate::input::state_csv::read_states;
use crate::input::tracks::Observation;
use crate::reconstruct::measurement::marker_pixel;
use nalgebra::{Quaternion, SMatrix, SVector, UnitQuaternion, Vector3};
use omniad_core::State;
use std::io::Write;
use std::path::Path;

/// The depth diagnostics of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let cam = set.camera.as_ref().ok_or("no camera")?;
    let eye = -cam.rotation.transpose() * cam.translation;
    let sigma = cam.pixel_noise;
    for take in &set.takes {
        let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
        let (mut res_sum, mut res_sq, mut nres) = (nalgebra::Vector2::zeros(), 0.0, 0usize);
        let (mut d_sum, mut d_sq, mut crb_info, mut crb_sq, mut n) = (0.0, 0.0, 0.0, 0.0, 0usize);
        for e in &take.epochs {
            let Observation::Markers(list) = &e.observation else {
                continue;
            };
            let Some(r) = truth.iter().find(|r| (r[0] - e.t).abs() < 1e-3) else {
                continue;
            };
            let s0 = State {
                position: Vector3::new(r[1], r[2], r[3]),
                orientation: UnitQuaternion::from_quaternion(Quaternion::new(
                    r[4], r[5], r[6], r[7],
                )),
                velocity: Vector3::zeros(),
                angular_velocity: Vector3::zeros(),
            };
            for m in list {
                let body = set.object.markers[m.marker].1;
                if let Some((p, _)) = marker_pixel(cam, &s0, &body) {
                    let d = m.pixel - p;
                    if d.norm() < 5.0 * sigma {
                        res_sum += d;
                        res_sq += d.norm_squared();
                        nres += 1;
                    }
                }
            }
            if list.len() < 4 {
                continue;
            }
            // Per-frame Gauss-Newton pose fit from the truth.
            let mut s = s0;
            let mut info = SMatrix::<f64, 6, 6>::zeros();
            for _ in 0..6 {
                info = SMatrix::<f64, 6, 6>::zeros();
                let mut g = SVector::<f64, 6>::zeros();
                for m in list {
                    let body = set.object.markers[m.marker].1;
                    let Some((p, h)) = marker_pixel(cam, &s, &body) else {
                        continue;
                    };
                    let h6 = h.fixed_view::<2, 6>(0, 0).into_owned();
                    let d = m.pixel - p;
                    if d.norm() > 5.0 * sigma {
                        continue;
                    }
                    info += h6.transpose() * h6 / (sigma * sigma);
                    g += h6.transpose() * d / (sigma * sigma);
                }
                let Some(step) = info.cholesky().map(|c| c.solve(&g)) else {
                    break;
                };
                s.position += Vector3::new(step[0], step[1], step[2]);
                s.orientation *=
                    UnitQuaternion::from_scaled_axis(Vector3::new(step[3], step[4], step[5]));
            }
            let los = (s0.position - eye).normalize();
            let d = (s.position - s0.position).dot(&los);
            if let Some(cov) = info.try_inverse() {
                let c = cov.fixed_view::<3, 3>(0, 0);
                let var = (los.transpose() * c * los)[0];
                crb_info += 1.0 / var;
                crb_sq += var;
            }
            d_sum += d;
            d_sq += d * d;
            n += 1;
        }
        let nf = n.max(1) as f64;
        say!(out,
            "{:8} reproj mean [{:5.2} {:5.2}] rms {:.2} px | per-frame LOS err mean {:6.2} rms {:5.2} cm, CRB rms {:5.2} cm, CRB of take mean {:4.2} cm ({n} frames)",
            take.name,
            res_sum.x / nres.max(1) as f64,
            res_sum.y / nres.max(1) as f64,
            (res_sq / nres.max(1) as f64 / 2.0).sqrt(),
            d_sum / nf * 100.0,
            (d_sq / nf).sqrt() * 100.0,
            (crb_sq / nf).sqrt() * 100.0,
            (1.0 / crb_info).sqrt() * 100.0,
        );
    }
    Ok(())
}
