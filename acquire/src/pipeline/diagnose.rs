//! Why a first fit failed: a model that comes out non-finite (or cannot be
//! solved) says which take's frames made it impossible, so the message
//! points at an input rather than at a coefficient array.

use crate::error::Error;
use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::Smoothed;
use crate::reconstruct::forces::Sample;

/// Per take: frames, non-finite frames, largest force in object weights.
#[derive(Default, Clone, Copy)]
struct TakeFrames {
    frames: usize,
    non_finite: usize,
    weights: f64,
}

/// `e` (the first iteration's fit error) with the take whose frames are
/// worst (most non-finite frames, then the largest force) and the take the
/// filter restarted most in.
pub(super) fn first_fit_failed(
    e: Error,
    set: &RecordingSet,
    smoothed: &[Smoothed],
    frames: &[Sample],
) -> Error {
    let weight = set.object.mass * set.world.gravity.norm();
    let mut per = vec![TakeFrames::default(); set.takes.len()];
    for s in frames {
        if let Some(t) = per.get_mut(s.take) {
            t.frames += 1;
            let finite = s
                .force
                .iter()
                .chain(&s.torque)
                .chain(&s.velocity)
                .all(|v| v.is_finite());
            if finite {
                t.weights = t.weights.max(s.force.norm() / weight);
            } else {
                t.non_finite += 1;
            }
        }
    }
    let worst = set.takes.iter().zip(&per).max_by(|(_, a), (_, b)| {
        (a.non_finite, a.weights)
            .partial_cmp(&(b.non_finite, b.weights))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut why = format!("{e}");
    if let Some((take, t)) = worst {
        why += &format!(
            "; take `{}` has the worst frames ({} of {} non-finite, force up to {:.3e} times \
             the object's weight)",
            take.name, t.non_finite, t.frames, t.weights
        );
    }
    if let Some((take, s)) = set
        .takes
        .iter()
        .zip(smoothed)
        .max_by_key(|(_, s)| s.stats.restarts)
    {
        why += &format!(
            "; the filter restarted most in take `{}` ({} times)",
            take.name, s.stats.restarts
        );
    }
    Error::Data(format!(
        "{why}. The first reconstruction cannot support a model: check that take's tracks and \
         {INPUTS}"
    ))
}

/// The inputs that make a first reconstruction impossible.
const INPUTS: &str = "recording.toml's camera (fps, distortion, pixel_noise, pose) and object \
                      (inertia, markers)";

/// Too few takes could be reconstructed: each left-out take named with
/// why, and the inputs to check.
pub(super) fn too_few_takes<'a>(
    kept: usize,
    total: usize,
    min: usize,
    left_out: impl Iterator<Item = (&'a str, &'a str)>,
) -> Error {
    let named: Vec<String> = left_out
        .map(|(take, why)| format!("take `{take}` ({why})"))
        .collect();
    Error::Data(format!(
        "only {kept} of {total} takes could be reconstructed (at least {min} are needed); \
         left out: {}. Check those takes' tracks and {INPUTS}",
        named.join("; ")
    ))
}
