//! How well a take's reconstruction fits its own observations: the
//! reprojection RMS of the smoothed states against the recorded marker
//! pixels (or poses), the filter's own measurement model (§5, `h(s)`:
//! `x = y + R X` through the camera).
//!
//! Why here: a refit round reconstructs every take again with the round's
//! process model; whether a take's reconstruction *broke* in a round is a
//! question about that reconstruction and its markers, not about the
//! held-out force, which also rises when the round's model simply fits the
//! take worse. See [`super::takes`].

use crate::input::recording::{RecordingSet, Take};
use crate::input::tracks::Observation;
use crate::reconstruct::filter::Smoothed;

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
    (pixel_noise, pose_noise): (f64, f64),
) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0.0);
    for (epoch, state) in take.epochs.iter().zip(&s.states) {
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
    }
    let m = sum / n;
    (n > 0.0 && m.is_finite()).then_some(m)
}

/// [`misfit`] of every take of `set` (index in the set; takes without a
/// reconstruction are skipped), with the camera's pixel noise and the
/// filter's pose-position noise `pose_noise` (m).
pub(crate) fn per_take(set: &RecordingSet, rec: &[Smoothed], pose_noise: f64) -> Vec<(usize, f64)> {
    let pixel = set.camera.as_ref().map_or(1.0, |c| c.pixel_noise);
    set.takes
        .iter()
        .zip(rec)
        .enumerate()
        .filter_map(|(i, (t, s))| misfit(set, t, s, (pixel, pose_noise)).map(|r| (i, r)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::residual::null::tests::truth;
    use crate::residual::refit::takes::{broken, MARKER_EXCESS};
    use crate::synth::write::generate;
    use crate::synth::{SynthConfig, SynthObject};
    use nalgebra::{UnitQuaternion, Vector3};

    /// The true states explain their markers to the noise (misfit per
    /// degree of freedom about 1); the same take with 15 of its frames
    /// turned by 20° about the line of sight's normal (a reconstruction
    /// that lost the object there) misfits by far more than the noise and
    /// is named broken against the true states; a 1 mm offset is not.
    #[test]
    fn misfit_of_true_and_broken_states() {
        let dir = tempfile::tempdir().expect("dir");
        let cfg = SynthConfig {
            object: SynthObject::Plate,
            takes: (1, 1),
            ..SynthConfig::default()
        };
        generate(dir.path(), &cfg).expect("synth");
        let set = RecordingSet::load(dir.path()).expect("load");
        let rec: Vec<Smoothed> = set
            .takes
            .iter()
            .map(|t| truth(dir.path(), &format!("{}.csv", t.name)))
            .collect();
        let good = per_take(&set, &rec, 0.002);
        assert_eq!(good.len(), 2);
        for &(_, m) in &good {
            assert!((0.7..1.3).contains(&m), "true states misfit {m}");
        }
        let mut bad = rec.clone();
        let turn = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 20f64.to_radians());
        for s in bad[0].states.iter_mut().skip(40).take(15) {
            s.orientation = turn * s.orientation;
        }
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
