//! How well a take's reconstruction fits its own observations
//! ([`crate::reconstruct::misfit`], which the refinement iterations use
//! too), as the refit rounds ask it.
//!
//! Why: a refit round reconstructs every take again with the round's
//! process model; whether a take's reconstruction *broke* in a round is a
//! question about that reconstruction and its markers, not about the
//! held-out force, which also rises when the round's model simply fits the
//! take worse. See [`super::takes`].

pub(crate) use crate::reconstruct::misfit::per_take;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::residual::null::tests::{plate_with_truth, turn_stretch};
    use crate::residual::refit::takes::{broken, MARKER_EXCESS};

    /// The true states explain their markers to the noise (misfit per
    /// degree of freedom about 1); the same take with 15 of its frames
    /// turned by 20° about the line of sight's normal (a reconstruction
    /// that lost the object there) misfits by far more than the noise and
    /// is named broken against the true states; a 1 mm offset is not.
    #[test]
    fn misfit_of_true_and_broken_states() {
        let (_dir, set, rec) = plate_with_truth();
        let good = per_take(&set, &rec, 0.002);
        assert_eq!(good.len(), 2);
        for &(_, m) in &good {
            assert!((0.7..1.3).contains(&m), "true states misfit {m}");
        }
        let mut bad = rec.clone();
        turn_stretch(&mut bad[0], 40, 15, 20.0);
        let mut near = rec.clone();
        for s in &mut near[0].states {
            s.position.x += 0.001;
        }
        let now = per_take(&set, &bad, 0.002);
        assert!(now[0].1 > good[0].1 + MARKER_EXCESS, "{now:?}");
        let b = broken(&good, &now);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].take, 0);
        assert!(broken(&good, &per_take(&set, &near, 0.002)).is_empty());
    }
}
