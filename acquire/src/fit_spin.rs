//! Fitting the spin-coupling extension (`omniad_core::spin_coupling`): the
//! force bilinear in Ω and V that eq. (5) cannot express (Magnus force,
//! added-mass coupling), `F_i = ½ρL³ Σ_jk K_ijk Ω_j V_k`.
//!
//! K is fitted by ridge-regularised least squares on the force residuals
//! `F* - F_model` of every frame that passes the no-thrust test (drops and
//! spins: spins carry most of the information). It is kept only when it
//! predicts held-out takes better than no coupling: leave-one-take-out
//! cross-validation over a grid of ridge weights, from per-take normal
//! equations, must lower the held-out squared error by at least
//! [`MIN_GAIN`]. A body whose air shows no such coupling gets none (27
//! more numbers fitted to noise would only add noise).

use crate::fit_cv::Normals;
use crate::fit_lsq::{
    enforce_no_thrust, fit_force_smoothed, force_frames, force_row, force_smoothing, force_weights,
    normals_with, regularise, sh_and_basis, FitContext, ForceRow, LsqConfig,
};
use crate::forces::Sample;
use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};
use omniad_core::sh::coeff_count;
use omniad_core::spin_coupling::{SpinCoupling, TERMS};
use std::ops::AddAssign;

/// Ridge weights tried, relative to the mean diagonal of the normal matrix.
pub const RIDGE_GRID: [f64; 5] = [1e-4, 1e-3, 1e-2, 1e-1, 1.0];

/// Smallest relative reduction of the held-out squared force error for
/// which the coupling is kept (2 %).
pub const MIN_GAIN: f64 = 0.02;

/// Fewest takes for the cross-validation (with fewer, no coupling is fitted).
pub const MIN_TAKES: usize = 3;

type M9 = SMatrix<f64, 9, 9>;
type M93 = SMatrix<f64, 9, 3>;

/// One take's normal equations: `XᵀX`, `XᵀR`, `Σ|r|²` with rows
/// `x = ½ρL³ (Ω ⊗ V)` and the three residual components as right-hand sides.
#[derive(Clone, Copy, Debug)]
struct TakeNormals {
    xtx: M9,
    xtr: M93,
    rtr: f64,
    frames: usize,
}

impl TakeNormals {
    fn zero() -> Self {
        Self {
            xtx: M9::zeros(),
            xtr: M93::zeros(),
            rtr: 0.0,
            frames: 0,
        }
    }
}

/// The regressor of one frame, `½ρL³ (Ω ⊗ V)` in the layout of
/// `SpinCoupling::k` rows.
pub(crate) fn regressor(s: &Sample, ctx: &FitContext) -> SMatrix<f64, 9, 1> {
    let scale = 0.5 * ctx.air_density * ctx.reference_length.powi(3);
    let (w, v) = (s.angular_velocity, s.velocity);
    SMatrix::<f64, 9, 1>::from_fn(|r, _| w[r / 3] * v[r % 3] * scale)
}

/// Per-take normal equations of the residuals `residual(s)` (N, body frame).
fn normals(
    samples: &[Sample],
    ctx: &FitContext,
    residual: &dyn Fn(&Sample) -> Vector3<f64>,
) -> Vec<TakeNormals> {
    let mut takes: Vec<(usize, TakeNormals)> = Vec::new();
    for s in samples.iter().filter(|s| s.use_force) {
        let x = regressor(s, ctx);
        let r = residual(s);
        if !x.iter().chain(r.iter()).all(|v| v.is_finite()) {
            continue;
        }
        let at = match takes.iter().position(|(t, _)| *t == s.take) {
            Some(i) => i,
            None => {
                takes.push((s.take, TakeNormals::zero()));
                takes.len() - 1
            }
        };
        if let Some((_, n)) = takes.get_mut(at) {
            n.xtx += x * x.transpose();
            n.xtr += x * r.transpose();
            n.rtr += r.norm_squared();
            n.frames += 1;
        }
    }
    takes.into_iter().map(|(_, n)| n).collect()
}

fn ridge_solve(xtx: &M9, xtr: &M93, ridge: f64) -> Option<M93> {
    (xtx + M9::identity() * ridge)
        .cholesky()
        .map(|c| c.solve(xtr))
}

/// Held-out squared error of the take `h` with the tensor `k`:
/// `Σ|r - Xk|² = rᵀr - 2 tr(kᵀXᵀR) + tr(kᵀXᵀX k)`.
fn held_out_error(h: &TakeNormals, k: &M93) -> f64 {
    h.rtr - 2.0 * k.component_mul(&h.xtr).sum() + (k.transpose() * h.xtx * k).trace()
}

/// The cross-validated test of the spin coupling on one fit's frames: the
/// residual analysis of the model loop, on held-out data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplingTest {
    /// K fitted to the residuals when kept, else `None`.
    pub coupling: Option<SpinCoupling<f64>>,
    /// RMS force residual of the model without the coupling, N (over all
    /// frames of the test; the term held out is K, so this is alpha's
    /// residual).
    pub held_out_rms_without: f64,
    /// RMS force residual on each take with K fitted to the other takes, N
    /// (best ridge weight).
    pub held_out_rms_with: f64,
    /// Frames in the test.
    pub frames: usize,
    /// Takes in the test.
    pub takes: usize,
}

/// Fits K to `residual(s) = F*(s) - F_model(s)` over the samples; `None`
/// when cross-validation does not keep it (see the module docs).
pub fn fit(
    samples: &[Sample],
    ctx: &FitContext,
    residual: &dyn Fn(&Sample) -> Vector3<f64>,
) -> Option<SpinCoupling<f64>> {
    test(samples, ctx, residual).and_then(|t| t.coupling)
}

/// Leave-one-take-out test of the coupling on `residual(s) = F*(s) -
/// F_model(s)`: `None` when it cannot be run (fewer than [`MIN_TAKES`]
/// takes, no spin in the frames).
pub fn test(
    samples: &[Sample],
    ctx: &FitContext,
    residual: &dyn Fn(&Sample) -> Vector3<f64>,
) -> Option<CouplingTest> {
    let takes = normals(samples, ctx, residual);
    if takes.len() < MIN_TAKES {
        return None;
    }
    let mut total = TakeNormals::zero();
    for t in &takes {
        total.xtx += t.xtx;
        total.xtr += t.xtr;
        total.rtr += t.rtr;
        total.frames += t.frames;
    }
    let scale = total.xtx.trace() / 9.0;
    if scale.is_nan() || scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    let baseline: f64 = takes.iter().map(|t| t.rtr).sum();
    let mut best: Option<(f64, f64)> = None;
    for ridge in RIDGE_GRID.map(|r| r * scale) {
        let mut score = 0.0;
        for t in &takes {
            let k = ridge_solve(&(total.xtx - t.xtx), &(total.xtr - t.xtr), ridge)?;
            score += held_out_error(t, &k);
        }
        if best.is_none_or(|(s, _)| score < s) {
            best = Some((score, ridge));
        }
    }
    let (score, ridge) = best?;
    let rms = |sum: f64| (sum.max(0.0) / total.frames.max(1) as f64).sqrt();
    // NaN scores keep no coupling.
    let keep = !score.is_nan() && score < (1.0 - MIN_GAIN) * baseline;
    let coupling = if keep {
        ridge_solve(&total.xtx, &total.xtr, ridge).map(|k| coupling_of(&k))
    } else {
        None
    };
    Some(CouplingTest {
        coupling,
        held_out_rms_without: rms(baseline),
        held_out_rms_with: rms(score),
        frames: total.frames,
        takes: takes.len(),
    })
}

/// The tensor of a solution whose row `3j + k`, column `i` multiplies
/// `Ω_j V_k` in force component i.
fn coupling_of(k: &M93) -> SpinCoupling<f64> {
    SpinCoupling {
        k: std::array::from_fn(|i| std::array::from_fn(|jk| k[(jk, i)])),
    }
}

/// Alpha and, when `cfg.spin_coupling`, the spin coupling. Whether K is
/// kept is decided by cross-validation on the residuals of alpha alone
/// ([`crate::fit_spin`]); a kept K is then fitted jointly with alpha in the
/// force fit's (weighted, smoothed) least squares, so that neither absorbs
/// the other's share of the forces. (The ridge that cross-validation
/// picks for K alone shrank the joint K: on a synthetic Magnus set of
/// scale 0.02 it gave 0.0137, [`COUPLING_RIDGE`] 0.0196.)
pub(crate) fn fit_force_and_coupling(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> (
    [Vec<f64>; 3],
    Option<SpinCoupling<f64>>,
    Option<CouplingTest>,
) {
    let smoothing = force_smoothing(samples, ctx, cfg);
    let plain = fit_force_smoothed(samples, ctx, cfg, smoothing);
    if !cfg.spin_coupling {
        return (plain, None, None);
    }
    let a = plain.clone();
    let residual = move |s: &Sample| s.force - alpha_force(&a, s, ctx, cfg.degree);
    let tested = test(samples, ctx, &residual);
    if tested.is_none_or(|t| t.coupling.is_none()) {
        return (plain, None, tested);
    }
    let frames = force_frames(samples);
    let weights = force_weights(&frames);
    let (_, Normals { mut ata, atb, .. }) = normals_with(&frames, &weights, ctx, cfg.degree);
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let (ata, atb) = with_coupling(ata, atb, &frames, &weights, ctx, cfg.degree);
    let x = enforce_no_thrust(ata, atb, cfg);
    let n = coeff_count(cfg.degree);
    let alpha = std::array::from_fn(|i| x.get(i * n..(i + 1) * n).unwrap_or(&[]).to_vec());
    let k = x.get(3 * n..3 * n + TERMS).unwrap_or(&[]);
    if k.len() != TERMS || !k.iter().all(|v| v.is_finite()) {
        return (plain, None, tested);
    }
    let coupling = SpinCoupling {
        k: std::array::from_fn(|i| std::array::from_fn(|jk| k[9 * i + jk])),
    };
    (alpha, Some(coupling), tested)
}

/// The force fit's normal equations in alpha (`3n` unknowns, already
/// smoothed) extended by the 27 unknowns `K_ijk` (index `9i + 3j + k`):
/// frame k's residual in the basis is `[a a a | BᵀX] [α; K] - BᵀF` with
/// `X` the 3x27 map `K -> ½ρL³ K(Ω⊗V)`, weighted by `BᵀWB` as in
/// [`normals_with`]. K gets a ridge of [`COUPLING_RIDGE`] times its mean
/// diagonal.
fn with_coupling(
    ata: DMatrix<f64>,
    atb: DVector<f64>,
    frames: &[&Sample],
    weights: &[Matrix3<f64>],
    ctx: &FitContext,
    degree: usize,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = coeff_count(degree);
    let dim = 3 * n + TERMS;
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
        let x = regressor(s, ctx);
        // BᵀX: row i (basis component), column 9c + jk = B[c][i] x_jk.
        let btx =
            nalgebra::SMatrix::<f64, 3, TERMS>::from_fn(|i, col| b[(col / 9, i)] * x[col % 9]);
        let wbtx = wb * btx;
        for i in 0..3 {
            let row = wbtx.row(i);
            for (p, ap) in a.iter().enumerate() {
                for q in 0..TERMS {
                    big[(i * n + p, 3 * n + q)] += ap * row[q];
                }
            }
        }
        big.view_mut((3 * n, 3 * n), (TERMS, TERMS))
            .add_assign(&(btx.transpose() * wbtx));
        rhs.rows_mut(3 * n, TERMS)
            .add_assign(&(wbtx.transpose() * target));
    }
    for p in 0..3 * n {
        for q in 3 * n..dim {
            big[(q, p)] = big[(p, q)];
        }
    }
    let mean = (3 * n..dim).map(|i| big[(i, i)]).sum::<f64>() / TERMS as f64;
    for i in 3 * n..dim {
        big[(i, i)] += COUPLING_RIDGE * mean.max(1e-300);
    }
    (big, rhs)
}

/// Ridge of K in the joint fit, relative to the mean diagonal of its
/// normal matrix: only keeps the system regular.
pub const COUPLING_RIDGE: f64 = 1e-6;

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
