//! Residual analysis from the TRUE states of a set: fit the paper's model
//! (no extension) to the forces of `truth/`, then regress the per-frame
//! force residual on candidate terms the model lacks, body frame: `Ω⊗V`
//! (bilinear: Magnus, added-mass coupling), plus `Ω⊗Ω`, `V`, `|Ω|V`, the
//! body-frame acceleration (added mass) or gravity `Rᵀg` (buoyancy, added
//! mass), or `Rᵀg` alone.
//! Prints the RMS residual (N) before and after each:
//! `omniad lab missing-terms SET`.

use super::{say, LabResult};
use crate::fit::model::zero_model;
use crate::fit::residuals::frame_residuals;
use crate::input::recording::RecordingSet;
use crate::pipeline::{self, FitConfig};
use crate::reconstruct::forces::ForceStats;
use crate::synth::truth::true_trajectories;
use nalgebra::{DMatrix, DVector};
use std::io::Write;
use std::path::Path;

/// The missing-terms residual analysis of the set in `dir` (with `truth/`).
pub fn run(dir: &Path, out: &mut dyn Write) -> LabResult {
    let set = RecordingSet::load(dir)?;
    let smoothed = true_trajectories(dir, &set)?;
    let mut cfg = FitConfig::default();
    cfg.lsq.extensions = false;
    let mut stats = ForceStats::default();
    let frames = crate::reconstruct::run::samples(&set, &smoothed, &mut stats);
    let base = zero_model(&set.object, cfg.degree)?;
    let model = pipeline::fit_samples(&base, &frames, &set, &cfg)?;
    let res = frame_residuals(&model, &frames, set.world.air_density);
    let set_ref = &set;
    let used: Vec<usize> = (0..frames.len()).filter(|&i| frames[i].use_force).collect();
    // force residual regress on w_j v_k (9) per output
    for (name, torque, set) in [
        ("force bil", false, 0),
        ("force bil+ww", false, 1),
        ("force bil+v", false, 2),
        ("force bil+|w|v", false, 3),
        ("force bil+all", false, 4),
        ("force bil+acc", false, 5),
        ("force bil+acc+v", false, 6),
        ("force bil+g_body", false, 7),
        ("force g_body only", false, 8),
    ] {
        let n = used.len();
        let nf = [9, 15, 12, 12, 21, 12, 15, 12, 3][set];
        let mut a = DMatrix::<f64>::zeros(3 * n, 3 * nf);
        let mut b = DVector::<f64>::zeros(3 * n);
        let mut tot_f = 0.0;
        let mut tot_ref = 0.0;
        for (r, &i) in used.iter().enumerate() {
            let s = &frames[i];
            let w = s.angular_velocity;
            let v = s.velocity;
            let mut feat = vec![];
            if set != 8 {
                for j in 0..3 {
                    for k in 0..3 {
                        feat.push(w[j] * v[k]);
                    }
                }
            }
            if set == 7 || set == 8 {
                let q = smoothed[s.take].states[s.index].orientation;
                let g = q.inverse_transform_vector(&set_ref.world.gravity);
                for j in 0..3 {
                    feat.push(g[j]);
                }
            }
            if set == 1 || set == 4 {
                for j in 0..3 {
                    for k in j..3 {
                        feat.push(w[j] * w[k]);
                    }
                }
            }
            if set == 2 || set == 4 || set == 6 {
                for j in 0..3 {
                    feat.push(v[j]);
                }
            }
            if set == 5 || set == 6 {
                // Body-frame acceleration: F*/M + Rᵀg (eq. 9 solved for it).
                let q = smoothed[s.take].states[s.index].orientation;
                let acc = s.force / set_ref.object.mass
                    + q.inverse_transform_vector(&set_ref.world.gravity);
                for j in 0..3 {
                    feat.push(acc[j]);
                }
            }
            if set == 3 || set == 4 {
                for j in 0..3 {
                    feat.push(w.norm() * v[j]);
                }
            }
            let rr = if torque { res[i].torque } else { res[i].force };
            let reff = if torque { s.torque } else { s.force };
            for c in 0..3 {
                for (f, x) in feat.iter().enumerate() {
                    a[(3 * r + c, c * nf + f)] = *x;
                }
                b[3 * r + c] = rr[c];
            }
            tot_f += rr.norm_squared();
            tot_ref += reff.norm_squared();
        }
        let sol = a.clone().svd(true, true).solve(&b, 1e-12)?;
        let after = (&b - &a * &sol).norm_squared();
        say!(
            out,
            "{name}: measured RMS {:.4}, OmniAD residual RMS {:.4}, after bilinear {:.4}",
            (tot_ref / n as f64).sqrt(),
            (tot_f / n as f64).sqrt(),
            (after / n as f64).sqrt()
        );
    }
    Ok(())
}
