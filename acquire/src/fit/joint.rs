//! The base fit extended by extra columns: one frame's rows `[A_base |
//! A_extra]` (three rows in the basis of the base fit, weight `W`, target
//! `b`), per-take normal equations of all columns at once
//! ([`crate::fit::normals::per_take`]), and leave-one-take-out scores of a
//! *design* (the base unknowns plus a subset of the extra columns) by
//! [`crate::fit::select::held_out_scores`]. The residual analysis
//! (`crate::residual`) fits each candidate effect jointly with the force
//! coefficients this way, so that alpha cannot absorb the effect's share
//! (and scores the torque fit with the effect's parameters held at the
//! force fit's values).

use crate::fit::normals::{per_take, solve, total, Normals, Rows};
use crate::fit::smoothing::{regularise, Smoothing};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// One frame of a joint problem.
#[derive(Clone, Debug)]
pub(crate) struct JointFrame {
    /// Take index in the set.
    pub take: usize,
    /// Rows of the base unknowns (3 x base), in the fit's basis.
    pub base: DMatrix<f64>,
    /// Rows of every extra column (3 x extra), same basis.
    pub extra: DMatrix<f64>,
    /// The rows' weight (3 x 3).
    pub weight: Matrix3<f64>,
    /// The target (3), same basis.
    pub target: Vector3<f64>,
}

struct JointRows {
    dim: usize,
}

impl Rows for JointRows {
    type Frame = JointFrame;
    type Normals = Normals;

    fn dim(&self) -> usize {
        self.dim
    }

    fn add(&self, f: &JointFrame, n: &mut Normals) {
        let mut r = DMatrix::zeros(3, self.dim);
        let nb = f.base.ncols();
        r.view_mut((0, 0), (3, nb)).copy_from(&f.base);
        r.view_mut((0, nb), (3, f.extra.ncols()))
            .copy_from(&f.extra);
        let w = DMatrix::from_fn(3, 3, |i, j| f.weight[(i, j)]);
        let wr = &w * &r;
        n.ata.gemm_tr(1.0, &r, &wr, 1.0);
        let wt = f.weight * f.target;
        let wt = DVector::from_column_slice(wt.as_slice());
        n.atb.gemv_tr(1.0, &r, &wt, 1.0);
        n.btb += f.target.dot(&(f.weight * f.target));
    }
}

/// A joint problem: its frames (grouped by take, takes in order of first
/// appearance) and per-take normal equations over all columns.
pub(crate) struct Joint {
    /// The frames.
    pub frames: Vec<JointFrame>,
    /// Per-take normal equations (base unknowns first).
    pub takes: Vec<Normals>,
    /// Take index of each entry of `takes`.
    pub take_ids: Vec<usize>,
    /// Base unknowns.
    pub base: usize,
    /// SH blocks of the base that are smoothed (3 x `degree`'s count).
    pub degree: usize,
    /// The base fit's smoothing.
    pub smoothing: Smoothing,
}

/// A solution of a design on some takes.
#[derive(Clone, Debug)]
pub(crate) struct Solution {
    /// Base unknowns then the design's extra columns, in design order.
    pub x: DVector<f64>,
}

impl Joint {
    /// Builds the per-take normals of `frames`.
    pub fn new(frames: Vec<JointFrame>, degree: usize, smoothing: Smoothing) -> Self {
        let base = frames.first().map_or(0, |f| f.base.ncols());
        let extra = frames.first().map_or(0, |f| f.extra.ncols());
        let rows = JointRows { dim: base + extra };
        let mut take_ids: Vec<usize> = Vec::new();
        for f in &frames {
            if !take_ids.contains(&f.take) {
                take_ids.push(f.take);
            }
        }
        let takes = per_take(frames.iter().map(|f| (f.take, f.clone())), &rows);
        Self {
            frames,
            takes,
            take_ids,
            base,
            degree,
            smoothing,
        }
    }

    /// The problem with the base unknowns held at `x` and the extra
    /// columns `held` (index, value) at their values: every target becomes
    /// its residual `b - A_base x - Σ A_extra,c v_c` and no base unknown
    /// is left (`base == 0`), so a design fits only its extra columns on
    /// top of a given model (`omniad residual --coeffs`).
    pub fn with_fixed_base(self, x: &DVector<f64>, held: &[(usize, f64)]) -> Self {
        let (degree, smoothing) = (self.degree, self.smoothing);
        let frames = self
            .frames
            .into_iter()
            .map(|mut f| {
                let p = &f.base * x;
                f.target -= Vector3::new(p[0], p[1], p[2]);
                for &(c, v) in held {
                    f.target -= Vector3::from_iterator(f.extra.column(c).iter().map(|e| e * v));
                }
                f.base = DMatrix::zeros(3, 0);
                f
            })
            .collect();
        Self::new(frames, degree, smoothing)
    }

    /// Indices of the unknowns of a design with extra columns `extra`.
    fn index(&self, extra: &[usize]) -> Vec<usize> {
        (0..self.base)
            .chain(extra.iter().map(|e| self.base + e))
            .collect()
    }

    /// Normal equations of the design, summed over takes except `skip`.
    fn restricted(&self, idx: &[usize], skip: Option<usize>) -> Normals {
        let parts: Vec<&Normals> = self
            .takes
            .iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != skip)
            .map(|(_, n)| n)
            .collect();
        let mut sum: Normals = total(&[], idx.len());
        for n in parts {
            sum.ata += n.ata.select_rows(idx).select_columns(idx);
            sum.atb += n.atb.select_rows(idx);
            sum.btb += n.btb;
        }
        sum
    }

    /// The design's solution without take `skip` (all takes: `None`);
    /// extra columns in `fixed` are held at the given values (the rest of
    /// `extra` is fitted).
    pub fn solve(&self, extra: &[usize], fixed: Option<&[f64]>, skip: Option<usize>) -> Solution {
        let idx = self.index(extra);
        let n = self.restricted(&idx, skip);
        let mut ata = n.ata;
        // A fixed base (`with_fixed_base`) has no SH blocks to smooth.
        if self.base > 0 {
            regularise(&mut ata, 3, self.degree, self.smoothing);
        }
        if let Some(u) = fixed {
            let b = self.base;
            if b == 0 {
                return Solution {
                    x: DVector::from_column_slice(u),
                };
            }
            let sub = ata.view((0, 0), (b, b)).into_owned();
            let cross = ata.view((0, b), (b, u.len())).into_owned();
            let u = DVector::from_column_slice(u);
            let rhs = n.atb.rows(0, b).into_owned() - cross * &u;
            let xb = solve(&sub, &rhs);
            let mut x = DVector::zeros(b + u.len());
            x.rows_mut(0, b).copy_from(&xb);
            x.rows_mut(b, u.len()).copy_from(&u);
            return Solution { x };
        }
        ridge_extra_columns(&mut ata, self.base..idx.len());
        Solution {
            x: solve(&ata, &n.atb),
        }
    }

    /// Weighted squared error of `x` (a design's solution) on take `t`.
    pub fn error(&self, extra: &[usize], x: &DVector<f64>, t: usize) -> f64 {
        let idx = self.index(extra);
        let Some(h) = self.takes.get(t) else {
            return f64::NAN;
        };
        let ata = h.ata.select_rows(&idx).select_columns(&idx);
        let atb = h.atb.select_rows(&idx);
        h.btb - 2.0 * x.dot(&atb) + x.dot(&(&ata * x))
    }

    /// Residuals (target minus rows times `x`, in the fit's basis) of the
    /// frames of take `t` (index into `takes`).
    pub fn frame_residuals(
        &self,
        extra: &[usize],
        x: &DVector<f64>,
        t: usize,
    ) -> Vec<(usize, Vector3<f64>)> {
        let Some(&id) = self.take_ids.get(t) else {
            return Vec::new();
        };
        let xb = x.rows(0, self.base);
        self.frames
            .iter()
            .enumerate()
            .filter(|(_, f)| f.take == id)
            .map(|(k, f)| {
                let mut p = &f.base * xb;
                for (j, e) in extra.iter().enumerate() {
                    p += f.extra.column(*e) * x[self.base + j];
                }
                (k, f.target - Vector3::new(p[0], p[1], p[2]))
            })
            .collect()
    }
}

/// The ridge that only keeps the extra (effect) columns regular: 1e-6
/// of each column's own diagonal entry, on the rows and columns `cols`
/// of `ata`. The joint solve and the residual's identifiability measures
/// (`residual::identify`) share it, so they judge the same problem.
pub(crate) fn ridge_extra_columns(ata: &mut DMatrix<f64>, cols: std::ops::Range<usize>) {
    for i in cols {
        if let Some(d) = ata.get_mut((i, i)) {
            *d *= 1.0 + 1e-6;
        }
    }
}

/// Leave-one-take-out of a design on `joint`: per held-out take its
/// weighted squared error, and each fold's solution. `fixed(t)` gives the
/// extra columns' values to hold in fold `t` (the torque problem holds an
/// effect at its force-fit value). `None` with fewer than
/// [`crate::fit::select::MIN_TAKES`] takes.
pub(crate) fn held_out(
    joint: &Joint,
    extra: &[usize],
    fixed: &(dyn Fn(usize) -> Option<Vec<f64>> + Sync),
) -> Option<Vec<(f64, Solution)>> {
    crate::fit::select::per_fold(joint.takes.len(), |t| {
        let u = fixed(t);
        let s = joint.solve(extra, u.as_deref(), Some(t));
        (joint.error(extra, &s.x, t), s)
    })
}
