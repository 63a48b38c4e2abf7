//! A carried wind's increment judged exactly: the round's frames moved to
//! the stepped wind, the selection scored there on held-out takes.
//!
//! Why: in a round that holds a wind, the wind candidate is the base
//! model's response linearised about that wind, and its held-out force
//! and torque gains are those of the linearisation, which for a step of
//! a sizeable fraction of the fall speed can misjudge it. Measured on
//! MuJoCo's plate in a (1.4, 0.5, 0) m/s wind (seed 2), where the first
//! round's search is the same with or without this: the rounds held
//! (1.36, 0.87, 0.19) m/s with the increments rejected and C_F 25 % off;
//! judged exactly, the increments of refits 1 and 2 ((0.02, -0.13,
//! -0.05), (0.02, -0.09, 0.04) m/s) moved it to (1.41, 0.58, 0.21), C_F
//! 22 % off. A significant increment the linearisation rejects is therefore
//! judged as the wind search judges a wind ([`super::wind_search`]): the
//! frames' air velocity moved by it (`in_wind`), C_F and C_T refitted in
//! each held-out fold, and the round's selection scored there against
//! the same frames unmoved; the step (or the largest of its
//! [`HALVINGS`] halvings) that lowers both the held-out force error and
//! the force-and-torque score moves the wind.

use super::wind_search::{in_wind, HALVINGS};
use super::Round;
use crate::reconstruct::forces::Sample;
use crate::residual::problems::Problems;
use crate::residual::select::{reduction, score, score_reduction, Scored};
use nalgebra::Vector3;

/// The step from `dw` that lowers the held-out force error and the
/// force-and-torque score of round `r`'s selection, judged on its frames
/// (the takes its selection used) moved by it; `None` when neither `dw`
/// nor a halving does. `build(samples)` gives the joint problems on
/// `samples` (`None` when they cannot be built).
pub(super) fn judge(
    r: &Round,
    dw: Vector3<f64>,
    build: &dyn Fn(&[Sample]) -> Option<Problems>,
) -> Option<Vector3<f64>> {
    let takes = &r.p.force.take_ids;
    let samples = r.selection_samples();
    let design = r.selected_besides_wind();
    let scored = |frames: &[Sample]| -> Option<Scored> {
        let s = score(&build(frames)?, &design)?;
        (s.per_take.len() == takes.len()).then_some(s)
    };
    let here = scored(&samples)?;
    let mut step = dw;
    for _ in 0..=HALVINGS {
        let moved = in_wind(&samples, &r.outcome.reconstruction, &step);
        if let Some(there) = scored(&moved) {
            let force = reduction(here.total(), there.total());
            if force > 0.0 && score_reduction(&r.sel.baseline, &here, &there) > 0.0 {
                return Some(step);
            }
        }
        step *= 0.5;
    }
    None
}
