//! The force fit (eqs. 5, 7): alpha by weighted, smoothed least squares.
//!
//! Per frame k with dynamic pressure `q_k = ½ρ|V_k|²` and basis `E^i_k`:
//! `F_k·E^i_k = q_k L² Σ_lm α^i_lm Y_lm(E_k)` — one problem in
//! `(α¹, α², α³)`, each frame's three residuals weighted by the inverse of
//! its reconstruction uncertainty ([`crate::fit::weights`]).

use crate::fit::config::LsqConfig;
use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::normals::{per_take, total, Normals, Rows};
use crate::fit::smoothing::{
    cross_validated, regularise, Smoothing, DEFAULT_SMOOTHNESS_ORDER, SMOOTHNESS_ORDERS,
};
use crate::fit::thrust::enforce_no_thrust;
use crate::fit::weights::{force_frames, force_weights};
use crate::reconstruct::forces::Sample;
use nalgebra::{DVector, Matrix3, Vector3};
use omniad_core::sh::coeff_count;

/// The force fit's normal equations per take and in total. Unknowns
/// `(α¹, α², α³)`; frame k contributes the residuals `r_i = q L² Y(E)·α^i -
/// F·E^i` (eqs. 5, 7) weighted by `Bᵀ W B` ([`crate::fit::weights::force_weights`] in the basis
/// `B = [E¹ E²  E³]`), which couples the three components.
fn force_normals(samples: &[Sample], ctx: &FitContext, degree: usize) -> (Vec<Normals>, Normals) {
    let frames = force_frames(samples);
    let weights = force_weights(&frames);
    normals_with(&frames, &weights, ctx, degree)
}

/// One frame of the force fit in the basis `B = [E¹ E² E³]` at its
/// direction (eqs. 5, 7): `a = ½ρ|V|²L² Y(E)`, so the model's force is
/// `B (a·α¹, a·α², a·α³)ᵀ`; the weight `BᵀWB`; the target `BᵀF*`.
pub(crate) struct ForceRow {
    /// `½ρ|V|²L² Y(E)`, one entry per SH coefficient.
    pub a: DVector<f64>,
    /// `B`, the basis vectors as columns.
    pub basis: Matrix3<f64>,
    /// `BᵀWB`.
    pub weight: Matrix3<f64>,
    /// `BᵀF*`, N.
    pub target: Vector3<f64>,
}

/// [`ForceRow`] of a frame with a non-zero velocity and weight `w`.
pub(crate) fn force_row(s: &Sample, w: &Matrix3<f64>, ctx: &FitContext, degree: usize) -> ForceRow {
    let speed = s.velocity.norm();
    let (y, basis) = sh_and_basis(degree, &(s.velocity / speed), &ctx.pole);
    let l2 = ctx.reference_length.powi(2);
    let b = Matrix3::from_columns(&basis);
    ForceRow {
        a: DVector::from_vec(y) * (0.5 * ctx.air_density * speed * speed * l2),
        basis: b,
        weight: b.transpose() * w * b,
        target: b.transpose() * s.force,
    }
}

/// [`force_normals`] of given frames and weights.
pub(crate) fn normals_with(
    frames: &[&Sample],
    weights: &[Matrix3<f64>],
    ctx: &FitContext,
    degree: usize,
) -> (Vec<Normals>, Normals) {
    let rows = ForceRows { ctx, degree };
    let takes = per_take(
        frames.iter().zip(weights).map(|(s, w)| (s.take, (*s, w))),
        &rows,
    );
    let total = total(&takes, rows.dim());
    (takes, total)
}

/// The force fit's rows: unknowns `(α¹, α², α³)`, a frame's three rows
/// [`ForceRow`] weighted by `BᵀWB`.
struct ForceRows<'a> {
    ctx: &'a FitContext,
    degree: usize,
}

impl<'a> Rows for ForceRows<'a> {
    type Frame = (&'a Sample, &'a Matrix3<f64>);
    type Normals = Normals;

    fn dim(&self) -> usize {
        3 * coeff_count(self.degree)
    }

    fn add(&self, (s, w): &Self::Frame, nt: &mut Normals) {
        let n = coeff_count(self.degree);
        let ForceRow {
            a,
            weight: wb,
            target,
            ..
        } = force_row(s, w, self.ctx, self.degree);
        let wt = wb * target;
        for i in 0..3 {
            for j in 0..3 {
                nt.ata
                    .view_mut((i * n, j * n), (n, n))
                    .ger(wb[(i, j)], &a, &a, 1.0);
            }
            nt.atb.rows_mut(i * n, n).axpy(wt[i], &a, 1.0);
        }
        nt.btb += target.dot(&wt);
    }
}

/// The force fit's smoothness penalty: `cfg.smoothing` of order
/// `cfg.smoothness_order`, or the cross-validated choice ([`crate::fit::select`])
/// of weight (and order, when not given) when `cfg.cross_validate`.
pub fn force_smoothing(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> Smoothing {
    let (takes, total) = force_normals(samples, ctx, cfg.degree);
    force_penalty(&takes, &total, cfg)
}

/// [`force_smoothing`] from the force fit's normal equations.
fn force_penalty(takes: &[Normals], total: &Normals, cfg: &LsqConfig) -> Smoothing {
    let fallback = Smoothing {
        weight: cfg.smoothing,
        order: cfg.smoothness_order.unwrap_or(DEFAULT_SMOOTHNESS_ORDER),
    };
    if !cfg.cross_validate {
        return fallback;
    }
    // Held-out takes are scored with the fit's own weights, i.e. by their
    // likelihood under the smoother's covariance (the weights are nearly
    // its inverse): the poorly observed line-of-sight components would
    // otherwise dominate the score with noise. Scored unweighted instead,
    // C_F was worse on 7 of 9 sets (plate-mujoco 14.42 % vs 11.81 %;
    // BENCHMARKS.md stop 11).
    let held_out = takes;
    let orders = cfg
        .smoothness_order
        .map_or(SMOOTHNESS_ORDERS.to_vec(), |p| vec![p]);
    cross_validated(takes, held_out, total, &orders, fallback, cfg.degree).1
}

/// Alpha fitted without each take's frames in turn, with the fixed
/// `smoothing` (cross-fitting, `pipeline::cross_fit`): the normal
/// equations are built once and each take's share subtracted. Per take
/// with usable force frames, in order of first appearance: (take index,
/// alpha).
pub(crate) fn fit_force_leaving_out_each_take(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
    smoothing: Smoothing,
) -> Vec<(usize, [Vec<f64>; 3])> {
    let frames = force_frames(samples);
    let weights = force_weights(&frames);
    let (takes, total) = normals_with(&frames, &weights, ctx, cfg.degree);
    let mut ids: Vec<usize> = Vec::new();
    for f in &frames {
        if !ids.contains(&f.take) {
            ids.push(f.take);
        }
    }
    let folds: Vec<(usize, &Normals)> = ids.into_iter().zip(&takes).collect();
    let n = coeff_count(cfg.degree);
    crate::parallel::map(&folds, |_, &(id, take)| {
        let mut ata = &total.ata - &take.ata;
        let atb = &total.atb - &take.atb;
        regularise(&mut ata, 3, cfg.degree, smoothing);
        let x = enforce_no_thrust(ata, atb, cfg);
        let alpha = std::array::from_fn(|i| x.get(i * n..(i + 1) * n).unwrap_or(&[]).to_vec());
        (id, alpha)
    })
}

/// Fits alpha (force), enforcing no thrust (the tests' entry).
#[cfg(test)]
pub(crate) fn fit_force(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> [Vec<f64>; 3] {
    fit_force_smoothed(samples, ctx, cfg).0
}

/// [`fit_force`], also returning the smoothness penalty used
/// ([`force_smoothing`]); the normal equations are built once for both.
pub(crate) fn fit_force_smoothed(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> ([Vec<f64>; 3], Smoothing) {
    let (takes, total) = force_normals(samples, ctx, cfg.degree);
    let smoothing = force_penalty(&takes, &total, cfg);
    let Normals { mut ata, atb, .. } = total;
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let x = enforce_no_thrust(ata, atb, cfg);
    let n = coeff_count(cfg.degree);
    let alpha = std::array::from_fn(|i| x.get(i * n..(i + 1) * n).unwrap_or(&[]).to_vec());
    (alpha, smoothing)
}
