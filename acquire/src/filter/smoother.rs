//! The Rauch-Tung-Striebel backward pass (§5) and the posterior
//! covariance of the velocity differences that eqs. (9)-(10) use.

use super::Step;
use crate::state::{boxminus, boxplus, Cov, FilterState};
use nalgebra::Matrix3;

/// Rauch-Tung-Striebel backward pass in error-state form; also returns
/// [`velocity_difference_cov`] of the smoothed trajectory.
pub(super) fn smooth(steps: &[Step]) -> (Vec<FilterState>, Vec<Matrix3<f64>>) {
    let n = steps.len();
    let mut out: Vec<FilterState> = steps.iter().map(|s| s.filtered).collect();
    // Smoothed covariances and gains `G_k` (None: epoch k+1 not linked).
    let mut covs: Vec<Cov> = steps.iter().map(|s| s.filtered_cov).collect();
    let mut gains: Vec<Option<Cov>> = vec![None; n];
    let Some(last) = steps.last() else {
        return (out, Vec::new());
    };
    let mut next_cov = last.filtered_cov;
    for k in (0..n.saturating_sub(1)).rev() {
        let (Some(cur), Some(nxt), Some(&xs_next)) =
            (steps.get(k), steps.get(k + 1), out.get(k + 1))
        else {
            break;
        };
        if nxt.switched {
            next_cov = cur.filtered_cov;
            continue;
        }
        let Some(pp_inv) = nxt.predicted_cov.cholesky().map(|c| c.inverse()) else {
            continue;
        };
        let gain = cur.filtered_cov * nxt.jacobian.transpose() * pp_inv;
        let delta = gain * boxminus(&xs_next, &nxt.predicted);
        let cov = cur.filtered_cov + gain * (next_cov - nxt.predicted_cov) * gain.transpose();
        next_cov = 0.5 * (cov + cov.transpose());
        if let Some(slot) = out.get_mut(k) {
            *slot = boxplus(&cur.filtered, &delta);
        }
        if let (Some(c), Some(g)) = (covs.get_mut(k), gains.get_mut(k)) {
            *c = next_cov;
            *g = Some(gain);
        }
    }
    (out, velocity_difference_cov(&covs, &gains))
}

/// Per epoch k, the posterior covariance of `v_{k+1} - v_{k-1}` (world
/// frame), the velocity difference of eqs. (9)-(10): with the smoothed
/// covariances `P_k` and the RTS gains `G_k`, the smoothed errors satisfy
/// `Cov(e_{k-1}, e_{k+1}) = G_{k-1} G_k P_{k+1}`, so it is
/// `P_{k+1} + P_{k-1} - C - Cᵀ` on the velocity block, `C` that cross term
/// (zero across a cut, which is conservative). Zero at the ends.
fn velocity_difference_cov(covs: &[Cov], gains: &[Option<Cov>]) -> Vec<Matrix3<f64>> {
    const V: usize = 6;
    let n = covs.len();
    let mut out = vec![Matrix3::zeros(); n];
    for k in 1..n.saturating_sub(1) {
        let (Some(prev), Some(next)) = (covs.get(k - 1), covs.get(k + 1)) else {
            continue;
        };
        let vv = |p: &Cov| p.fixed_view::<3, 3>(V, V).into_owned();
        let mut sum = vv(prev) + vv(next);
        if let (Some(Some(g0)), Some(Some(g1))) = (gains.get(k - 1), gains.get(k)) {
            let cross = (g0 * g1 * next).fixed_view::<3, 3>(V, V).into_owned();
            sum -= cross + cross.transpose();
        }
        if let Some(slot) = out.get_mut(k) {
            *slot = 0.5 * (sum + sum.transpose());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocity_difference_cov_uses_the_cross_covariance() {
        let p = Cov::identity() * 2.0;
        // Unlinked epochs: the two velocity errors are independent.
        let free = velocity_difference_cov(&[p, p, p], &[None, None, None]);
        assert!((free[1] - Matrix3::identity() * 4.0).norm() < 1e-12);
        assert_eq!(free[0], Matrix3::zeros());
        // Gains of one: the errors are the same, their difference is exact.
        let g = Some(Cov::identity());
        let tied = velocity_difference_cov(&[p, p, p], &[g, g, None]);
        assert!(tied[1].norm() < 1e-12);
    }
}
