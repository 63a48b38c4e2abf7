//! Fitting the model extensions the paper's eqs. (5)-(6) lack, from the
//! force residuals `F* - F_model` of every frame that passes the no-thrust
//! test (drops and spins):
//! * the spin coupling (`omniad_core::spin_coupling`), a force bilinear in
//!   Ω and V (Magnus force, added-mass coupling):
//!   `F_i = ½ρL³ Σ_jk K_ijk Ω_j V_k`, 27 numbers;
//! * the gravity coupling (`omniad_core::gravity_coupling`), a force linear
//!   in gravity seen from the body (buoyancy, added mass):
//!   `F = ρL³ G Rᵀg`, 9 numbers.
//!
//! Which of them a set gets is decided on held-out data: for each candidate
//! ({spin}, {gravity}, {spin, gravity}) the terms are fitted by
//! ridge-regularised least squares without one take and scored on it
//! (leave-one-take-out, from per-take normal equations, over a grid of ridge
//! weights). The best candidate is kept when it lowers the held-out squared
//! force error by at least [`MIN_GAIN`] (and the pair must beat the better
//! single term by as much). A body whose air shows neither effect gets none
//! (numbers fitted to noise would only add noise). Kept terms are then
//! fitted jointly with alpha.

use crate::fit::config::LsqConfig;
use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::effects::{regressor, Terms};
use crate::fit::force::{fit_force_smoothed, force_row, normals_with, ForceRow};
use crate::fit::normals::{per_take, total, Accumulate, Normals, Rows};
use crate::fit::select::held_out_scores;
use crate::fit::smoothing::{regularise, Smoothing};
use crate::fit::thrust::enforce_no_thrust;
use crate::fit::weights::{force_frames, force_weights};
use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use omniad_core::gravity_coupling::GravityCoupling;
use omniad_core::sh::coeff_count;
use omniad_core::spin_coupling::SpinCoupling;
use std::ops::AddAssign;

/// Ridge weights tried, relative to the mean diagonal of the normal matrix.
pub const RIDGE_GRID: [f64; 5] = [1e-4, 1e-3, 1e-2, 1e-1, 1.0];

/// Smallest relative reduction of the held-out squared force error for
/// which an extension is kept (2 %).
pub const MIN_GAIN: f64 = 0.02;

/// Ridge of the extensions in the joint fit with alpha, relative to the
/// mean diagonal of their normal matrix: only keeps the system regular.
/// (The ridge that cross-validation picks for the terms alone shrank the
/// joint estimate: on a synthetic Magnus set of scale 0.02 it gave 0.0137,
/// this 0.0196.)
pub const COUPLING_RIDGE: f64 = 1e-6;

/// One take's normal equations: `XᵀX`, `XᵀR` (one column per force
/// component), `Σ|r|²`, frames.
#[derive(Clone, Debug)]
struct TakeNormals {
    xtx: DMatrix<f64>,
    xtr: DMatrix<f64>,
    rtr: f64,
    frames: usize,
}

impl TakeNormals {
    /// The normal equations of the regressors `rows` of these.
    fn restrict(&self, rows: &[usize]) -> Self {
        Self {
            xtx: self.xtx.select_rows(rows).select_columns(rows),
            xtr: self.xtr.select_rows(rows),
            rtr: self.rtr,
            frames: self.frames,
        }
    }
}

impl Accumulate for TakeNormals {
    fn zeros(width: usize) -> Self {
        Self {
            xtx: DMatrix::zeros(width, width),
            xtr: DMatrix::zeros(width, 3),
            rtr: 0.0,
            frames: 0,
        }
    }

    fn add(&mut self, other: &Self) {
        self.xtx += &other.xtx;
        self.xtr += &other.xtr;
        self.rtr += other.rtr;
        self.frames += other.frames;
    }
}

/// Per-take normal equations of the residuals `residual(s)` (N, body frame).
fn normals(
    samples: &[Sample],
    ctx: &FitContext,
    terms: Terms,
    residual: &dyn Fn(&Sample) -> Vector3<f64>,
) -> Vec<TakeNormals> {
    let frames = samples.iter().filter(|s| s.use_force).filter_map(|s| {
        let x = regressor(s, ctx, terms);
        let r = residual(s);
        let finite = x.iter().chain(r.iter()).all(|v| v.is_finite());
        finite.then_some((s.take, (x, r)))
    });
    per_take(frames, &ResidualRows(terms.width()))
}

/// The extension test's rows: `width` regressors per force component, the
/// residual force the three targets.
struct ResidualRows(usize);

impl Rows for ResidualRows {
    type Frame = (DVector<f64>, Vector3<f64>);
    type Normals = TakeNormals;

    fn dim(&self) -> usize {
        self.0
    }

    fn add(&self, (x, r): &Self::Frame, n: &mut TakeNormals) {
        n.xtx += x * x.transpose();
        n.xtr += x * r.transpose();
        n.rtr += r.norm_squared();
        n.frames += 1;
    }
}

fn ridge_solve(xtx: &DMatrix<f64>, xtr: &DMatrix<f64>, ridge: f64) -> Option<DMatrix<f64>> {
    let n = xtx.nrows();
    (xtx + DMatrix::identity(n, n) * ridge)
        .cholesky()
        .map(|c| c.solve(xtr))
}

/// Held-out squared error of the take `h` with the solution `k`:
/// `Σ|r - Xk|² = rᵀr - 2 tr(kᵀXᵀR) + tr(kᵀXᵀX k)`.
fn held_out_error(h: &TakeNormals, k: &DMatrix<f64>) -> f64 {
    h.rtr - 2.0 * k.component_mul(&h.xtr).sum() + (k.transpose() * &h.xtx * k).trace()
}

/// The extensions of a solution `k` (row f, column c: regressor f in force
/// component c) for `terms`.
fn extensions_of(
    k: &DMatrix<f64>,
    terms: Terms,
) -> (Option<SpinCoupling<f64>>, Option<GravityCoupling<f64>>) {
    let at = |f: usize, c: usize| k.get((f, c)).copied().unwrap_or(0.0);
    let spin = terms.spin.then(|| SpinCoupling {
        k: std::array::from_fn(|i| std::array::from_fn(|jk| at(jk, i))),
    });
    let offset = if terms.spin { 9 } else { 0 };
    let gravity = terms.gravity.then(|| GravityCoupling {
        g: Matrix3::from_fn(|i, j| at(offset + j, i)),
    });
    (spin, gravity)
}

/// The held-out test of the extensions on one fit's frames: the residual
/// analysis of the model loop, on held-out data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtensionTest {
    /// The terms kept (none: the paper's model alone predicts best).
    pub kept: Terms,
    /// RMS force residual of the model without extensions, N (over all
    /// frames of the test).
    pub held_out_rms_without: f64,
    /// RMS force residual with the spin coupling fitted without each take,
    /// N (best ridge weight).
    pub held_out_rms_spin: f64,
    /// The same with the gravity coupling, N.
    pub held_out_rms_gravity: f64,
    /// The same with both, N.
    pub held_out_rms_both: f64,
    /// Frames in the test.
    pub frames: usize,
    /// Takes in the test.
    pub takes: usize,
}

/// Leave-one-take-out held-out squared error of `terms` (best ridge of
/// [`RIDGE_GRID`], by [`crate::fit::select`]), from the per-take normal
/// equations `all` of both terms; `None` with fewer than
/// [`crate::fit::select::MIN_TAKES`] takes or when a fold
/// cannot be solved.
fn held_out(all: &[TakeNormals], terms: Terms) -> Option<(f64, f64, usize, usize)> {
    let rows = terms.rows();
    let takes: Vec<TakeNormals> = all.iter().map(|t| t.restrict(&rows)).collect();
    let total: TakeNormals = total(&takes, terms.width());
    let scale = total.xtx.trace() / terms.width() as f64;
    if scale.is_nan() || scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    let ridges = RIDGE_GRID.map(|r| r * scale);
    let scores = held_out_scores(takes.len(), &ridges, |ridge, i, score| {
        let t = takes.get(i)?;
        let k = ridge_solve(&(&total.xtx - &t.xtx), &(&total.xtr - &t.xtr), *ridge)?;
        Some(score + held_out_error(t, &k))
    })?;
    let mut best = f64::INFINITY;
    for score in scores {
        let score = score?;
        if score < best {
            best = score;
        }
    }
    Some((best, total.rtr, total.frames, takes.len()))
}

/// The held-out test of every candidate on `residual(s) = F*(s) -
/// F_model(s)`; `None` when it cannot be run (fewer than `crate::fit::select::MIN_TAKES`
/// takes, no usable frames).
pub fn test(
    samples: &[Sample],
    ctx: &FitContext,
    residual: &dyn Fn(&Sample) -> Vector3<f64>,
) -> Option<ExtensionTest> {
    // One pass over the frames (the residual evaluates eq. 5 per frame);
    // each candidate takes its block of the normal equations.
    let all = normals(samples, ctx, Terms::CANDIDATES[2], residual);
    let mut scores = [f64::INFINITY; 3];
    let (mut baseline, mut frames, mut takes) = (f64::NAN, 0, 0);
    for (score, terms) in scores.iter_mut().zip(Terms::CANDIDATES) {
        if let Some((s, b, f, t)) = held_out(&all, terms) {
            *score = s;
            (baseline, frames, takes) = (b, f, t);
        }
    }
    if frames == 0 || baseline.is_nan() {
        return None;
    }
    let [spin, gravity, both] = scores;
    let gain = |score: f64, reference: f64| score < (1.0 - MIN_GAIN) * reference;
    let best_single = if spin <= gravity {
        (spin, Terms::CANDIDATES[0])
    } else {
        (gravity, Terms::CANDIDATES[1])
    };
    let kept = if gain(both, best_single.0) && gain(both, baseline) {
        Terms::CANDIDATES[2]
    } else if gain(best_single.0, baseline) {
        best_single.1
    } else {
        Terms::default()
    };
    let rms = |sum: f64| (sum.max(0.0) / frames.max(1) as f64).sqrt();
    Some(ExtensionTest {
        kept,
        held_out_rms_without: rms(baseline),
        held_out_rms_spin: rms(spin),
        held_out_rms_gravity: rms(gravity),
        held_out_rms_both: rms(both),
        frames,
        takes,
    })
}

/// What [`fit_force_and_extensions`] found.
pub(crate) struct ForceFit {
    /// `alpha[i][k]`.
    pub alpha: [Vec<f64>; 3],
    /// The spin coupling, when kept.
    pub spin: Option<SpinCoupling<f64>>,
    /// The gravity coupling, when kept.
    pub gravity: Option<GravityCoupling<f64>>,
    /// The held-out test that decided (when it was run).
    pub test: Option<ExtensionTest>,
    /// The smoothness penalty of alpha.
    pub smoothing: Smoothing,
}

/// Alpha and, when `cfg.extensions`, the extensions the held-out test
/// keeps ([`test`] on the residuals of alpha alone), fitted jointly with
/// alpha in the force fit's weighted, smoothed least squares so that
/// neither absorbs the other's share of the forces.
pub(crate) fn fit_force_and_extensions(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> ForceFit {
    let (plain, smoothing) = fit_force_smoothed(samples, ctx, cfg);
    let none = |alpha, test| ForceFit {
        alpha,
        spin: None,
        gravity: None,
        test,
        smoothing,
    };
    if !cfg.extensions {
        return none(plain, None);
    }
    let a = plain.clone();
    let residual = move |s: &Sample| s.force - alpha_force(&a, s, ctx, cfg.degree);
    let tested = test(samples, ctx, &residual);
    let terms = tested.map(|t| t.kept).unwrap_or_default();
    if terms.width() == 0 {
        return none(plain, tested);
    }
    let frames = force_frames(samples);
    let weights = force_weights(&frames);
    let (_, Normals { mut ata, atb, .. }) = normals_with(&frames, &weights, ctx, cfg.degree);
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let (ata, atb) = with_extensions(ata, atb, &frames, &weights, ctx, cfg.degree, terms);
    let x = enforce_no_thrust(ata, atb, cfg);
    let n = coeff_count(cfg.degree);
    let m = terms.width();
    let alpha = std::array::from_fn(|i| x.get(i * n..(i + 1) * n).unwrap_or(&[]).to_vec());
    let u = x.get(3 * n..3 * n + 3 * m).unwrap_or(&[]);
    if u.len() != 3 * m || !u.iter().all(|v| v.is_finite()) {
        return none(plain, tested);
    }
    // Unknown c*m + f is regressor f in force component c.
    let (spin, gravity) = extensions_of(&DMatrix::from_column_slice(m, 3, u), terms);
    ForceFit {
        alpha,
        spin,
        gravity,
        test: tested,
        smoothing,
    }
}

/// The force fit's normal equations in alpha (`3n` unknowns, already
/// smoothed) extended by the `3m` unknowns of `terms` (`m` regressors
/// [`regressor`] per force component; unknown `3n + c m + f`): frame k's
/// residual in the basis is `[a a a | BᵀX] [α; u] - BᵀF` with `X` the
/// 3 x 3m map `u -> (x·u_c)_c`, weighted by `BᵀWB` as in [`normals_with`].
/// The extensions get a ridge of [`COUPLING_RIDGE`] times their mean
/// diagonal.
fn with_extensions(
    ata: DMatrix<f64>,
    atb: DVector<f64>,
    frames: &[&Sample],
    weights: &[Matrix3<f64>],
    ctx: &FitContext,
    degree: usize,
    terms: Terms,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = coeff_count(degree);
    let m = terms.width();
    let extra = 3 * m;
    let dim = 3 * n + extra;
    let mut big = DMatrix::<f64>::zeros(dim, dim);
    big.view_mut((0, 0), (3 * n, 3 * n)).copy_from(&ata);
    let mut rhs = DVector::<f64>::zeros(dim);
    rhs.rows_mut(0, 3 * n).copy_from(&atb);
    for (s, w) in frames.iter().zip(weights) {
        let ForceRow {
            a,
            basis: b,
            weight: wb,
            target,
        } = force_row(s, w, ctx, degree);
        let x = regressor(s, ctx, terms);
        // BᵀX: row i (basis component), column c m + f = B[c][i] x_f.
        let btx = DMatrix::from_fn(3, extra, |i, col| b[(col / m, i)] * x[col % m]);
        let wbtx = wb * &btx;
        for i in 0..3 {
            let row = wbtx.row(i);
            for (p, ap) in a.iter().enumerate() {
                for q in 0..extra {
                    big[(i * n + p, 3 * n + q)] += ap * row[q];
                }
            }
        }
        big.view_mut((3 * n, 3 * n), (extra, extra))
            .add_assign(&(btx.transpose() * &wbtx));
        rhs.rows_mut(3 * n, extra)
            .add_assign(&(wbtx.transpose() * target));
    }
    for p in 0..3 * n {
        for q in 3 * n..dim {
            big[(q, p)] = big[(p, q)];
        }
    }
    let mean = (3 * n..dim).map(|i| big[(i, i)]).sum::<f64>() / extra as f64;
    for i in 3 * n..dim {
        big[(i, i)] += COUPLING_RIDGE * mean.max(1e-300);
    }
    (big, rhs)
}

/// Eq. (5) with the fitted `alpha` at a sample: `q L² Σ_i E^i (Y(E)·α^i)`
/// (body frame, N; zero when V = 0).
fn alpha_force(alpha: &[Vec<f64>; 3], s: &Sample, ctx: &FitContext, degree: usize) -> Vector3<f64> {
    let speed = s.velocity.norm();
    if speed.is_nan() || speed <= 0.0 {
        return Vector3::zeros();
    }
    let (y, basis) = sh_and_basis(degree, &(s.velocity / speed), &ctx.pole);
    let q = 0.5 * ctx.air_density * speed * speed * ctx.reference_length.powi(2);
    basis
        .iter()
        .zip(alpha)
        .map(|(e, a)| e * (q * y.iter().zip(a).map(|(y, a)| y * a).sum::<f64>()))
        .sum()
}
