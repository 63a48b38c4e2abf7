//! Least squares over cycles: per-cycle normal equations of the design
//! (the terms' columns), a penalised solve, leave-one-cycle-out scores and
//! jackknife uncertainties — on the acquisition's engine
//! (`omniad_acquire::fit::{normals, select}`): a pumping cycle is held out
//! as a take is.
//!
//! Why per cycle: samples at 10 Hz within a cycle are strongly correlated,
//! so held-out scores and uncertainties must leave out whole cycles (a
//! cycle is never split), and per-cycle sums make each held-out fit one
//! subtraction and one solve.

use crate::sample::Sample;
use crate::terms::{columns, roughness, Setup, Term};
use nalgebra::{DMatrix, DVector, Vector3};
use omniad_acquire::fit::normals::{solve, total, Normals};
use omniad_acquire::fit::select::per_fold;

/// A model design: the setup and its terms, base first.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// Degree, pole, reference length.
    pub setup: Setup,
    /// Terms, in column order.
    pub terms: Vec<Term>,
}

impl Design {
    /// Total number of columns.
    pub fn width(&self) -> usize {
        self.terms.iter().map(|t| t.width(self.setup.degree)).sum()
    }

    /// All columns of a sample, in order.
    pub fn row_block(&self, s: &Sample) -> Vec<Vector3<f64>> {
        let mut out = Vec::with_capacity(self.width());
        for t in &self.terms {
            columns(t, &self.setup, s, &mut out);
        }
        out
    }

    /// The model's force at a sample for parameters `theta`, FRD, N.
    pub fn predict(&self, theta: &DVector<f64>, s: &Sample) -> Vector3<f64> {
        self.row_block(s)
            .iter()
            .zip(theta.iter())
            .fold(Vector3::zeros(), |acc, (c, p)| acc + c * *p)
    }

    /// Diagonal penalty shape: roughness `l(l+1)` on SH columns (plus a
    /// tiny ridge so that the solve is always regular), a tiny ridge on
    /// scalar effects.
    fn penalty_shape(&self) -> Vec<(f64, bool)> {
        let mut out = Vec::with_capacity(self.width());
        for t in &self.terms {
            if t.is_sh() {
                out.extend(roughness(self.setup.degree).into_iter().map(|r| (r, true)));
            } else {
                out.push((0.0, false));
            }
        }
        out
    }

    /// Column range of term `i`.
    pub fn columns_of(&self, i: usize) -> std::ops::Range<usize> {
        let start: usize = self
            .terms
            .iter()
            .take(i)
            .map(|t| t.width(self.setup.degree))
            .sum();
        let w = self.terms.get(i).map_or(0, |t| t.width(self.setup.degree));
        start..start + w
    }
}

/// The normal equations of `samples` under `design` (`AᵀA`, `Aᵀb`, `bᵀb`
/// of the force rows, unweighted) — the acquisition's per-take type, so
/// that one engine holds cycles out as it holds takes out.
fn normals_of(design: &Design, samples: &[Sample]) -> Normals {
    let w = design.width();
    let n = samples.len();
    let mut x = DMatrix::zeros(3 * n, w);
    let mut y = DVector::zeros(3 * n);
    for (i, s) in samples.iter().enumerate() {
        for (j, col) in design.row_block(s).iter().enumerate() {
            for c in 0..3 {
                x[(3 * i + c, j)] = col[c];
            }
        }
        for c in 0..3 {
            y[3 * i + c] = s.aero_force[c];
        }
    }
    Normals {
        ata: x.tr_mul(&x),
        atb: x.tr_mul(&y),
        btb: y.dot(&y),
    }
}

/// Sum of squared force errors of the rows of `n` under `theta`, N².
fn sse(n: &Normals, theta: &DVector<f64>) -> f64 {
    (n.btb - 2.0 * theta.dot(&n.atb) + theta.dot(&(&n.ata * theta))).max(0.0)
}

/// One training cycle: its number, normal equations and sample count.
#[derive(Clone, Debug)]
struct CycleNormals {
    normals: Normals,
    samples: usize,
}

/// A design with its per-cycle normal equations (training cycles only).
#[derive(Clone, Debug)]
pub struct Problem {
    /// The design.
    pub design: Design,
    cycles: Vec<CycleNormals>,
    total: Normals,
    /// The penalty's scale: the mean diagonal of the whole `AᵀA`, so that
    /// every fold is smoothed alike (as the acquisition's fits do).
    scale: f64,
}

/// Smoothness weights tried, relative to the mean diagonal of `AᵀA`.
pub const SMOOTHING_GRID: [f64; 6] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2];

impl Problem {
    /// Builds the per-cycle normal equations of `cycles` (each a slice of
    /// one cycle's samples).
    pub fn new(design: Design, cycles: &[(u32, Vec<Sample>)]) -> Self {
        let per: Vec<CycleNormals> = cycles
            .iter()
            .map(|(_, s)| CycleNormals {
                normals: normals_of(&design, s),
                samples: s.len(),
            })
            .collect();
        let all: Vec<Normals> = per.iter().map(|c| c.normals.clone()).collect();
        let total = total(&all, design.width());
        let scale = (total.ata.trace() / design.width().max(1) as f64).max(f64::MIN_POSITIVE);
        Self {
            design,
            cycles: per,
            total,
            scale,
        }
    }

    /// The penalised solve of `ata c = atb` with smoothing weight `lambda`;
    /// `None` when the result is not finite.
    fn solve(&self, ata: &DMatrix<f64>, atb: &DVector<f64>, lambda: f64) -> Option<DVector<f64>> {
        let mut a = ata.clone();
        for (j, (r, sh)) in self.design.penalty_shape().into_iter().enumerate() {
            let p = if sh { lambda * r + 1e-9 } else { 1e-9 };
            a[(j, j)] += p * self.scale;
        }
        let x = solve(&a, atb);
        x.iter().all(|v| v.is_finite()).then_some(x)
    }

    /// The fit on all training cycles.
    pub fn fit(&self, lambda: f64) -> Option<DVector<f64>> {
        self.solve(&self.total.ata, &self.total.atb, lambda)
    }

    /// The fit without cycle `c`.
    fn fit_without(&self, c: usize, lambda: f64) -> Option<DVector<f64>> {
        let held = &self.cycles.get(c)?.normals;
        self.solve(
            &(&self.total.ata - &held.ata),
            &(&self.total.atb - &held.atb),
            lambda,
        )
    }

    /// Leave-one-cycle-out: each training cycle's squared force error (N²)
    /// and sample count under the fit without it — the acquisition's fold
    /// engine ([`per_fold`]), so `None` with fewer than its minimum of
    /// training cycles or when a fold cannot be solved.
    pub fn held_out(&self, lambda: f64) -> Option<Vec<(f64, usize)>> {
        per_fold(self.cycles.len(), |c| {
            let theta = self.fit_without(c, lambda)?;
            let cycle = self.cycles.get(c)?;
            Some((sse(&cycle.normals, &theta), cycle.samples))
        })?
        .into_iter()
        .collect()
    }

    /// Leave-one-cycle-out mean squared force error per sample, N²
    /// (infinite when it cannot be computed).
    pub fn held_out_mse(&self, lambda: f64) -> f64 {
        let Some(folds) = self.held_out(lambda) else {
            return f64::INFINITY;
        };
        let (e, n) = folds
            .iter()
            .fold((0.0, 0), |(e, n), (fe, fn_)| (e + fe, n + fn_));
        if n == 0 {
            f64::INFINITY
        } else {
            e / n as f64
        }
    }

    /// The smoothing weight of [`SMOOTHING_GRID`] with the lowest held-out
    /// error, and that error; the middle of the grid, with an infinite
    /// error, when there are too few training cycles to hold one out.
    pub fn choose_smoothing(&self) -> (f64, f64) {
        SMOOTHING_GRID
            .iter()
            .map(|&l| (l, self.held_out_mse(l)))
            .fold((SMOOTHING_GRID[3], f64::INFINITY), |best, c| {
                if c.1 < best.1 {
                    c
                } else {
                    best
                }
            })
    }

    /// Jackknife standard errors over cycles of the parameters.
    pub fn jackknife(&self, lambda: f64) -> Option<DVector<f64>> {
        let fits: Vec<DVector<f64>> = per_fold(self.cycles.len(), |c| self.fit_without(c, lambda))?
            .into_iter()
            .collect::<Option<_>>()?;
        let g = fits.len() as f64;
        let w = self.design.width();
        let mean = fits.iter().fold(DVector::zeros(w), |a, f| a + f) / g;
        let var = fits.iter().fold(DVector::zeros(w), |a, f| {
            a + (f - &mean).component_mul(&(f - &mean))
        }) * ((g - 1.0) / g);
        Some(var.map(f64::sqrt))
    }
}
