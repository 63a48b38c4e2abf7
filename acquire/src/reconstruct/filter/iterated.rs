//! Iterated smoothing: the filter and smoother run again with the process
//! model and the marker projections linearised about the previous sweep's
//! smoothed trajectory instead of about the running filtered estimate (the
//! iterated extended Kalman smoother; at convergence it is Gauss-Newton on
//! the whole take's maximum-a-posteriori problem of §5).
//!
//! Why: the first sweep linearises the early frames about a rough guess
//! (zero velocity, a pose from the first frame), and the RTS pass corrects
//! them only to first order about those poor points. Along the line of sight
//! a frame's markers fix the position only to ~10 cm (the constellation's
//! size in pixels); the take's dynamics (gravity's absolute scale, the
//! model's drag) are what tie the depth down, and they act through the
//! process Jacobians, which are only right about a good trajectory.

use super::{finite, smooth, Filter, Posterior, Step};
use crate::input::tracks::Epoch;
use crate::reconstruct::state::{boxminus, boxplus, Cov, FilterState};

use super::FilterStats;

/// A sweep stops the iteration when no smoothed position moved by more
/// than this, m (far below the pixel noise's depth resolution).
pub const CONVERGED_POSITION: f64 = 2e-4;

impl Filter<'_> {
    /// One forward sweep linearised about `reference` (one smoothed state
    /// per epoch): the prediction is `f(x̄) ⊕ F (x ⊖ x̄)` with `F` at the
    /// reference, and every marker update's Gauss-Newton starts at the
    /// reference. The prior of the first epoch is `initial` as in the first
    /// sweep. At an epoch where the first sweep moved to the other
    /// mirror-image branch (`switched`), the chain is cut: the prediction is
    /// the reference with the initial covariance added, and the smoother
    /// does not cross it.
    pub(super) fn forward_about(
        &self,
        epochs: &[Epoch],
        initial: FilterState,
        reference: &[FilterState],
        switched: &[bool],
        stats: &mut FilterStats,
    ) -> Vec<Step> {
        let mut out: Vec<Step> = Vec::with_capacity(epochs.len());
        let mut lost = 0;
        for (k, (e, r)) in epochs.iter().zip(reference).enumerate() {
            let cut = switched.get(k).copied().unwrap_or(false);
            let (predicted, predicted_cov, jacobian) = match (out.last(), k.checked_sub(1)) {
                (Some(p), Some(j)) if !cut => {
                    let prev_ref = reference.get(j).copied().unwrap_or(p.filtered);
                    let prev_t = epochs.get(j).map_or(e.t, |x| x.t);
                    let dt = e.t - prev_t;
                    let (fx, f) = self.process.step_with_jacobian(&prev_ref, dt);
                    let x = boxplus(&fx, &(f * boxminus(&p.filtered, &prev_ref)));
                    let cov =
                        f * p.filtered_cov * f.transpose() + self.process.noise(&prev_ref, dt);
                    if finite(&x) && cov.iter().all(|v| v.is_finite()) {
                        (x, cov, f)
                    } else {
                        stats.restarts += 1;
                        (*r, p.filtered_cov + self.initial_cov(), Cov::identity())
                    }
                }
                (Some(p), _) => (*r, p.filtered_cov + self.initial_cov(), Cov::identity()),
                (None, _) => (initial, self.initial_cov(), Cov::identity()),
            };
            let (mut filtered, mut filtered_cov) = self.update(
                &e.observation,
                r,
                &predicted,
                &predicted_cov,
                &mut lost,
                stats,
            );
            if !finite(&filtered) || filtered_cov.iter().any(|v| !v.is_finite()) {
                stats.restarts += 1;
                (filtered, filtered_cov) = (predicted, predicted_cov);
            }
            out.push(Step {
                predicted,
                predicted_cov,
                filtered,
                filtered_cov,
                jacobian,
                switched: cut,
                stats: *stats,
                lost,
            });
        }
        out
    }

    /// Sweeps linearised about the previous smoothed trajectory until it
    /// stops moving ([`CONVERGED_POSITION`]) or `sweeps` are done, keeping a
    /// sweep only when it does not fit the markers worse ([`diverged`]: a
    /// Gauss-Newton step is accepted only if it does not increase the
    /// misfit, as in Levenberg-Marquardt); returns
    /// the last smoothed trajectory and its sweep's counts (`stats` on
    /// entry: the first sweep's, whose mirror switches are kept).
    pub(super) fn relinearise(
        &self,
        epochs: &[Epoch],
        initial: FilterState,
        reference: (Vec<FilterState>, Posterior),
        switched: &[bool],
        mut stats: FilterStats,
        sweeps: usize,
    ) -> ((Vec<FilterState>, Posterior), FilterStats) {
        let (mut smoothed, mut dv) = reference;
        for _ in 0..sweeps {
            let mut s = FilterStats {
                mirror_switches: stats.mirror_switches,
                ..FilterStats::default()
            };
            let steps = self.forward_about(epochs, initial, &smoothed, switched, &mut s);
            let (next, next_dv) = smooth(&steps);
            if next.len() != smoothed.len()
                || next.iter().any(|x| !finite(x))
                || diverged(&s, &stats)
            {
                break;
            }
            let moved = next
                .iter()
                .zip(&smoothed)
                .map(|(a, b)| (a.body.position - b.body.position).norm())
                .fold(0.0, f64::max);
            smoothed = next;
            dv = next_dv;
            stats = s;
            if moved < CONVERGED_POSITION {
                break;
            }
        }
        ((smoothed, dv), stats)
    }
}

/// Rows a relinearised sweep may lose to gating, unprojectable markers or
/// restarts beyond the previous sweep's before it counts as diverged, as a
/// fraction of the rows used.
pub const DIVERGED_ROWS: f64 = 0.005;

/// The sweep that gave `new` fits the markers clearly worse than the one
/// that gave `old`: it gated, failed to project or restarted on more than
/// [`DIVERGED_ROWS`] more of the rows (a relinearisation about a poor
/// reference can run away; that sweep is then discarded).
fn diverged(new: &FilterStats, old: &FilterStats) -> bool {
    let bad = |s: &FilterStats| (s.gated + s.unprojectable + s.restarts) as f64;
    let rows = (new.used + new.gated) as f64;
    bad(new) > bad(old) + DIVERGED_ROWS * rows
}
