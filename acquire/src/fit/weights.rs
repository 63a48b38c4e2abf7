//! Frame weighting of the force fit: generalised least-squares weights
//! from the smoother's force covariance, the velocity's spread through the
//! model's slope, and the markers-only covariances of the refinement.

use crate::reconstruct::filter::Smoothed;
use crate::reconstruct::forces::Sample;
use nalgebra::{Matrix3, Vector3};
use omniad_core::Coefficients;

/// Frames the force fit uses: every frame that passes the no-thrust test,
/// drops (K1) and spins (K2) alike. (§6 fits C_F on K1 only; the spin
/// takes add directions the drops rarely reach, and with the spin-coupling
/// extension their spin-driven forces are modelled rather than misread as
/// C_F. Measured on every set in BENCHMARKS.md: C_F error lower on 8 of 9.)
pub(crate) fn force_frames(samples: &[Sample]) -> Vec<&Sample> {
    samples
        .iter()
        .filter(|s| s.use_force && s.velocity.norm() > 0.0)
        .collect()
}

/// The error the smoother's covariance does not describe (SH truncation,
/// unsteady air), as a fraction of the mean reconstruction variance (see
/// [`force_weights`]). Small: the covariance is roughly calibrated (it
/// over-states the error, `omniad lab forcenoise`), and C_F is insensitive
/// below a few per cent (openbox-clean 6.80 / 6.78 / 6.77 % at 0.03 / 0.01
/// / 0.001; 7.28 % at 1, 7.96 % unweighted; BENCHMARKS.md stop 11; with
/// the markers-only covariances of stop 12, 5.91 / 5.86 / 5.84 % at 0.03 /
/// 0.01 / 0.003, 6.07 % at 0.1). It only keeps the weights bounded where
/// `Σ_F` is nearly singular.
pub const UNDESCRIBED_VARIANCE: f64 = 0.01;

/// Per-frame weights of the force residual (body frame), generalised least
/// squares: `σ² (Σ_F + σ² I)⁻¹`, `Σ_F` the smoother's posterior covariance
/// of the reconstructed force ([`Sample::force_cov`]; large along the
/// poorly observed line of sight, §5; in the refinement the model-free
/// reconstruction's, plus the velocity's spread) and `σ² I` the error it does not
/// describe, [`UNDESCRIBED_VARIANCE`] times the mean reconstruction variance
/// `mean tr Σ_F / 3`: along an eigenvector of `Σ_F` of variance `λ` the
/// weight is `σ²/(σ² + λ)`, in (0, 1] (no weight can blow up), nearly
/// `σ²/λ` (the inverse covariance) where the reconstruction is uncertain.
/// Identity when no frame has a covariance (e.g. true states).
pub(crate) fn force_weights(frames: &[&Sample]) -> Vec<Matrix3<f64>> {
    let mean =
        frames.iter().map(|s| s.force_cov.trace()).sum::<f64>() / (3 * frames.len().max(1)) as f64;
    let sigma2 = UNDESCRIBED_VARIANCE * mean;
    let identity = Matrix3::identity();
    if sigma2 <= 0.0 || !sigma2.is_finite() {
        return vec![identity; frames.len()];
    }
    frames
        .iter()
        .map(|s| {
            (s.force_cov + identity * sigma2)
                .try_inverse()
                .map_or(identity, |w| w * sigma2)
        })
        .collect()
}

/// `smoothed` with the covariances of `first`, the same takes smoothed with
/// no model (§6's first iteration): that of eq. (9)'s velocity difference
/// (world frame) and that of the attitude and velocity, which
/// [`Smoothed::body_velocity_cov`] turns into the body velocity's about
/// `smoothed`'s own states. A take whose epochs differ in number keeps
/// its own.
///
/// Why: with a model, the smoother's posterior is tight wherever the
/// model rather than the markers fixed the state, above all the velocity
/// along the camera's line of sight, which the markers show only through
/// their spread. Those frames repeat the model being refined; weighed by
/// that posterior they counted most, and the refinement confirmed its own
/// model (through the camera's tilt the line-of-sight velocity sets |V|).
/// Weighed by what the markers alone say, the refit can move away from it.
pub(crate) fn with_markers_only_covariances(
    smoothed: &[Smoothed],
    first: &[Smoothed],
) -> Vec<Smoothed> {
    smoothed
        .iter()
        .zip(first)
        .map(|(s, f)| {
            let mut out = s.clone();
            if f.velocity_difference_cov.len() == s.states.len()
                && f.attitude_velocity_cov.len() == s.states.len()
            {
                out.velocity_difference_cov
                    .clone_from(&f.velocity_difference_cov);
                out.attitude_velocity_cov
                    .clone_from(&f.attitude_velocity_cov);
            }
            out
        })
        .collect()
}

/// Adds to each frame's force covariance the spread of the model's force
/// that the uncertainty of its body-frame velocity causes, `J Σ_V Jᵀ`
/// with `J = ∂F_model/∂V` (central differences) and `Σ_V` the smoother's
/// ([`Smoothed::body_velocity_cov`]): the fit regresses the force on the
/// velocity, whose error makes a residual of its own (errors in
/// variables; the effective-variance method).
pub(crate) fn add_velocity_spread(
    frames: &mut [Sample],
    smoothed: &[Smoothed],
    model: &Coefficients<f64>,
    air_density: f64,
) {
    for s in frames {
        let Some(cov) = smoothed
            .get(s.take)
            .and_then(|x| x.body_velocity_cov(s.index))
        else {
            continue;
        };
        let speed = s.velocity.norm();
        if speed.is_nan() || speed <= 0.0 {
            continue;
        }
        let h = 1e-4 * speed;
        let mut j = nalgebra::Matrix3::zeros();
        for c in 0..3 {
            let mut e = Vector3::zeros();
            e[c] = h;
            let f = |v: Vector3<f64>| model.wrench(&v, &s.angular_velocity, air_density).force;
            j.set_column(c, &((f(s.velocity + e) - f(s.velocity - e)) / (2.0 * h)));
        }
        let spread = j * cov * j.transpose();
        if spread.iter().all(|v| v.is_finite()) {
            s.force_cov += spread;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::lsq::tests::samples;
    use crate::input::recording::TakeKind;
    use crate::reconstruct::filter::FilterStats;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use omniad_core::State;

    fn frame(velocity: Vector3<f64>) -> Sample {
        Sample {
            take: 0,
            index: 1,
            t: 0.0,
            kind: TakeKind::Drop,
            velocity,
            angular_velocity: Vector3::new(1.0, -2.0, 0.5),
            velocity_rate: Vector3::zeros(),
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            gravity_body: Vector3::new(0.0, 0.0, -9.81),
            force_cov: Matrix3::identity() * 1e-4,
            use_force: true,
            use_torque: true,
        }
    }

    #[test]
    fn velocity_spread_is_the_models_slope_times_the_velocity_covariance() {
        let model = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let cov = Matrix3::new(4e-4, 1e-4, 0.0, 1e-4, 9e-4, -2e-4, 0.0, -2e-4, 1e-3);
        // At rest and unrotated, the body velocity's covariance is the
        // world velocity's block.
        let mut block = nalgebra::Matrix6::zeros();
        block.fixed_view_mut::<3, 3>(3, 3).copy_from(&cov);
        let rest = State {
            position: Vector3::zeros(),
            orientation: nalgebra::UnitQuaternion::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
        };
        let smoothed = vec![Smoothed {
            times: vec![0.0; 3],
            states: vec![rest; 3],
            cuts: Vec::new(),
            velocity_difference_cov: Vec::new(),
            attitude_velocity_cov: vec![
                nalgebra::Matrix6::zeros(),
                block,
                nalgebra::Matrix6::zeros(),
            ],
            stats: FilterStats::default(),
        }];
        let v = Vector3::new(1.0, -3.0, 2.0);
        let mut frames = vec![frame(v)];
        add_velocity_spread(&mut frames, &smoothed, &model, 1.2);
        // The slope by a coarser difference than the function's own.
        let f = |v: Vector3<f64>| model.wrench(&v, &Vector3::new(1.0, -2.0, 0.5), 1.2).force;
        let h = 1e-3;
        let j = Matrix3::from_columns(&[0, 1, 2].map(|c| {
            let e = Vector3::ith(c, h);
            (f(v + e) - f(v - e)) / (2.0 * h)
        }));
        let expected = Matrix3::identity() * 1e-4 + j * cov * j.transpose();
        let got = frames.first().map(|s| s.force_cov).unwrap_or_default();
        assert!(
            (got - expected).norm() < 1e-4 * expected.norm(),
            "{got} vs {expected}"
        );
        assert!(j.norm() > 0.0);
        // The zero model has no slope; a frame without a covariance keeps
        // its own.
        let zero = Coefficients::zeros(6, model.pole(), model.reference_length()).expect("zero");
        let mut frames = vec![frame(v)];
        add_velocity_spread(&mut frames, &smoothed, &zero, 1.2);
        assert_eq!(
            frames.first().map(|s| s.force_cov),
            Some(Matrix3::identity() * 1e-4)
        );
        let mut frames = vec![Sample {
            index: 7,
            ..frame(v)
        }];
        add_velocity_spread(&mut frames, &smoothed, &model, 1.2);
        assert_eq!(
            frames.first().map(|s| s.force_cov),
            Some(Matrix3::identity() * 1e-4)
        );
    }

    fn take(states: Vec<State<f64>>, scale: f64) -> Smoothed {
        let n = states.len();
        Smoothed {
            times: (0..n).map(|k| k as f64 / 60.0).collect(),
            states,
            cuts: vec![false; n],
            velocity_difference_cov: vec![Matrix3::identity() * scale; n],
            attitude_velocity_cov: (0..n)
                .map(|k| {
                    let a = nalgebra::Matrix6::<f64>::from_fn(|i, j| {
                        scale * (1.0 + (i * 6 + j + k) as f64 * 0.01)
                    });
                    a * a.transpose()
                })
                .collect(),
            stats: FilterStats::default(),
        }
    }

    #[test]
    fn markers_only_covariances_are_the_first_runs_about_the_current_states() {
        let state = |k: usize| State {
            position: Vector3::zeros(),
            orientation: nalgebra::UnitQuaternion::from_euler_angles(0.3 * k as f64, -0.2, 1.0),
            velocity: Vector3::new(0.5, -0.2 * k as f64, -2.0),
            angular_velocity: Vector3::zeros(),
        };
        let current = take((0..3).map(state).collect(), 1e-4);
        // The model-free run sat elsewhere (a mirror branch, say).
        let other = |k: usize| State {
            orientation: nalgebra::UnitQuaternion::from_euler_angles(1.0, 0.4, -0.3 * k as f64),
            velocity: Vector3::new(-1.0, 0.0, -1.5),
            ..state(k)
        };
        let first = take((0..3).map(other).collect(), 3e-3);
        let got = with_markers_only_covariances(
            std::slice::from_ref(&current),
            std::slice::from_ref(&first),
        );
        let got = got.first().expect("one take");
        assert_eq!(got.states, current.states);
        assert_eq!(got.velocity_difference_cov, first.velocity_difference_cov);
        assert_eq!(got.attitude_velocity_cov, first.attitude_velocity_cov);
        for k in 0..3 {
            // The body velocity's covariance is about the current state,
            // not the first run's.
            let expected = crate::reconstruct::filter::body_velocity_cov(
                &current.states[k],
                &first.attitude_velocity_cov[k],
            );
            let own = first.body_velocity_cov(k).expect("first run's");
            assert_eq!(got.body_velocity_cov(k), Some(expected));
            assert!((expected - own).norm() > 1e-6);
        }
        // A take whose epochs differ in number keeps its own covariances.
        let short = take((0..2).map(other).collect(), 3e-3);
        let kept = with_markers_only_covariances(std::slice::from_ref(&current), &[short]);
        assert_eq!(kept.first(), Some(&current));
    }

    #[test]
    fn weights_are_bounded_and_discount_the_uncertain_direction() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Box), 4).expect("model");
        let mut frames = samples(&truth, 4, TakeKind::Drop);
        let refs: Vec<&Sample> = frames.iter().collect();
        assert!(force_weights(&refs)
            .iter()
            .all(|w| *w == Matrix3::identity()));
        for (i, s) in frames.iter_mut().enumerate() {
            s.force_cov = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0 + 9.0 * i as f64));
        }
        let refs: Vec<&Sample> = frames.iter().collect();
        for w in force_weights(&refs) {
            let e = w.symmetric_eigen().eigenvalues;
            assert!(e.max() <= 1.0 + 1e-12 && e.min() > 0.0, "{e}");
            assert!(w[(2, 2)] <= w[(0, 0)] + 1e-12);
        }
    }
}
