//! Least squares over cycles: per-cycle normal equations of the design
//! (the terms' columns), a penalised solve, leave-one-cycle-out scores and
//! jackknife uncertainties.
//!
//! Why per cycle: samples at 10 Hz within a cycle are strongly correlated,
//! so held-out scores and uncertainties must leave out whole cycles (a
//! cycle is never split), and per-cycle sums make each held-out fit one
//! subtraction and one solve.

use crate::sample::Sample;
use crate::terms::{columns, roughness, Setup, Term};
use nalgebra::{DMatrix, DVector, Vector3};

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

/// Normal equations of some samples: `XᵀX`, `Xᵀy`, `yᵀy`, count.
#[derive(Clone, Debug, PartialEq)]
pub struct Normals {
    xtx: DMatrix<f64>,
    xty: DVector<f64>,
    yty: f64,
    /// Samples summed.
    pub samples: usize,
}

impl Normals {
    fn zeros(w: usize) -> Self {
        Self {
            xtx: DMatrix::zeros(w, w),
            xty: DVector::zeros(w),
            yty: 0.0,
            samples: 0,
        }
    }

    /// The normal equations of `samples` under `design`.
    pub fn of(design: &Design, samples: &[Sample]) -> Self {
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
        Self {
            xtx: x.tr_mul(&x),
            xty: x.tr_mul(&y),
            yty: y.dot(&y),
            samples: n,
        }
    }

    fn add(&mut self, o: &Self, sign: f64) {
        self.xtx += &o.xtx * sign;
        self.xty += &o.xty * sign;
        self.yty += o.yty * sign;
        self.samples = if sign > 0.0 {
            self.samples + o.samples
        } else {
            self.samples.saturating_sub(o.samples)
        };
    }

    /// Sum of squared force errors of these samples under `theta`, N².
    pub fn sse(&self, theta: &DVector<f64>) -> f64 {
        (self.yty - 2.0 * theta.dot(&self.xty) + theta.dot(&(&self.xtx * theta))).max(0.0)
    }
}

/// A design with its per-cycle normal equations (training cycles only).
#[derive(Clone, Debug)]
pub struct Problem {
    /// The design.
    pub design: Design,
    /// `(cycle, normals)` in cycle order.
    pub cycles: Vec<(u32, Normals)>,
    total: Normals,
}

/// Smoothness weights tried, relative to the mean diagonal of `XᵀX`.
pub const SMOOTHING_GRID: [f64; 6] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2];

impl Problem {
    /// Builds the per-cycle normal equations of `cycles` (each a slice of
    /// one cycle's samples).
    pub fn new(design: Design, cycles: &[(u32, Vec<Sample>)]) -> Self {
        let per: Vec<(u32, Normals)> = cycles
            .iter()
            .map(|(n, s)| (*n, Normals::of(&design, s)))
            .collect();
        let mut total = Normals::zeros(design.width());
        for (_, n) in &per {
            total.add(n, 1.0);
        }
        Self {
            design,
            cycles: per,
            total,
        }
    }

    /// The penalised solve of `normals` with smoothing weight `lambda`.
    fn solve(&self, normals: &Normals, lambda: f64) -> Option<DVector<f64>> {
        let w = self.design.width();
        let scale = (normals.xtx.trace() / w.max(1) as f64).max(f64::MIN_POSITIVE);
        let mut a = normals.xtx.clone();
        for (j, (r, sh)) in self.design.penalty_shape().into_iter().enumerate() {
            let p = if sh { lambda * r + 1e-9 } else { 1e-9 };
            a[(j, j)] += p * scale;
        }
        a.cholesky().map(|c| c.solve(&normals.xty))
    }

    /// The fit on all training cycles.
    pub fn fit(&self, lambda: f64) -> Option<DVector<f64>> {
        self.solve(&self.total, lambda)
    }

    /// Leave-one-cycle-out: the fits without each cycle.
    fn held_out_fits(&self, lambda: f64) -> Vec<Option<DVector<f64>>> {
        self.cycles
            .iter()
            .map(|(_, n)| {
                let mut rest = self.total.clone();
                rest.add(n, -1.0);
                self.solve(&rest, lambda)
            })
            .collect()
    }

    /// Leave-one-cycle-out mean squared force error per sample, N².
    pub fn held_out_mse(&self, lambda: f64) -> f64 {
        let fits = self.held_out_fits(lambda);
        let (mut sse, mut n) = (0.0, 0usize);
        for ((_, normals), fit) in self.cycles.iter().zip(&fits) {
            match fit {
                Some(theta) => {
                    sse += normals.sse(theta);
                    n += normals.samples;
                }
                None => return f64::INFINITY,
            }
        }
        if n == 0 {
            f64::INFINITY
        } else {
            sse / n as f64
        }
    }

    /// The smoothing weight of [`SMOOTHING_GRID`] with the lowest held-out
    /// error, and that error.
    pub fn choose_smoothing(&self) -> (f64, f64) {
        SMOOTHING_GRID
            .iter()
            .map(|&l| (l, self.held_out_mse(l)))
            .fold((SMOOTHING_GRID[0], f64::INFINITY), |best, c| {
                if c.1 < best.1 {
                    c
                } else {
                    best
                }
            })
    }

    /// Jackknife standard errors over cycles of the parameters.
    pub fn jackknife(&self, lambda: f64) -> Option<DVector<f64>> {
        let fits: Option<Vec<DVector<f64>>> = self.held_out_fits(lambda).into_iter().collect();
        let fits = fits?;
        let g = fits.len() as f64;
        if g < 2.0 {
            return None;
        }
        let mean = fits
            .iter()
            .fold(DVector::zeros(self.design.width()), |a, f| a + f)
            / g;
        let var = fits
            .iter()
            .fold(DVector::zeros(self.design.width()), |a, f| {
                a + (f - &mean).component_mul(&(f - &mean))
            })
            * ((g - 1.0) / g);
        Some(var.map(f64::sqrt))
    }
}
