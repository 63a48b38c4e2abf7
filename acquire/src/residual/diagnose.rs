//! What the held-out force residual of the base model looks like: how much
//! of it each candidate's columns explain (least squares over all frames,
//! R²), and its RMS against speed |V|, spin |Ω|, acceleration |dV/dt|
//! (body frame, from the smoothed states) and time in the take, in
//! equal-count bins. The words of the report are made from these.

use crate::residual::candidates::{Candidate, ALL};
use crate::residual::problems::Problems;
use nalgebra::{DMatrix, DVector, Vector3};
use serde::Serialize;

/// Bins per profile.
pub const BINS: usize = 8;

/// The residual's RMS against one quantity.
#[derive(Clone, Debug, Serialize)]
pub struct Profile {
    /// Quantity and unit, e.g. `|V| (m/s)`.
    pub quantity: String,
    /// Per bin: mean of the quantity, RMS residual force (N), frames.
    pub bins: Vec<(f64, f64, usize)>,
    /// Spearman-like trend: correlation of the bin index with the bin's
    /// RMS (-1..1).
    pub trend: f64,
}

/// The diagnosis of a residual.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// Per candidate: the share of the held-out residual its columns
    /// explain (R², 0..1).
    pub explained: Vec<(String, f64)>,
    /// Profiles against |V|, |Ω|, |dV/dt|, time in take.
    pub profiles: Vec<Profile>,
    /// Per frame: (unit direction of V, body frame; |residual| N), for the
    /// sphere map.
    #[serde(skip)]
    pub directions: Vec<(Vector3<f64>, f64)>,
}

/// R² of `r` (stacked) on the columns `cols` of every frame.
fn explained(p: &Problems, residuals: &[Vector3<f64>], c: Candidate) -> f64 {
    let range = p.columns_of(c);
    let w = range.len();
    let (mut ctc, mut ctr, mut rtr) = (DMatrix::zeros(w, w), DVector::zeros(w), 0.0);
    for (f, r) in p.force.frames.iter().zip(residuals) {
        let cols = f.extra.columns(range.start, w);
        ctc += cols.transpose() * cols;
        ctr += cols.transpose() * r;
        rtr += r.norm_squared();
    }
    let trace = ctc.trace().max(1e-300);
    for i in 0..w {
        ctc[(i, i)] += 1e-9 * trace / w as f64;
    }
    let Some(ch) = ctc.cholesky() else { return 0.0 };
    let x = ch.solve(&ctr);
    if rtr > 0.0 {
        (x.dot(&ctr) / rtr).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// RMS of `r` in [`BINS`] equal-count bins of `q`.
fn profile(name: &str, q: &[f64], r: &[Vector3<f64>]) -> Profile {
    let mut idx: Vec<usize> = (0..q.len()).filter(|&i| q[i].is_finite()).collect();
    idx.sort_by(|&a, &b| q[a].total_cmp(&q[b]));
    let per = idx.len().div_ceil(BINS).max(1);
    let bins: Vec<(f64, f64, usize)> = idx
        .chunks(per)
        .map(|c| {
            let n = c.len() as f64;
            let mean = c.iter().map(|&i| q[i]).sum::<f64>() / n;
            let rms = (c.iter().map(|&i| r[i].norm_squared()).sum::<f64>() / n).sqrt();
            (mean, rms, c.len())
        })
        .collect();
    Profile {
        quantity: name.to_owned(),
        trend: correlation(&bins),
        bins,
    }
}

/// Correlation of bin index and RMS.
fn correlation(bins: &[(f64, f64, usize)]) -> f64 {
    let n = bins.len() as f64;
    if n < 2.0 {
        return 0.0;
    }
    let mx = (n - 1.0) / 2.0;
    let my = bins.iter().map(|b| b.1).sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (i, b) in bins.iter().enumerate() {
        let (dx, dy) = (i as f64 - mx, b.1 - my);
        sxy += dx * dy;
        sxx += dx * dx;
        syy += dy * dy;
    }
    if sxx > 0.0 && syy > 0.0 {
        sxy / (sxx * syy).sqrt()
    } else {
        0.0
    }
}

/// Diagnoses the held-out residuals `residuals` (force frames' order).
pub(crate) fn diagnose(p: &Problems, residuals: &[Vector3<f64>]) -> Diagnosis {
    let s = &p.force_samples;
    let pick = |f: &dyn Fn(&crate::reconstruct::forces::Sample) -> f64| -> Vec<f64> {
        s.iter().map(f).collect()
    };
    let starts: Vec<f64> = s
        .iter()
        .map(|x| {
            s.iter()
                .filter(|y| y.take == x.take)
                .map(|y| y.t)
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let time: Vec<f64> = s.iter().zip(&starts).map(|(x, t0)| x.t - t0).collect();
    Diagnosis {
        explained: ALL
            .iter()
            .map(|c| (c.name().to_owned(), explained(p, residuals, *c)))
            .collect(),
        profiles: vec![
            profile("|V| (m/s)", &pick(&|x| x.velocity.norm()), residuals),
            profile(
                "|Ω| (rad/s)",
                &pick(&|x| x.angular_velocity.norm()),
                residuals,
            ),
            profile(
                "|dV/dt| (m/s²)",
                &pick(&|x| x.velocity_rate.norm()),
                residuals,
            ),
            profile("time in take (s)", &time, residuals),
        ],
        directions: s
            .iter()
            .zip(residuals)
            .map(|(x, r)| (x.velocity.normalize(), r.norm()))
            .collect(),
    }
}
