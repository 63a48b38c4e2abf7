//! Comparison with a synthetic set's `truth/` (never used by the fitter):
//! state errors of a reconstruction and the coefficient error of a model.

use crate::error::Result;
use crate::fit::coverage::count_within;
use crate::fit::torque::TorqueFrames;
use crate::input::state_csv::read_states;
use crate::input::tracks::{csv_text, number, rows};
use crate::reconstruct::filter::Smoothed;
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::Coefficients;
use std::path::Path;

/// The true trajectory of every take of the set in `dir` (from
/// `truth/<take>.csv`), in the form the force computation takes, for
/// diagnostics that fit from true states.
pub fn true_trajectories(
    dir: &Path,
    set: &crate::input::recording::RecordingSet,
) -> Result<Vec<Smoothed>> {
    set.takes
        .iter()
        .map(|take| {
            let truth = read_states(&dir.join("truth").join(format!("{}.csv", take.name)))?;
            let states = truth
                .iter()
                .map(|r| omniad_core::State {
                    position: Vector3::new(r[1], r[2], r[3]),
                    orientation: UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                        r[4], r[5], r[6], r[7],
                    )),
                    velocity: Vector3::new(r[8], r[9], r[10]),
                    angular_velocity: Vector3::new(r[11], r[12], r[13]),
                })
                .collect();
            Ok(Smoothed {
                times: truth.iter().map(|r| r[0]).collect(),
                states,
                cuts: Vec::new(),
                velocity_difference_cov: Vec::new(),
                attitude_velocity_cov: Vec::new(),
                stats: crate::reconstruct::filter::FilterStats::default(),
            })
        })
        .collect()
}

/// Squared-error sums of a reconstruction against truth rows matched by time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StateError {
    /// Σ |Δy|², m².
    pub position_sq: f64,
    /// Σ angle², rad².
    pub angle_sq: f64,
    /// Matched frames.
    pub count: usize,
}

impl StateError {
    /// Adds another take's sums.
    pub fn add(&mut self, o: &StateError) {
        self.position_sq += o.position_sq;
        self.angle_sq += o.angle_sq;
        self.count += o.count;
    }
    /// RMS position error, m.
    pub fn position_rms(&self) -> f64 {
        (self.position_sq / self.count.max(1) as f64).sqrt()
    }
    /// RMS orientation error, rad.
    pub fn angle_rms(&self) -> f64 {
        (self.angle_sq / self.count.max(1) as f64).sqrt()
    }
}

/// Errors of `s` against truth rows at the same times (within 1 ms).
pub fn state_error(s: &Smoothed, truth: &[[f64; 14]]) -> StateError {
    let mut e = StateError::default();
    for (t, st) in s.times.iter().zip(&s.states) {
        let Some(row) = truth.iter().find(|r| (r[0] - t).abs() < 1e-3) else {
            continue;
        };
        let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            row[4], row[5], row[6], row[7],
        ));
        e.position_sq += (st.position - Vector3::new(row[1], row[2], row[3])).norm_squared();
        e.angle_sq += st.orientation.angle_to(&q).powi(2);
        e.count += 1;
    }
    e
}

/// Reads `truth/coefficients.csv`: (E, C_F, C_T) rows.
pub fn read_coefficients(path: &Path) -> Result<Vec<[Vector3<f64>; 3]>> {
    let text = csv_text(path)?;
    let cols = ["ex", "ey", "ez", "cfx", "cfy", "cfz", "ctx", "cty", "ctz"];
    let mut out = Vec::new();
    for (line, f) in rows(path, &text, &cols)? {
        let mut v = [0.0; 9];
        for ((slot, s), col) in v.iter_mut().zip(&f).zip(cols) {
            *slot = number(path, line, col, s)?;
        }
        out.push([
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
            Vector3::new(v[6], v[7], v[8]),
        ]);
    }
    Ok(out)
}

/// The body-frame air directions of the frames that entered the force fit,
/// for [`force_error`]'s coverage count.
pub fn fitted_directions(samples: &[crate::reconstruct::forces::Sample]) -> Vec<Vector3<f64>> {
    samples
        .iter()
        .filter(|s| s.use_force && s.velocity.norm() > 0.0)
        .map(|s| s.velocity.normalize())
        .collect()
}

/// The body-frame air directions of the frames a torque fit of kind
/// `which` takes (`Stable`: both stability tests passed; the pipeline's
/// final fit: `FitOutcome::torque_frames`), for [`torque_error`]'s
/// coverage count.
pub fn torque_directions(
    samples: &[crate::reconstruct::forces::Sample],
    which: TorqueFrames,
) -> Vec<Vector3<f64>> {
    samples
        .iter()
        .filter(|s| which.takes(s) && s.velocity.norm() > 0.0)
        .map(|s| s.velocity.normalize())
        .collect()
}

/// The three direction sets `C_T` is scored over (`omniad lab accept`,
/// BENCHMARKS issue 20): the frames the pipeline's final torque fit takes
/// (`which`, from the reconstruction `samples`), the reconstruction's
/// frames that pass both stability tests, and the true states' such frames
/// (`true_frames`: the same set whatever the reconstruction, so runs with
/// different reconstructions compare on common ground).
pub fn torque_direction_sets(
    samples: &[crate::reconstruct::forces::Sample],
    which: TorqueFrames,
    true_frames: &[crate::reconstruct::forces::Sample],
) -> [Vec<Vector3<f64>>; 3] {
    [
        torque_directions(samples, which),
        torque_directions(samples, TorqueFrames::Stable),
        torque_directions(true_frames, TorqueFrames::Stable),
    ]
}

/// Relative L2 error of the model's `C_F` over the truth grid directions
/// that have at least `min_frames` of `directions` within `angle` rad:
/// `sqrt(Σ|C_F - C_F*|² / Σ|C_F*|²)`, and the number of such directions.
pub fn force_error(
    model: &Coefficients<f64>,
    truth: &[[Vector3<f64>; 3]],
    directions: &[Vector3<f64>],
    min_frames: usize,
    angle: f64,
) -> (f64, usize) {
    coefficient_error(
        model,
        truth,
        directions,
        min_frames,
        angle,
        Coefficient::Force,
    )
}

/// The C_T error by the acceptance rule (issue 20 item 5: truth grid
/// directions with at least 20 of the torque-fit `directions` within 15°),
/// as [`coefficient_error`] with [`Coefficient::Torque`].
pub fn torque_error(
    model: &Coefficients<f64>,
    truth: &[[Vector3<f64>; 3]],
    directions: &[Vector3<f64>],
) -> (f64, usize) {
    coefficient_error(
        model,
        truth,
        directions,
        20,
        15f64.to_radians(),
        Coefficient::Torque,
    )
}

/// Which coefficient [`coefficient_error`] scores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coefficient {
    /// The force coefficient `C_F` (eq. 7).
    Force,
    /// The torque coefficient `C_T` (eq. 8's dimensionless `Σ_i E^i
    /// β^i·Y`, body frame; the damping D is not in it), scored normally
    /// over [`torque_directions`].
    Torque,
}

/// The relative L2 error of `which` coefficient over the truth grid
/// directions covered by `directions` (as [`force_error`]):
/// `sqrt(Σ|C - C*|² / Σ|C*|²)`, and the number of such directions.
pub fn coefficient_error(
    model: &Coefficients<f64>,
    truth: &[[Vector3<f64>; 3]],
    directions: &[Vector3<f64>],
    min_frames: usize,
    angle: f64,
    which: Coefficient,
) -> (f64, usize) {
    let (mut num, mut den, mut n) = (0.0, 0.0, 0);
    for row in truth {
        let e = row[0].normalize();
        if count_within(directions, &e, angle) < min_frames {
            continue;
        }
        let Some(c) = model.at_direction(&e) else {
            continue;
        };
        let (fitted, true_value) = if which == Coefficient::Torque {
            (c.torque, row[2])
        } else {
            (c.force, row[1])
        };
        num += (fitted - true_value).norm_squared();
        den += true_value.norm_squared();
        n += 1;
    }
    (
        if den > 0.0 {
            (num / den).sqrt()
        } else {
            f64::NAN
        },
        n,
    )
}
