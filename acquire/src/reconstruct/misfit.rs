//! How well a take's reconstruction fits its own observations: the
//! misfit of the smoothed states to the recorded marker pixels (or poses)
//! through the filter's own measurement model (§5, `h(s)`: `x = y + R X`
//! through the camera), per degree of freedom in noise variances.
//!
//! Why here: whether a reconstruction *broke* (lost the object, or took a
//! mirror-image pose branch its markers do not support) is a question about
//! that reconstruction and its markers, asked by the refinement iterations
//! (`pipeline::carry`) and by the residual analysis's refit rounds
//! (`residual::refit::takes`).

use crate::input::recording::{RecordingSet, Take};
use crate::input::tracks::Observation;
use crate::reconstruct::filter::Smoothed;

/// Extra misfit per degree of freedom of a take's markers, in units of
/// their noise variance ([`misfit`]), beyond which the take's
/// reconstruction is broken against an earlier one: the states miss the
/// markers by a systematic error at least as large as the noise itself (the
/// misfit per degree of freedom of a reconstruction that explains its
/// markers is about 1, so the take's markers then fit at least twice as
/// badly, in likelihood terms `-2 ln LR >= n_dof` against the earlier one).
pub const MARKER_EXCESS: f64 = 1.0;

/// The misfit of `s`'s states to `take`'s observations per degree of
/// freedom, in units of the observations' noise variance: the mean over
/// every sighting (2 pixel coordinates, noise `pixel_noise` px) or pose
/// position (3 coordinates, noise `pose_noise` m) of `|r|² / (d σ²)`
/// (`None`: no state or no observation). A reconstruction that explains
/// its markers to their noise gives about 1 (a little less: the states are
/// fitted to them); a systematic miss of `s` per coordinate adds `s²/σ²`.
pub(crate) fn misfit(
    set: &RecordingSet,
    take: &Take,
    s: &Smoothed,
    noise: (f64, f64),
) -> Option<f64> {
    let (sum, n) = per_epoch(set, take, s, noise)?
        .into_iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let m = sum / n;
    (n > 0.0 && m.is_finite()).then_some(m)
}

/// Per epoch of `take` with a state in `s`: the sum of `|r|² / σ²` over its
/// observations and their degrees of freedom (see [`misfit`]); `None`
/// for marker observations without a camera.
fn per_epoch(
    set: &RecordingSet,
    take: &Take,
    s: &Smoothed,
    (pixel_noise, pose_noise): (f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let mut out = Vec::with_capacity(s.states.len());
    for (epoch, state) in take.epochs.iter().zip(&s.states) {
        let (mut sum, mut n) = (0.0, 0.0);
        match &epoch.observation {
            Observation::Markers(seen) => {
                let camera = set.camera.as_ref()?;
                let r = state.orientation.to_rotation_matrix();
                for m in seen {
                    let Some((_, body)) = set.object.markers.get(m.marker) else {
                        continue;
                    };
                    let world = state.position + r * body;
                    if let Some(p) = camera.project(&world) {
                        sum += (p - m.pixel).norm_squared() / pixel_noise.powi(2);
                        n += 2.0;
                    }
                }
            }
            Observation::Pose(y, _) => {
                sum += (y - state.position).norm_squared() / pose_noise.powi(2);
                n += 3.0;
            }
        }
        out.push((sum, n));
    }
    Some(out)
}

/// The largest rise of the misfit per degree of freedom from `before` to
/// `now` (two reconstructions of `take`) over any `window` consecutive
/// epochs, in noise variances: a reconstruction that left the markers'
/// pose branch for a stretch misses them there by tens of pixels, which
/// the whole take's mean would dilute by its length. `None` when either
/// has no misfit (no states, a different length, nothing observed); a
/// window whose rise is not a number counts as `INFINITY`.
pub(crate) fn stretch_rise(
    set: &RecordingSet,
    take: &Take,
    (now, before): (&Smoothed, &Smoothed),
    noise: (f64, f64),
    window: usize,
) -> Option<f64> {
    let a = per_epoch(set, take, now, noise)?;
    let b = per_epoch(set, take, before, noise)?;
    if a.len() != b.len() || a.is_empty() {
        return None;
    }
    let mut worst = f64::NEG_INFINITY;
    for (wa, wb) in a
        .windows(window.clamp(1, a.len()))
        .zip(b.windows(window.clamp(1, b.len())))
    {
        let sum = |w: &[(f64, f64)]| w.iter().fold((0.0, 0.0), |(s, n), (x, y)| (s + x, n + y));
        let ((sa, na), (sb, nb)) = (sum(wa), sum(wb));
        if na > 0.0 && nb > 0.0 {
            let rise = sa / na - sb / nb;
            worst = worst.max(if rise.is_nan() { f64::INFINITY } else { rise });
        }
    }
    (worst > f64::NEG_INFINITY).then_some(worst)
}

/// [`misfit`] of every take of `set` (index in the set; takes without a
/// reconstruction are skipped), with the camera's pixel noise and the
/// filter's pose-position noise `pose_noise` (m).
pub(crate) fn per_take(set: &RecordingSet, rec: &[Smoothed], pose_noise: f64) -> Vec<(usize, f64)> {
    let noise = noises(set, pose_noise);
    set.takes
        .iter()
        .zip(rec)
        .enumerate()
        .filter_map(|(i, (t, s))| misfit(set, t, s, noise).map(|r| (i, r)))
        .collect()
}

/// The observations' noise of `set` for [`misfit`]: the camera's pixel
/// noise (px; 1 without a camera) and the pose-position noise `pose_noise`
/// (m).
pub(crate) fn noises(set: &RecordingSet, pose_noise: f64) -> (f64, f64) {
    let pixel = set.camera.as_ref().map_or(1.0, |c| c.pixel_noise);
    (pixel, pose_noise)
}
