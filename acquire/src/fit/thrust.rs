//! No thrust (§5): `C_F(E)·E < 0` enforced on a dense direction grid by
//! penalty rows.

use crate::fit::config::LsqConfig;
use crate::fit::context::sh_and_basis;
use crate::fit::coverage::sphere_grid;
use crate::fit::normals::solve;
use nalgebra::{DMatrix, DVector};

/// Solves for alpha (the first `coeff_count` unknowns are alpha^1) and adds
/// penalty rows `Σ α¹_k Y_k(E) = -margin` at directions of a dense grid
/// where `C_F(E)·E > -margin`, until none is left.
pub(crate) fn enforce_no_thrust(
    mut ata: DMatrix<f64>,
    mut atb: DVector<f64>,
    cfg: &LsqConfig,
) -> Vec<f64> {
    let grid = sphere_grid(64, 32);
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
