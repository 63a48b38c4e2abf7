//! Weighted normal equations `AᵀWA c = AᵀWb`, one set per take, and their
//! solution. The force, torque and extension fits supply rows; the
//! per-take builder [`per_take`] groups them by take (cross-validation
//! holds whole takes out, [`crate::fit::select`]).

use nalgebra::{DMatrix, DVector};

/// One take's weighted normal equations: `AᵀWA`, `AᵀWb` and `bᵀWb`.
#[derive(Clone, Debug)]
pub struct Normals {
    /// `AᵀWA`.
    pub ata: DMatrix<f64>,
    /// `AᵀWb`.
    pub atb: DVector<f64>,
    /// `bᵀWb`.
    pub btb: f64,
}

impl Normals {
    /// Empty normal equations of `n` unknowns.
    pub fn zeros(n: usize) -> Self {
        Self {
            ata: DMatrix::zeros(n, n),
            atb: DVector::zeros(n),
            btb: 0.0,
        }
    }

    /// Adds `other`.
    pub fn add(&mut self, other: &Self) {
        self.ata += &other.ata;
        self.atb += &other.atb;
        self.btb += other.btb;
    }
}

pub(crate) fn solve(ata: &DMatrix<f64>, atb: &DVector<f64>) -> DVector<f64> {
    match ata.clone().cholesky() {
        Some(c) => c.solve(atb),
        None => ata
            .clone()
            .lu()
            .solve(atb)
            .unwrap_or_else(|| DVector::zeros(atb.len())),
    }
}
