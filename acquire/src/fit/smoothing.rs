//! The smoothness penalty of the SH coefficients (Tikhonov on a
//! Sobolev-type norm, §6 improved) and its leave-one-take-out choice of
//! weight and order (`crate::fit::select`).

use crate::fit::normals::Normals;
use nalgebra::DMatrix;
use omniad_core::sh::coeff_count;

/// Candidate smoothing weights (half-decades around the default 1e-3).
pub const SMOOTHING_GRID: [f64; 7] = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1];

/// Penalty of each SH coefficient up to `degree` for smoothness order
/// `order` (see [`LsqConfig::smoothness_order`]).
fn roughness(degree: usize, order: u32) -> Vec<f64> {
    let top = (degree * (degree + 1)).max(1) as f64;
    let power = i32::try_from(order.max(1) - 1).unwrap_or(0);
    (0..=degree)
        .flat_map(|l| {
            let ll = (l * (l + 1)) as f64;
            std::iter::repeat_n(ll * (ll / top).powi(power), 2 * l + 1)
        })
        .collect()
}

/// Orders of the smoothness penalty that cross-validation chooses among
/// (see `LsqConfig::smoothness_order`).
pub const SMOOTHNESS_ORDERS: [u32; 4] = [1, 2, 3, 4];

/// The order used without cross-validation.
pub const DEFAULT_SMOOTHNESS_ORDER: u32 = 2;

/// The smoothness penalty: the smoothing weight `λ`, and the order `p` of
/// `LsqConfig::smoothness_order`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoothing {
    /// `λ`, relative to the mean data weight per coefficient.
    pub weight: f64,
    /// `p`.
    pub order: u32,
}

/// Adds `λ · scale · penalty(l)` (plus a tiny ridge) to the diagonal
/// blocks of `ata`, `scale` the mean data weight per coefficient and
/// `penalty` that of [`roughness`].
pub(crate) fn regularise(
    ata: &mut DMatrix<f64>,
    blocks: usize,
    degree: usize,
    smoothing: Smoothing,
) {
    let scale = data_scale(ata, blocks * coeff_count(degree));
    regularise_scaled(ata, blocks, degree, smoothing, scale);
}

/// The mean of the first `n` diagonal entries (1 when not positive).
fn data_scale(ata: &DMatrix<f64>, n: usize) -> f64 {
    let scale = (0..n).map(|i| ata[(i, i)]).sum::<f64>() / n.max(1) as f64;
    if scale > 0.0 {
        scale
    } else {
        1.0
    }
}

/// [`regularise`] with a given `scale`.
fn regularise_scaled(
    ata: &mut DMatrix<f64>,
    blocks: usize,
    degree: usize,
    smoothing: Smoothing,
    scale: f64,
) {
    let n = coeff_count(degree);
    let rough = roughness(degree, smoothing.order);
    for b in 0..blocks {
        for (k, r) in rough.iter().enumerate() {
            ata[(b * n + k, b * n + k)] += scale * (smoothing.weight * r + 1e-9);
        }
    }
}

/// The penalty of [`SMOOTHING_GRID`] x `orders` whose fits
/// without each take predict that take best, on unknowns whose first three
/// blocks are SH coefficients, with its held-out score
/// ([`crate::fit::select::choose`]).
pub(crate) fn cross_validated(
    takes: &[Normals],
    held_out: &[Normals],
    total: &Normals,
    orders: &[u32],
    fallback: Smoothing,
    degree: usize,
) -> (f64, Smoothing) {
    let scale = data_scale(&total.ata, 3 * coeff_count(degree));
    let candidates: Vec<Smoothing> = orders
        .iter()
        .flat_map(|&order| {
            SMOOTHING_GRID
                .iter()
                .map(move |&weight| Smoothing { weight, order })
        })
        .collect();
    crate::fit::select::choose(takes, held_out, total, &candidates, fallback, |m, p| {
        regularise_scaled(m, 3, degree, p, scale);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn higher_orders_penalise_low_degrees_less_and_the_top_degree_alike() {
        let first = roughness(8, 1);
        assert_eq!(first.len(), 81);
        for order in 2..=4 {
            let r = roughness(8, order);
            // Degree 8 (the last 17 coefficients) costs 72 whatever the order.
            assert!(r.iter().skip(64).all(|v| (v - 72.0).abs() < 1e-9), "{r:?}");
            // Degree 0 is free; degrees 1-7 cost less than at order 1, and
            // less the higher the order.
            assert_eq!(r.first().copied(), Some(0.0));
            let lower = roughness(8, order - 1);
            for k in 1..64 {
                assert!(r[k] < lower[k], "order {order}, coefficient {k}");
            }
        }
    }
}
