//! The two joint problems of the residual analysis, built once with every
//! candidate's columns ([`crate::fit::joint`]): the force fit (unknowns
//! alpha, eqs. 5, 7, weighted and smoothed as the base fit) and the torque
//! fit (beta and D, eqs. 6, 8), each frame's candidate columns rotated into
//! the fit's basis. Column `offsets[c]..offsets[c] + width` belongs to
//! candidate `c` of [`super::candidates::ALL`].

use crate::fit::context::FitContext;
use crate::fit::force::{force_row, ForceRow};
use crate::fit::joint::{Joint, JointFrame};
use crate::fit::model::FitSmoothing;
use crate::fit::weights::{force_frames, force_weights};
use crate::reconstruct::filter::Smoothed;
use crate::reconstruct::forces::Sample;
use crate::residual::candidates::{columns, Candidate, ColumnContext, ALL};
use nalgebra::{DMatrix, Matrix3, UnitQuaternion};
use omniad_core::sh::coeff_count;

/// Both problems and where each candidate's columns are.
pub(crate) struct Problems {
    /// The force fit.
    pub force: Joint,
    /// The torque fit.
    pub torque: Joint,
    /// First column of each candidate of [`ALL`].
    pub offsets: Vec<usize>,
    /// The force frames' body-frame samples, in `force.frames` order.
    pub force_samples: Vec<Sample>,
    /// The force frames' bases (the fit's `B`, eq. 7: basis vectors as
    /// columns, body frame), in `force.frames` order.
    pub force_bases: Vec<Matrix3<f64>>,
    /// The object's mass, kg ([`super::output_error`]).
    pub mass: f64,
    /// Added mass already in the targets (a given model's, held by
    /// [`super::fixed::hold`]), kg, body frame; zero otherwise.
    pub held_added_mass: Matrix3<f64>,
}

impl Problems {
    /// Columns of `c` in the joint problems.
    pub fn columns_of(&self, c: Candidate) -> std::ops::Range<usize> {
        let i = ALL.iter().position(|a| *a == c).unwrap_or(0);
        let start = self.offsets.get(i).copied().unwrap_or(0);
        start..start + c.width()
    }
}

/// First column of each candidate of [`ALL`] in the problems' extra
/// columns ([`Problems::offsets`]).
pub(crate) fn offsets() -> Vec<usize> {
    ALL.iter()
        .scan(0, |at, c| {
            let first = *at;
            *at += c.width();
            Some(first)
        })
        .collect()
}

/// The attitude of sample `s` in the reconstruction.
fn attitude(s: &Sample, rec: &[Smoothed]) -> UnitQuaternion<f64> {
    rec.get(s.take)
        .and_then(|r| r.states.get(s.index))
        .map_or_else(UnitQuaternion::identity, |st| st.orientation)
}

/// Every candidate's columns at a frame, side by side (force, torque).
fn all_columns(
    s: &Sample,
    rec: &[Smoothed],
    ctx: &ColumnContext<'_>,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let width: usize = ALL.iter().map(|c| c.width()).sum();
    let (mut f, mut t) = (DMatrix::zeros(3, width), DMatrix::zeros(3, width));
    let q = attitude(s, rec);
    let mut at = 0;
    for c in ALL {
        let (cf, ct) = columns(c, s, &q, ctx);
        f.view_mut((0, at), (3, c.width())).copy_from(&cf);
        t.view_mut((0, at), (3, c.width())).copy_from(&ct);
        at += c.width();
    }
    (f, t)
}

/// Builds the problems from the base fit's frames, reconstruction and
/// smoothing, the force at SH degree `degrees.0` and the torque at its own
/// `degrees.1` (a model's N and N_T), for an object of mass `mass` (kg).
pub(crate) fn build(
    mass: f64,
    samples: &[Sample],
    rec: &[Smoothed],
    fit: &FitContext,
    cols: &ColumnContext<'_>,
    degrees: (usize, usize),
    smoothing: FitSmoothing,
) -> Problems {
    let (degree, torque_degree) = degrees;
    let n = coeff_count(degree);
    let frames = force_frames(samples);
    let weights = force_weights(&frames);
    let mut force_frames_out = Vec::with_capacity(frames.len());
    let mut force_samples = Vec::with_capacity(frames.len());
    let mut force_bases = Vec::with_capacity(frames.len());
    for (s, w) in frames.iter().zip(&weights) {
        let (cf, _) = all_columns(s, rec, cols);
        if cf.iter().any(|v| !v.is_finite()) {
            continue;
        }
        let ForceRow {
            a,
            basis,
            weight,
            target,
        } = force_row(s, w, fit, degree);
        let mut base = DMatrix::zeros(3, 3 * n);
        for i in 0..3 {
            base.view_mut((i, i * n), (1, n)).copy_from(&a.transpose());
        }
        force_frames_out.push(JointFrame {
            take: s.take,
            base,
            extra: DMatrix::from_fn(3, cf.ncols(), |i, j| basis.column(i).dot(&cf.column(j))),
            weight,
            target,
        });
        force_samples.push(**s);
        force_bases.push(basis);
    }
    let mut torque_frames = Vec::new();
    for s in samples.iter().filter(|s| s.use_torque) {
        let (_, ct) = all_columns(s, rec, cols);
        let (base, target, axes) = crate::fit::torque::dense_rows(s, fit, torque_degree);
        if ct.iter().chain(base.iter()).any(|v| !v.is_finite()) {
            continue;
        }
        torque_frames.push(JointFrame {
            take: s.take,
            base,
            extra: DMatrix::from_fn(3, ct.ncols(), |i, j| {
                axes.row(i).transpose().dot(&ct.column(j))
            }),
            weight: Matrix3::identity(),
            target,
        });
    }
    Problems {
        force: Joint::new(force_frames_out, degree, smoothing.force),
        torque: Joint::new(torque_frames, torque_degree, smoothing.torque),
        offsets: offsets(),
        force_samples,
        force_bases,
        mass,
        held_added_mass: Matrix3::zeros(),
    }
}
