//! The default fit (§6, improved): regularised linear least squares of
//! alpha, beta and D directly on the reconstructed frames, in force space.
//!
//! Per frame k with dynamic pressure `q_k = ½ρ|V_k|²` and basis `E^i_k`:
//! `F_k·E^i_k = q_k L² Σ_lm α^i_lm Y_lm(E_k)` (eqs. 5, 7) — one problem in
//! `(α¹, α², α³)`, each frame's three residuals weighted by the inverse of
//! its reconstruction uncertainty (generalised least squares, see
//! `force_weights`) — and
//! `T_k = Σ_i E^i_k q_k L³ Σ_lm β^i_lm Y_lm(E_k) - ½ρL⁵ |Ω_k| D Ω_k` (eqs. 6, 8),
//! one joint problem in (β, D). Smoothness: Tikhonov on a Sobolev-type norm
//! `Σ l(l+1) (l(l+1)/(N(N+1)))^(p-1) c_lm²` scaled by the data, its weight
//! and order `p` chosen for each of the two problems by leave-one-take-out
//! cross-validation ([`crate::fit::select`]). D is projected onto positive definite
//! matrices and β refitted; `C_F(E)·E < 0` (no thrust, §5) is enforced on a
//! dense direction grid by penalty rows.

use crate::fit::damping::{matrix, omega_map, positive_definite};
use crate::fit::select::Normals;
use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use omniad_core::basis::vector_basis;
use omniad_core::sh::{coeff_count, evaluate, MAX_COEFFS};
use omniad_core::spin_coupling::SpinCoupling;

/// Settings of the least-squares fit.
#[derive(Clone, Debug, PartialEq)]
pub struct LsqConfig {
    /// SH degree N.
    pub degree: usize,
    /// Smoothing weight relative to the mean data weight per coefficient
    /// (dimensionless; default 1e-3). The force and torque fits choose
    /// their own by cross-validation when `cross_validate` is set and there
    /// are enough takes (see [`crate::fit::select`]).
    pub smoothing: f64,
    /// Order `p` of the force fit's smoothness penalty: SH degree `l` is
    /// penalised by `l(l+1) (l(l+1)/(N(N+1)))^(p-1)`, a Sobolev-type norm
    /// of order `p` on the sphere, scaled so that degree N costs `N(N+1)`
    /// whatever `p` (the smoothing weights of every order then sit in the
    /// same range). Order 1 is the Dirichlet energy; higher orders hold
    /// the highest degrees down harder, where the reconstruction's noise
    /// would otherwise go. `None` (default): cross-validation chooses it
    /// among [`SMOOTHNESS_ORDERS`] together with the weight (order 2 without
    /// cross-validation). The torque fit always chooses among all orders
    /// (order 1 without cross-validation).
    pub smoothness_order: Option<u32>,
    /// Choose the force and torque fits' smoothing by leave-one-take-out
    /// cross-validation (default true).
    pub cross_validate: bool,
    /// Fit the model extensions (spin coupling, gravity coupling) and
    /// keep those that predict held-out takes better
    /// ([`crate::fit::extensions`]; default true).
    pub extensions: bool,
    /// Smallest allowed eigenvalue of D relative to its largest (default 1e-3).
    pub damping_floor: f64,
    /// Required margin of `-C_F(E)·E` (default 1e-3).
    pub thrust_margin: f64,
}

impl Default for LsqConfig {
    fn default() -> Self {
        Self {
            degree: 8,
            smoothing: 1e-3,
            smoothness_order: None,
            cross_validate: true,
            extensions: true,
            damping_floor: 1e-3,
            thrust_margin: 1e-3,
        }
    }
}

/// The fitted numbers (body frame, non-dimensional).
#[derive(Clone, Debug, PartialEq)]
pub struct RawModel {
    /// `alpha[i][k]`, i = basis component, k = SH index.
    pub alpha: [Vec<f64>; 3],
    /// `beta[i][k]`.
    pub beta: [Vec<f64>; 3],
    /// `[d11, d22, d33, d12, d13, d23]`.
    pub damping: [f64; 6],
    /// The spin-coupling extension, when fitted and kept.
    pub spin_coupling: Option<SpinCoupling<f64>>,
    /// The gravity-coupling extension, when fitted and kept.
    pub gravity_coupling: Option<omniad_core::gravity_coupling::GravityCoupling<f64>>,
    /// The held-out test that decided on them (when it was run).
    pub extension_test: Option<crate::fit::extensions::ExtensionTest>,
    /// The smoothness penalties of the force and torque fits (least
    /// squares only).
    pub smoothing: Option<FitSmoothing>,
}

/// The smoothness penalties a least-squares fit used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSmoothing {
    /// Of alpha ([`force_smoothing`]).
    pub force: Smoothing,
    /// Of beta ([`torque_smoothing`]).
    pub torque: Smoothing,
}

/// Object constants the fit needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitContext {
    /// Air density ρ, kg/m³.
    pub air_density: f64,
    /// Reference length L, m.
    pub reference_length: f64,
    /// Unit pole Z.
    pub pole: Vector3<f64>,
}

/// SH values `Y_lm(E)` and the basis at a unit direction.
pub(crate) fn sh_and_basis(
    degree: usize,
    e: &Vector3<f64>,
    pole: &Vector3<f64>,
) -> (Vec<f64>, [Vector3<f64>; 3]) {
    let mut y = [0.0; MAX_COEFFS];
    let n = evaluate(degree, e, &mut y);
    (y.get(..n).unwrap_or(&[]).to_vec(), vector_basis(e, pole))
}

/// Penalty of each SH coefficient up to `degree` for smoothness order
/// `order` (see [`LsqConfig::smoothness_order`]).
fn roughness(degree: usize, order: u32) -> Vec<f64> {
    let top = (degree * (degree + 1)).max(1) as f64;
    let power = i32::try_from(order.max(1) - 1).unwrap_or(0);
    (0..=degree)
        .flat_map(|l| {
            let ll = (l * (l + 1)) as f64;
            std::iter::repeat_n(ll * (ll / top).powi(power), 2 * l + 1)
        })
        .collect()
}

/// Orders of the smoothness penalty that cross-validation chooses among
/// (see [`LsqConfig::smoothness_order`]).
pub const SMOOTHNESS_ORDERS: [u32; 4] = [1, 2, 3, 4];

/// The order used without cross-validation.
pub const DEFAULT_SMOOTHNESS_ORDER: u32 = 2;

/// The smoothness penalty: the smoothing weight `λ`, and the order `p` of
/// [`LsqConfig::smoothness_order`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoothing {
    /// `λ`, relative to the mean data weight per coefficient.
    pub weight: f64,
    /// `p`.
    pub order: u32,
}

/// Adds `λ · scale · penalty(l)` (plus a tiny ridge) to the diagonal
/// blocks of `ata`, `scale` the mean data weight per coefficient and
/// `penalty` that of [`roughness`].
pub(crate) fn regularise(
    ata: &mut DMatrix<f64>,
    blocks: usize,
    degree: usize,
    smoothing: Smoothing,
) {
    let scale = data_scale(ata, blocks * coeff_count(degree));
    regularise_scaled(ata, blocks, degree, smoothing, scale);
}

/// The mean of the first `n` diagonal entries (1 when not positive).
fn data_scale(ata: &DMatrix<f64>, n: usize) -> f64 {
    let scale = (0..n).map(|i| ata[(i, i)]).sum::<f64>() / n.max(1) as f64;
    if scale > 0.0 {
        scale
    } else {
        1.0
    }
}

/// [`regularise`] with a given `scale`.
fn regularise_scaled(
    ata: &mut DMatrix<f64>,
    blocks: usize,
    degree: usize,
    smoothing: Smoothing,
    scale: f64,
) {
    let n = coeff_count(degree);
    let rough = roughness(degree, smoothing.order);
    for b in 0..blocks {
        for (k, r) in rough.iter().enumerate() {
            ata[(b * n + k, b * n + k)] += scale * (smoothing.weight * r + 1e-9);
        }
    }
}

fn solve(ata: &DMatrix<f64>, atb: &DVector<f64>) -> DVector<f64> {
    match ata.clone().cholesky() {
        Some(c) => c.solve(atb),
        None => ata
            .clone()
            .lu()
            .solve(atb)
            .unwrap_or_else(|| DVector::zeros(atb.len())),
    }
}

/// Frames the force fit uses: every frame that passes the no-thrust test,
/// drops (K1) and spins (K2) alike. (§6 fits C_F on K1 only; the spin
/// takes add directions the drops rarely reach, and with the spin-coupling
/// extension their spin-driven forces are modelled rather than misread as
/// C_F. Measured on every set in BENCHMARKS.md: C_F error lower on 8 of 9.)
pub(crate) fn force_frames(samples: &[Sample]) -> Vec<&Sample> {
    samples
        .iter()
        .filter(|s| s.use_force && s.velocity.norm() > 0.0)
        .collect()
}

/// The error the smoother's covariance does not describe (SH truncation,
/// unsteady air), as a fraction of the mean reconstruction variance (see
/// [`force_weights`]). Small: the covariance is roughly calibrated (it
/// over-states the error, `examples/forcenoise`), and C_F is insensitive
/// below a few per cent (openbox-clean 6.80 / 6.78 / 6.77 % at 0.03 / 0.01
/// / 0.001; 7.28 % at 1, 7.96 % unweighted; BENCHMARKS.md stop 11; with
/// the markers-only covariances of stop 12, 5.91 / 5.86 / 5.84 % at 0.03 /
/// 0.01 / 0.003, 6.07 % at 0.1). It only keeps the weights bounded where
/// `Σ_F` is nearly singular.
pub const UNDESCRIBED_VARIANCE: f64 = 0.01;

/// Per-frame weights of the force residual (body frame), generalised least
/// squares: `σ² (Σ_F + σ² I)⁻¹`, `Σ_F` the smoother's posterior covariance
/// of the reconstructed force ([`Sample::force_cov`]; large along the
/// poorly observed line of sight, §5; in the refinement the model-free
/// reconstruction's, plus the velocity's spread) and `σ² I` the error it does not
/// describe, [`UNDESCRIBED_VARIANCE`] times the mean reconstruction variance
/// `mean tr Σ_F / 3`: along an eigenvector of `Σ_F` of variance `λ` the
/// weight is `σ²/(σ² + λ)`, in (0, 1] (no weight can blow up), nearly
/// `σ²/λ` (the inverse covariance) where the reconstruction is uncertain.
/// Identity when no frame has a covariance (e.g. true states).
pub(crate) fn force_weights(frames: &[&Sample]) -> Vec<Matrix3<f64>> {
    let mean =
        frames.iter().map(|s| s.force_cov.trace()).sum::<f64>() / (3 * frames.len().max(1)) as f64;
    let sigma2 = UNDESCRIBED_VARIANCE * mean;
    let identity = Matrix3::identity();
    if sigma2 <= 0.0 || !sigma2.is_finite() {
        return vec![identity; frames.len()];
    }
    frames
        .iter()
        .map(|s| {
            (s.force_cov + identity * sigma2)
                .try_inverse()
                .map_or(identity, |w| w * sigma2)
        })
        .collect()
}

/// The force fit's normal equations per take and in total. Unknowns
/// `(α¹, α², α³)`; frame k contributes the residuals `r_i = q L² Y(E)·α^i -
/// F·E^i` (eqs. 5, 7) weighted by `Bᵀ W B` ([`force_weights`] in the basis
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
    let n = coeff_count(degree);
    let mut takes: Vec<(usize, Normals)> = Vec::new();
    for (s, w) in frames.iter().zip(weights) {
        let ForceRow {
            a,
            weight: wb,
            target,
            ..
        } = force_row(s, w, ctx, degree);
        let at = match takes.iter().position(|(t, _)| *t == s.take) {
            Some(i) => i,
            None => {
                takes.push((s.take, Normals::zeros(3 * n)));
                takes.len() - 1
            }
        };
        let Some((_, nt)) = takes.get_mut(at) else {
            continue;
        };
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
    let takes: Vec<Normals> = takes.into_iter().map(|(_, t)| t).collect();
    let mut total = Normals::zeros(3 * n);
    for t in &takes {
        total.add(t);
    }
    (takes, total)
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
    cross_validated(takes, held_out, total, &orders, fallback, cfg.degree)
}

/// The penalty of [`crate::fit::select::SMOOTHING_GRID`] x `orders` whose fits
/// without each take predict that take best, on unknowns whose first three
/// blocks are SH coefficients.
fn cross_validated(
    takes: &[Normals],
    held_out: &[Normals],
    total: &Normals,
    orders: &[u32],
    fallback: Smoothing,
    degree: usize,
) -> Smoothing {
    let scale = data_scale(&total.ata, 3 * coeff_count(degree));
    let candidates: Vec<Smoothing> = orders
        .iter()
        .flat_map(|&order| {
            crate::fit::select::SMOOTHING_GRID
                .iter()
                .map(move |&weight| Smoothing { weight, order })
        })
        .collect();
    crate::fit::select::choose(takes, held_out, total, &candidates, fallback, |m, p| {
        regularise_scaled(m, 3, degree, p, scale);
    })
}

/// Fits alpha (force), enforcing no thrust.
pub fn fit_force(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> [Vec<f64>; 3] {
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

/// Solves for alpha (the first `coeff_count` unknowns are alpha^1) and adds
/// penalty rows `Σ α¹_k Y_k(E) = -margin` at directions of a dense grid
/// where `C_F(E)·E > -margin`, until none is left.
pub(crate) fn enforce_no_thrust(
    mut ata: DMatrix<f64>,
    mut atb: DVector<f64>,
    cfg: &LsqConfig,
) -> Vec<f64> {
    let grid = crate::fit::paper::sphere_grid(64, 32);
    let dim = ata.nrows();
    let ys: Vec<DVector<f64>> = grid
        .iter()
        .map(|(e, _)| {
            let y = sh_and_basis(cfg.degree, e, e).0;
            let mut v = DVector::zeros(dim);
            v.rows_mut(0, y.len().min(dim))
                .copy_from_slice(y.get(..dim.min(y.len())).unwrap_or(&[]));
            v
        })
        .collect();
    let weight = (0..ata.nrows())
        .map(|i| ata[(i, i)])
        .fold(0.0, f64::max)
        .max(1e-12)
        * 10.0;
    let mut x = solve(&ata, &atb);
    for _ in 0..20 {
        let mut violated = false;
        for y in &ys {
            if y.dot(&x) > -cfg.thrust_margin {
                ata.ger(weight, y, y, 1.0);
                atb.axpy(-cfg.thrust_margin * weight, y, 1.0);
                violated = true;
            }
        }
        if !violated {
            break;
        }
        x = solve(&ata, &atb);
    }
    x.as_slice().to_vec()
}

/// The torque fit's normal equations per take and in total, unknowns
/// `(β¹, β², β³, d)` (eqs. 6, 8; unweighted), from the frames that pass
/// both stability tests.
fn torque_normals(samples: &[Sample], ctx: &FitContext, degree: usize) -> (Vec<Normals>, Normals) {
    let n = coeff_count(degree);
    let dim = 3 * n + 6;
    let mut takes: Vec<(usize, Normals)> = Vec::new();
    for s in samples.iter().filter(|s| s.use_torque) {
        let at = match takes.iter().position(|(t, _)| *t == s.take) {
            Some(i) => i,
            None => {
                takes.push((s.take, Normals::zeros(dim)));
                takes.len() - 1
            }
        };
        let Some((_, nt)) = takes.get_mut(at) else {
            continue;
        };
        for row in torque_rows(s, ctx, degree) {
            accumulate(&mut nt.ata, &mut nt.atb, n, &row);
            nt.btb += row.target * row.target;
        }
    }
    let takes: Vec<Normals> = takes.into_iter().map(|(_, t)| t).collect();
    let mut total = Normals::zeros(dim);
    for t in &takes {
        total.add(t);
    }
    (takes, total)
}

/// The torque fit's smoothness penalty on beta: `cfg.smoothing` of order
/// 1 (the Dirichlet energy), or, when `cfg.cross_validate`, the weight and
/// order of [`crate::fit::select::SMOOTHING_GRID`] x [`SMOOTHNESS_ORDERS`] that
/// predicts held-out takes' torques best. (The torque model steers the
/// reconstructed attitude, and through it the direction E every force
/// frame is filed under: openbox-clean's C_F went from 7.74 % to 7.35 %
/// with a ten times heavier fixed weight, see BENCHMARKS.md.)
pub fn torque_smoothing(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> Smoothing {
    let (takes, total) = torque_normals(samples, ctx, cfg.degree);
    torque_penalty(&takes, &total, cfg)
}

/// [`torque_smoothing`] from the torque fit's normal equations.
fn torque_penalty(takes: &[Normals], total: &Normals, cfg: &LsqConfig) -> Smoothing {
    let fallback = Smoothing {
        weight: cfg.smoothing,
        order: 1,
    };
    if !cfg.cross_validate {
        return fallback;
    }
    cross_validated(
        takes,
        takes,
        total,
        &SMOOTHNESS_ORDERS,
        fallback,
        cfg.degree,
    )
}

/// Fits beta and D jointly on the frames that pass both stability tests;
/// also returns the smoothness penalty used ([`torque_smoothing`]).
pub fn fit_torque(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> ([Vec<f64>; 3], [f64; 6], Smoothing) {
    let n = coeff_count(cfg.degree);
    let (takes, total) = torque_normals(samples, ctx, cfg.degree);
    let smoothing = torque_penalty(&takes, &total, cfg);
    let Normals { mut ata, atb, .. } = total;
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let x = solve(&ata, &atb);
    let raw: [f64; 6] = std::array::from_fn(|i| x[3 * n + i]);
    let d = positive_definite(&matrix(&raw), 0.0);
    let floor = cfg.damping_floor * d.symmetric_eigen().eigenvalues.max().max(1e-9);
    let d = positive_definite(&matrix(&raw), floor);
    let six = [
        d[(0, 0)],
        d[(1, 1)],
        d[(2, 2)],
        d[(0, 1)],
        d[(0, 2)],
        d[(1, 2)],
    ];
    // Refit beta with D fixed: move the damping term to the right-hand side.
    let sub = ata.view((0, 0), (3 * n, 3 * n)).into_owned();
    let cross = ata.view((0, 3 * n), (3 * n, 6)).into_owned();
    let rhs = atb.rows(0, 3 * n).into_owned() - cross * DVector::from_row_slice(&six);
    let beta = solve(&sub, &rhs);
    (
        std::array::from_fn(|i| beta.rows(i * n, n).as_slice().to_vec()),
        six,
        smoothing,
    )
}

/// One torque equation: `target = sh · β^block + damp · d`.
struct TorqueRow {
    block: Option<usize>,
    sh: Vec<f64>,
    damp: [f64; 6],
    target: f64,
}

/// The torque equations of one frame, in the basis `E^i` when `V != 0`
/// (each row then touches one β block), else along the body axes.
fn torque_rows(s: &Sample, ctx: &FitContext, degree: usize) -> Vec<TorqueRow> {
    let l = ctx.reference_length;
    let speed = s.velocity.norm();
    let damp = omega_map(&s.angular_velocity)
        * (-0.5 * ctx.air_density * l.powi(5) * s.angular_velocity.norm());
    let row_of =
        |axis: &Vector3<f64>| -> [f64; 6] { std::array::from_fn(|j| axis.dot(&damp.column(j))) };
    if speed > 0.0 {
        let (y, basis) = sh_and_basis(degree, &(s.velocity / speed), &ctx.pole);
        let q = 0.5 * ctx.air_density * speed * speed * l.powi(3);
        let sh: Vec<f64> = y.iter().map(|v| v * q).collect();
        basis
            .iter()
            .enumerate()
            .map(|(i, b)| TorqueRow {
                block: Some(i),
                sh: sh.clone(),
                damp: row_of(b),
                target: s.torque.dot(b),
            })
            .collect()
    } else {
        [Vector3::x(), Vector3::y(), Vector3::z()]
            .iter()
            .map(|b| TorqueRow {
                block: None,
                sh: Vec::new(),
                damp: row_of(b),
                target: s.torque.dot(b),
            })
            .collect()
    }
}

/// Adds one sparse row to the normal equations.
fn accumulate(ata: &mut DMatrix<f64>, atb: &mut DVector<f64>, n: usize, r: &TorqueRow) {
    let d0 = 3 * n;
    if let Some(b) = r.block {
        let o = b * n;
        for (i, yi) in r.sh.iter().enumerate() {
            for (j, yj) in r.sh.iter().enumerate() {
                ata[(o + i, o + j)] += yi * yj;
            }
            for (j, dj) in r.damp.iter().enumerate() {
                ata[(o + i, d0 + j)] += yi * dj;
                ata[(d0 + j, o + i)] += yi * dj;
            }
            atb[o + i] += yi * r.target;
        }
    }
    for (i, di) in r.damp.iter().enumerate() {
        for (j, dj) in r.damp.iter().enumerate() {
            ata[(d0 + i, d0 + j)] += di * dj;
        }
        atb[d0 + i] += di * r.target;
    }
}

/// The full least-squares fit.
pub fn fit(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> RawModel {
    let force = crate::fit::extensions::fit_force_and_extensions(samples, ctx, cfg);
    let (beta, damping, torque) = fit_torque(samples, ctx, cfg);
    RawModel {
        alpha: force.alpha,
        beta,
        damping,
        spin_coupling: force.spin,
        gravity_coupling: force.gravity,
        extension_test: force.test,
        smoothing: Some(FitSmoothing {
            force: force.smoothing,
            torque,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::recording::TakeKind;
    use crate::synth::rng::Rng;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use omniad_core::gravity_coupling::GravityCoupling;

    /// Exact samples of a known model at random directions and spins.
    pub(crate) fn samples(
        model: &omniad_core::Coefficients<f64>,
        n: usize,
        kind: TakeKind,
    ) -> Vec<Sample> {
        let mut rng = Rng::new(3);
        (0..n)
            .map(|i| {
                let velocity = rng.direction() * rng.range(2.0, 6.0);
                let angular_velocity = rng.direction() * rng.range(0.0, 15.0);
                let w = model.wrench(&velocity, &angular_velocity, 1.2);
                Sample {
                    take: 0,
                    index: i,
                    t: 0.0,
                    kind,
                    velocity,
                    angular_velocity,
                    force: w.force,
                    torque: w.torque,
                    gravity_body: nalgebra::Vector3::new(0.0, 0.0, -9.81),
                    force_cov: nalgebra::Matrix3::zeros(),
                    use_force: true,
                    use_torque: true,
                }
            })
            .collect()
    }

    #[test]
    fn recovers_a_known_model_from_exact_frames() {
        let spec = ObjectSpec::of(SynthObject::Box);
        let truth = truth_model(&spec, 6).expect("model");
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: truth.reference_length(),
            pole: truth.pole(),
        };
        let frames = samples(&truth, 3000, TakeKind::Drop);
        let raw = fit(
            &frames,
            &ctx,
            &LsqConfig {
                degree: 6,
                smoothing: 1e-7,
                ..LsqConfig::default()
            },
        );
        let model = crate::fit::model::with_raw(&truth, &raw).expect("model");
        let (mut num, mut den) = (0.0, 0.0);
        for e in crate::panel::fibonacci_sphere(200) {
            let (a, b) = (
                model.at_direction(&e).expect("dir"),
                truth.at_direction(&e).expect("dir"),
            );
            num += (a.force - b.force).norm_squared() + (a.torque - b.torque).norm_squared();
            den += b.force.norm_squared();
        }
        assert!(
            (num / den).sqrt() < 0.02,
            "relative error {}",
            (num / den).sqrt()
        );
        assert!(
            (model.damping() - truth.damping()).norm() < 0.05 * truth.damping().norm(),
            "{} vs {}",
            model.damping(),
            truth.damping()
        );
    }

    /// Frames of `truth` spread over five takes, each take's forces off by
    /// a take-constant body-frame vector of size `offset` x the force scale.
    fn takes_with_offsets(truth: &omniad_core::Coefficients<f64>, offset: f64) -> Vec<Sample> {
        let mut rng = Rng::new(9);
        let bias: Vec<Vector3<f64>> = (0..5).map(|_| rng.direction() * offset).collect();
        samples(truth, 1500, TakeKind::Drop)
            .into_iter()
            .enumerate()
            .map(|(i, mut s)| {
                s.take = i % 5;
                let q = 0.5 * 1.2 * s.velocity.norm_squared() * truth.reference_length().powi(2);
                s.force += bias.get(s.take).copied().unwrap_or_default() * q;
                s
            })
            .collect()
    }

    /// Exact frames of `truth` spread over six takes (cross-validation
    /// needs takes), with a little noise so that the fit is not exact.
    fn six_takes(truth: &omniad_core::Coefficients<f64>) -> Vec<Sample> {
        let mut rng = Rng::new(17);
        let mut frames = samples(truth, 3000, TakeKind::Drop);
        for (i, s) in frames.iter_mut().enumerate() {
            s.take = i % 6;
            s.gravity_body = rng.direction() * 9.81;
            if let Some(g) = truth.gravity_coupling() {
                s.force += g.force(&s.gravity_body, 1.2, truth.reference_length());
            }
            s.force += rng.direction() * 1e-3;
        }
        frames
    }

    /// The fit context of `model` at ρ = 1.2 and a degree-6 fit.
    fn degree_six(model: &omniad_core::Coefficients<f64>) -> (FitContext, LsqConfig) {
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: model.reference_length(),
            pole: model.pole(),
        };
        let cfg = LsqConfig {
            degree: 6,
            ..LsqConfig::default()
        };
        (ctx, cfg)
    }

    #[test]
    fn gravity_coupling_is_found_when_present_and_only_then() {
        let plain = truth_model(&ObjectSpec::of(SynthObject::Plate), 6).expect("model");
        let (ctx, cfg) = degree_six(&plain);
        assert_eq!(fit(&six_takes(&plain), &ctx, &cfg).gravity_coupling, None);
        // Buoyancy of 2.4 litres.
        let buoyant = GravityCoupling::buoyancy(2.4e-3, plain.reference_length());
        let mut floated = plain.clone();
        floated
            .set_gravity_coupling(Some(buoyant))
            .expect("coupling");
        let raw = fit(&six_takes(&floated), &ctx, &cfg);
        assert_eq!(raw.spin_coupling, None);
        let g = raw.gravity_coupling.expect("gravity coupling kept");
        assert!((g.g - buoyant.g).abs().max() < 1e-3, "G {}", g.g);
    }

    #[test]
    fn spin_coupling_is_found_when_present_and_only_then() {
        let spec = ObjectSpec::of(SynthObject::Plate);
        let plain = truth_model(&spec, 6).expect("model");
        let (ctx, cfg) = degree_six(&plain);
        assert_eq!(fit(&six_takes(&plain), &ctx, &cfg).spin_coupling, None);
        let mut spun = plain.clone();
        let magnus = SpinCoupling::magnus(0.02);
        spun.set_spin_coupling(Some(magnus)).expect("coupling");
        let raw = fit(&six_takes(&spun), &ctx, &cfg);
        let k = raw.spin_coupling.expect("coupling kept");
        for (got, want) in k.k.iter().flatten().zip(magnus.k.iter().flatten()) {
            assert!((got - want).abs() < 1e-3, "K {:?}", k.k);
        }
        // Alpha is the plain model's: the coupling took its share.
        let alpha = &raw.alpha[0];
        for (k, got) in alpha.iter().enumerate().take(coeff_count(6)) {
            let truth = plain.alpha(0, k).expect("alpha");
            assert!((got - truth).abs() < 2e-3, "alpha1[{k}] {got} vs {truth}");
        }
        let off = LsqConfig {
            extensions: false,
            ..cfg
        };
        assert_eq!(fit(&six_takes(&spun), &ctx, &off).spin_coupling, None);
    }

    #[test]
    fn cross_validation_smooths_noisy_takes_more() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let (ctx, cfg) = degree_six(&truth);
        for order in SMOOTHNESS_ORDERS {
            let cfg = LsqConfig {
                smoothness_order: Some(order),
                ..cfg.clone()
            };
            let clean = force_smoothing(&takes_with_offsets(&truth, 0.0), &ctx, &cfg);
            let noisy = force_smoothing(&takes_with_offsets(&truth, 0.5), &ctx, &cfg);
            assert_eq!((clean.order, noisy.order), (order, order));
            assert!(clean.weight <= 1e-3, "clean frames smoothed by {clean:?}");
            assert!(
                noisy.weight > clean.weight,
                "noisy {noisy:?} <= clean {clean:?}"
            );
        }
        // Left to choose, it picks one of the orders offered.
        let chosen = force_smoothing(&takes_with_offsets(&truth, 0.5), &ctx, &cfg);
        assert!(SMOOTHNESS_ORDERS.contains(&chosen.order), "{chosen:?}");
    }

    #[test]
    fn higher_orders_penalise_low_degrees_less_and_the_top_degree_alike() {
        let first = roughness(8, 1);
        assert_eq!(first.len(), 81);
        for order in 2..=4 {
            let r = roughness(8, order);
            // Degree 8 (the last 17 coefficients) costs 72 whatever the order.
            assert!(r.iter().skip(64).all(|v| (v - 72.0).abs() < 1e-9), "{r:?}");
            // Degree 0 is free; degrees 1-7 cost less than at order 1, and
            // less the higher the order.
            assert_eq!(r.first().copied(), Some(0.0));
            let lower = roughness(8, order - 1);
            for k in 1..64 {
                assert!(r[k] < lower[k], "order {order}, coefficient {k}");
            }
        }
    }

    #[test]
    fn weights_are_bounded_and_discount_the_uncertain_direction() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Box), 4).expect("model");
        let mut frames = samples(&truth, 4, TakeKind::Drop);
        let refs: Vec<&Sample> = frames.iter().collect();
        assert!(force_weights(&refs)
            .iter()
            .all(|w| *w == Matrix3::identity()));
        for (i, s) in frames.iter_mut().enumerate() {
            s.force_cov = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0 + 9.0 * i as f64));
        }
        let refs: Vec<&Sample> = frames.iter().collect();
        for w in force_weights(&refs) {
            let e = w.symmetric_eigen().eigenvalues;
            assert!(e.max() <= 1.0 + 1e-12 && e.min() > 0.0, "{e}");
            assert!(w[(2, 2)] <= w[(0, 0)] + 1e-12);
        }
    }

    #[test]
    fn never_fits_thrust() {
        // Frames whose drag points along E (thrust) must not produce C_F·E >= 0.
        let spec = ObjectSpec::of(SynthObject::Plate);
        let truth = truth_model(&spec, 4).expect("model");
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: truth.reference_length(),
            pole: truth.pole(),
        };
        let mut frames = samples(&truth, 500, TakeKind::Drop);
        for s in &mut frames {
            s.force = -s.force;
        }
        let cfg = LsqConfig {
            degree: 4,
            ..LsqConfig::default()
        };
        let alpha = fit_force(&frames, &ctx, &cfg);
        for e in crate::panel::fibonacci_sphere(500) {
            let (y, _) = sh_and_basis(4, &e, &ctx.pole);
            let drag: f64 = y.iter().zip(&alpha[0]).map(|(a, b)| a * b).sum();
            assert!(drag < 0.0, "C_F·E = {drag} at {e:?}");
        }
    }
}
