//! The torque fit (eqs. 6, 8): per frame
//! `T_k = Σ_i E^i_k q_k L³ Σ_lm β^i_lm Y_lm(E_k) − ½ρL⁵ |Ω_k| D Ω_k`,
//! one joint problem in (β, D); D is projected onto positive definite
//! matrices and β refitted.

use crate::fit::config::LsqConfig;
use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::damping::{omega_map, with_floor};
use crate::fit::normals::{per_take, solve, total, Normals, Rows};
use crate::fit::smoothing::{cross_validated, regularise, Smoothing, SMOOTHNESS_ORDERS};
use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, DVector, Vector3};
use omniad_core::sh::coeff_count;

/// The torque fit's normal equations per take and in total, unknowns
/// `(β¹, β², β³, d)` (eqs. 6, 8; unweighted), from the frames that pass
/// both stability tests.
fn torque_normals(samples: &[Sample], ctx: &FitContext, degree: usize) -> (Vec<Normals>, Normals) {
    let rows = TorqueRows { ctx, degree };
    let frames = samples.iter().filter(|s| s.use_torque).map(|s| (s.take, s));
    let takes = per_take(frames, &rows);
    let total = total(&takes, rows.dim());
    (takes, total)
}

/// The torque fit's rows: unknowns `(β¹, β², β³, d)`, a frame's three
/// [`TorqueRow`]s, unweighted.
struct TorqueRows<'a> {
    ctx: &'a FitContext,
    degree: usize,
}

impl<'a> Rows for TorqueRows<'a> {
    type Frame = &'a Sample;
    type Normals = Normals;

    fn dim(&self) -> usize {
        3 * coeff_count(self.degree) + 6
    }

    fn add(&self, s: &Self::Frame, nt: &mut Normals) {
        let n = coeff_count(self.degree);
        for row in torque_rows(s, self.ctx, self.degree) {
            accumulate(&mut nt.ata, &mut nt.atb, n, &row);
            nt.btb += row.target * row.target;
        }
    }
}

/// The torque fit's smoothness penalty on beta: `cfg.smoothing` of order
/// 1 (the Dirichlet energy), or, when `cfg.cross_validate`, the weight and
/// order of [`crate::fit::smoothing::SMOOTHING_GRID`] x [`SMOOTHNESS_ORDERS`] that
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
    let six = with_floor(&raw, cfg.damping_floor);
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

/// A frame's three torque equations as dense rows over `(β¹, β², β³, d)`
/// (3 x (3n + 6)), their targets, and the unit axes they are taken along
/// (as rows; the basis `E^i` when `V != 0`, else the body axes): the joint
/// problems of the residual analysis ([`crate::fit::joint`]) add their
/// columns along the same axes.
pub(crate) fn dense_rows(
    s: &Sample,
    ctx: &FitContext,
    degree: usize,
) -> (DMatrix<f64>, Vector3<f64>, nalgebra::Matrix3<f64>) {
    let n = coeff_count(degree);
    let rows = torque_rows(s, ctx, degree);
    let mut m = DMatrix::zeros(3, 3 * n + 6);
    let mut target = Vector3::zeros();
    for (i, r) in rows.iter().enumerate().take(3) {
        if let Some(b) = r.block {
            for (k, y) in r.sh.iter().enumerate() {
                m[(i, b * n + k)] = *y;
            }
        }
        for (j, d) in r.damp.iter().enumerate() {
            m[(i, 3 * n + j)] = *d;
        }
        target[i] = r.target;
    }
    let speed = s.velocity.norm();
    let axes = if speed > 0.0 {
        let (_, basis) = sh_and_basis(degree, &(s.velocity / speed), &ctx.pole);
        nalgebra::Matrix3::from_rows(&basis.map(|b| b.transpose()))
    } else {
        nalgebra::Matrix3::identity()
    };
    (m, target, axes)
}
