//! The Rauch-Tung-Striebel backward pass (§5) and the posterior
//! covariance of the velocity differences that eqs. (9)-(10) use.

use super::Step;
use crate::reconstruct::state::{boxminus, boxplus, Cov, FilterState};
use nalgebra::{Matrix3, Matrix6};

/// Posterior covariances of a smoothed take that the force fit needs, per
/// epoch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Posterior {
    /// `velocity_difference_cov`, world frame, (m/s)².
    pub velocity_difference: Vec<Matrix3<f64>>,
    /// The block of the attitude error (rad, body frame) and the velocity
    /// (m/s, world frame), in that order: what [`body_velocity_cov`] is made
    /// from.
    pub attitude_velocity: Vec<Matrix6<f64>>,
}

/// Rauch-Tung-Striebel backward pass in error-state form; also returns the
/// [`Posterior`] covariances of the smoothed trajectory.
pub(super) fn smooth(steps: &[Step]) -> (Vec<FilterState>, Posterior) {
    let n = steps.len();
    let mut out: Vec<FilterState> = steps.iter().map(|s| s.filtered).collect();
    // Smoothed covariances and gains `G_k` (None: epoch k+1 not linked).
    let mut covs: Vec<Cov> = steps.iter().map(|s| s.filtered_cov).collect();
    let mut gains: Vec<Option<Cov>> = vec![None; n];
    let Some(last) = steps.last() else {
        return (out, Posterior::default());
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
    let posterior = Posterior {
        velocity_difference: velocity_difference_cov(&covs, &gains),
        attitude_velocity: covs.iter().map(attitude_velocity_block).collect(),
    };
    (out, posterior)
}

/// The attitude-and-velocity block of an error-state covariance `p`
/// (attitude error in rad, body frame; velocity in m/s, world frame).
fn attitude_velocity_block(p: &Cov) -> Matrix6<f64> {
    const THETA: usize = 3;
    p.fixed_view::<6, 6>(THETA, THETA).into_owned()
}

/// The covariance of the body-frame velocity `V = Rᵀv` of state `x` whose
/// attitude error (body frame) and velocity (world frame) have covariance
/// `block` ((m/s)²): with `R' = R exp([δθ]×)`, `δV = Rᵀδv + [V]× δθ`.
pub fn body_velocity_cov(x: &omniad_core::State<f64>, block: &Matrix6<f64>) -> Matrix3<f64> {
    let r = x.orientation.to_rotation_matrix().into_inner();
    let v = r.transpose() * x.velocity;
    let mut a = nalgebra::SMatrix::<f64, 3, 6>::zeros();
    a.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&crate::reconstruct::measurement::skew(&v));
    a.fixed_view_mut::<3, 3>(0, 3).copy_from(&r.transpose());
    let c = a * block * a.transpose();
    0.5 * (c + c.transpose())
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
    fn body_velocity_cov_matches_finite_differences() {
        use crate::reconstruct::state::{boxplus, Delta};
        let x = FilterState::new(omniad_core::State {
            position: nalgebra::Vector3::new(0.1, -0.2, 3.0),
            orientation: nalgebra::UnitQuaternion::from_euler_angles(0.4, -0.3, 1.1),
            velocity: nalgebra::Vector3::new(1.5, -0.5, -4.0),
            angular_velocity: nalgebra::Vector3::new(2.0, 0.0, -1.0),
        });
        let body = |s: &FilterState| {
            s.body
                .orientation
                .inverse_transform_vector(&s.body.velocity)
        };
        // A unit variance in one error component gives the outer product of
        // that component's column of ∂V/∂δ.
        for i in 3..9 {
            let mut p = Cov::zeros();
            p[(i, i)] = 1.0;
            let mut d = Delta::zeros();
            d[i] = 1e-6;
            let column = (body(&boxplus(&x, &d)) - body(&x)) / 1e-6;
            let expected = column * column.transpose();
            let got = body_velocity_cov(&x.body, &attitude_velocity_block(&p));
            assert!(
                (got - expected).norm() < 1e-5 * (1.0 + expected.norm()),
                "component {i}: {got} vs {expected}"
            );
        }
        // Position, angular velocity and the unexplained wrench do not move V.
        let mut p = Cov::zeros();
        for i in (0..3).chain(9..18) {
            p[(i, i)] = 1.0;
        }
        assert_eq!(
            body_velocity_cov(&x.body, &attitude_velocity_block(&p)),
            Matrix3::zeros()
        );
    }

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
