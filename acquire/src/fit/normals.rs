//! Weighted normal equations `AᵀWA c = AᵀWb`, one set per take, and their
//! solution. The force, torque and extension fits supply rows; the
//! per-take builder [`per_take`] groups them by take (cross-validation
//! holds whole takes out, [`crate::fit::select`]).

use nalgebra::{DMatrix, DVector};

/// Normal equations that add up over takes.
pub trait Accumulate {
    /// Empty equations of `dim` unknowns.
    fn zeros(dim: usize) -> Self;
    /// Adds `other`.
    fn add(&mut self, other: &Self);
}

/// A fit's rows: how many unknowns it has, and how one frame's weighted
/// rows add to a take's normal equations. The force fit, the torque fit
/// and the extension terms each implement it; [`per_take`] does the rest.
pub(crate) trait Rows {
    /// One frame as this fit sees it.
    type Frame;
    /// The normal equations it builds.
    type Normals: Accumulate;
    /// Unknowns.
    fn dim(&self) -> usize;
    /// Adds `frame`'s rows to `normals`.
    fn add(&self, frame: &Self::Frame, normals: &mut Self::Normals);
}

/// One take's normal equations per take of `frames` (take index, frame),
/// in order of first appearance.
pub(crate) fn per_take<R: Rows>(
    frames: impl IntoIterator<Item = (usize, R::Frame)>,
    rows: &R,
) -> Vec<R::Normals> {
    let mut takes: Vec<(usize, R::Normals)> = Vec::new();
    for (take, frame) in frames {
        let at = match takes.iter().position(|(t, _)| *t == take) {
            Some(i) => i,
            None => {
                takes.push((take, R::Normals::zeros(rows.dim())));
                takes.len() - 1
            }
        };
        if let Some((_, n)) = takes.get_mut(at) {
            rows.add(&frame, n);
        }
    }
    takes.into_iter().map(|(_, n)| n).collect()
}

/// The sum of per-take normal equations of `dim` unknowns.
pub fn total<N: Accumulate>(takes: &[N], dim: usize) -> N {
    let mut total = N::zeros(dim);
    for t in takes {
        total.add(t);
    }
    total
}

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

impl Accumulate for Normals {
    fn zeros(n: usize) -> Self {
        Self {
            ata: DMatrix::zeros(n, n),
            atb: DVector::zeros(n),
            btb: 0.0,
        }
    }

    fn add(&mut self, other: &Self) {
        self.ata += &other.ata;
        self.atb += &other.atb;
        self.btb += other.btb;
    }
}

/// The solution of `ata c = atb` (Cholesky, else LU, else zeros).
pub fn solve(ata: &DMatrix<f64>, atb: &DVector<f64>) -> DVector<f64> {
    match ata.clone().cholesky() {
        Some(c) => c.solve(atb),
        None => ata
            .clone()
            .lu()
            .solve(atb)
            .unwrap_or_else(|| DVector::zeros(atb.len())),
    }
}
