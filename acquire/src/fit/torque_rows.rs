//! A frame's torque equations (eqs. 6, 8) and which frames a torque fit
//! takes: what the per-frame fit ([`crate::fit::torque`]) and the windowed
//! one ([`crate::fit::torque_window`]) both build their rows from.

use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::damping::omega_map;
use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, DVector, Vector3};
use omniad_core::sh::coeff_count;

/// Which frames a torque fit takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorqueFrames {
    /// Those that pass both stability tests (§5: `F·V <= 0` and
    /// `T·Ω <= 0`): the refinement's fits, whose model steers the next
    /// reconstruction (a spin-up frame's torque would feed the filter
    /// energy the air cannot give).
    Stable,
    /// Every frame that passes the no-thrust test `F·V <= 0`, spin-up
    /// frames included: the final torque fit
    /// ([`crate::fit::torque::refit_final_torque`]).
    /// The SH torque of eq. (8) is not dissipative, so a frame whose air
    /// spins the body up is physics, not an error (BENCHMARKS.md stop 15:
    /// the T·Ω test drops about half the frames, scattered over the
    /// directions, whatever the noise); only D must dissipate, and it is
    /// projected onto positive definite matrices as before.
    NoThrust,
}

impl TorqueFrames {
    /// Whether frame `s` enters a fit of this kind.
    pub fn takes(self, s: &Sample) -> bool {
        match self {
            Self::Stable => s.use_torque,
            Self::NoThrust => s.use_force,
        }
    }
}

/// One torque equation: `target = sh · β^block + damp · d`.
pub(crate) struct TorqueRow {
    block: Option<usize>,
    sh: Vec<f64>,
    damp: [f64; 6],
    /// The torque along the row's axis, N m.
    pub(crate) target: f64,
}

/// The torque equations of one frame, in the basis `E^i` when `V != 0`
/// (each row then touches one β block), else along the body axes.
pub(crate) fn torque_rows(s: &Sample, ctx: &FitContext, degree: usize) -> Vec<TorqueRow> {
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
pub(crate) fn accumulate(ata: &mut DMatrix<f64>, atb: &mut DVector<f64>, n: usize, r: &TorqueRow) {
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
