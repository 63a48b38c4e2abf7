//! Choosing the force fit's smoothing weight by leave-one-take-out
//! cross-validation.
//!
//! The Tikhonov weight of [`crate::fit_lsq`] trades the reconstructed
//! forces' noise against the SH truncation: from exact states less
//! smoothing is better, from noisy reconstructions (early refinement
//! iterations, §6; noisy tracks) more. A take's force errors are strongly
//! correlated in time (the smoother's error along the line of sight wanders
//! slowly), so frames are not independent and per-frame criteria such as
//! GCV would follow that noise; holding out whole takes does not. Each
//! candidate weight is fitted without one take and scored on that take's
//! frames, all from per-take normal equations (no frame is visited twice).

use nalgebra::{DMatrix, DVector};

/// Candidate smoothing weights (half-decades around the default 1e-3).
pub const SMOOTHING_GRID: [f64; 7] = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1];

/// Fewest takes for cross-validation (else the configured weight is used).
pub const MIN_TAKES: usize = 3;

/// One take's normal equations for the three force components sharing the
/// design matrix `A`: `AᵀA`, `Aᵀb_i` and `Σ b_iᵀb_i`.
#[derive(Clone, Debug)]
pub struct Normals {
    /// `AᵀA`.
    pub ata: DMatrix<f64>,
    /// `Aᵀb_i`, i = 1..3.
    pub atb: [DVector<f64>; 3],
    /// `Σ_i b_iᵀ b_i`.
    pub btb: f64,
}

impl Normals {
    /// Empty normal equations of `n` unknowns.
    pub fn zeros(n: usize) -> Self {
        Self {
            ata: DMatrix::zeros(n, n),
            atb: std::array::from_fn(|_| DVector::zeros(n)),
            btb: 0.0,
        }
    }

    /// Adds `other`.
    pub fn add(&mut self, other: &Self) {
        self.ata += &other.ata;
        for (a, b) in self.atb.iter_mut().zip(&other.atb) {
            *a += b;
        }
        self.btb += other.btb;
    }
}

/// The weight of [`SMOOTHING_GRID`] whose fits without each take predict
/// that take's forces best (summed squared error), or `fallback` with fewer
/// than [`MIN_TAKES`] takes. `regularise(ata, λ)` adds the smoothing term
/// (scaled from the whole data, so that every fold is smoothed alike).
pub fn choose(
    takes: &[Normals],
    total: &Normals,
    fallback: f64,
    regularise: impl Fn(&mut DMatrix<f64>, f64),
) -> f64 {
    if takes.len() < MIN_TAKES {
        return fallback;
    }
    let mut best = (f64::INFINITY, fallback);
    for &lambda in &SMOOTHING_GRID {
        let mut score = 0.0;
        for t in takes {
            let mut ata = &total.ata - &t.ata;
            regularise(&mut ata, lambda);
            let Some(chol) = ata.cholesky() else {
                score = f64::INFINITY;
                break;
            };
            // Held-out error: Σ_i |b_i - A c_i|² = b_iᵀb_i - 2 c_iᵀAᵀb_i + c_iᵀAᵀA c_i.
            score += t.btb;
            for (rest, held) in total.atb.iter().zip(&t.atb) {
                let c = chol.solve(&(rest - held));
                score += c.dot(&(&t.ata * &c)) - 2.0 * c.dot(held);
            }
        }
        if score < best.0 {
            best = (score, lambda);
        }
    }
    best.1
}
