//! Aerodynamic force reconstruction (§5): eqs. (9)-(10) by central
//! differences of the smoothed states, and the stability enforcement.

use crate::input::recording::{Object, TakeKind};
use crate::reconstruct::filter::Smoothed;
use nalgebra::{Matrix3, Vector3};
use omniad_core::effect::EffectInputs;

/// One reconstructed frame: velocities and the air's force and torque.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Take index in the set.
    pub take: usize,
    /// Epoch index in the take.
    pub index: usize,
    /// Time, s.
    pub t: f64,
    /// The take's kind (K1 drops, K2 spins).
    pub kind: TakeKind,
    /// Velocity relative to the air, body frame, m/s (`V* = Rᵀ(v* - w)`,
    /// `w` the recording's wind, zero unless the residual analysis found one).
    pub velocity: Vector3<f64>,
    /// Angular velocity Ω*, body frame, rad/s.
    pub angular_velocity: Vector3<f64>,
    /// `dV*/dt`, the rate of change of the body-frame components of V*
    /// (central difference of `R_kᵀ v_k`), m/s²: what added mass acts on
    /// ([`omniad_core::effect::EffectInputs::velocity_rate`]).
    pub velocity_rate: Vector3<f64>,
    /// Aerodynamic force F*, body frame, N (eq. 9).
    pub force: Vector3<f64>,
    /// Aerodynamic torque T*, body frame, N m (eq. 10).
    pub torque: Vector3<f64>,
    /// Gravity in the body frame, `Rᵀg`, m/s² (for the gravity-coupling
    /// extension).
    pub gravity_body: Vector3<f64>,
    /// Posterior covariance of `force` from the smoother, body frame, N²
    /// (zero: unknown; see [`Smoothed::velocity_difference_cov`]). The
    /// refinement gives its fits the model-free first reconstruction's
    /// (`pipeline::fit`: frames are weighed by what the markers alone say).
    pub force_cov: Matrix3<f64>,
    /// Passes `F·V <= 0` (no thrust): used by every fit.
    pub use_force: bool,
    /// Passes `T·Ω <= 0` as well: used by the refinement's torque and damping
    /// fits (the final torque fit takes every `use_force` frame, see
    /// `fit::torque::TorqueFrames`).
    pub use_torque: bool,
}

impl Sample {
    /// What the named effects act on at this frame (body frame; air of
    /// density `air_density`, kg/m³, object of reference length
    /// `reference_length`, m).
    pub fn effect_inputs(&self, air_density: f64, reference_length: f64) -> EffectInputs<f64> {
        EffectInputs {
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
            gravity: self.gravity_body,
            velocity_rate: self.velocity_rate,
            air_density,
            reference_length,
        }
    }
}

/// Counts of the stability enforcement (§5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ForceStats {
    /// Frames with a reconstructed force (all but each take's first and last).
    pub frames: usize,
    /// Dropped entirely: `F*·V* > 0` (the air would add energy).
    pub dropped_thrust: usize,
    /// Dropped from the refinement's torque/damping fits only: `T*·Ω* > 0`.
    pub dropped_spin_up: usize,
    /// Dropped: a non-finite number in the reconstruction.
    pub non_finite: usize,
    /// Not reconstructed: the difference quotient would cross a cut
    /// ([`Smoothed::linked`]), two chains the smoother did not link.
    pub across_cut: usize,
}

/// Eqs. (9)-(10) on every interior frame of one smoothed take.
///
/// `F*_k = R_kᵀ { M (v_{k+1} - v_{k-1}) / (t_{k+1} - t_{k-1}) - M g }`,
/// `T*_k = I (Ω_{k+1} - Ω_{k-1}) / (t_{k+1} - t_{k-1}) + Ω_k × I Ω_k`
/// (the difference quotient is eq. 9-10's `/(2Δt)` for uniform frames);
/// `(gravity, wind)` are world-frame m/s² and m/s.
pub fn reconstruct(
    take: usize,
    kind: TakeKind,
    s: &Smoothed,
    object: &Object,
    (gravity, wind): (&Vector3<f64>, &Vector3<f64>),
    stats: &mut ForceStats,
) -> Vec<Sample> {
    let mut out = Vec::with_capacity(s.states.len());
    for k in 1..s.states.len().saturating_sub(1) {
        let (Some(prev), Some(cur), Some(next)) =
            (s.states.get(k - 1), s.states.get(k), s.states.get(k + 1))
        else {
            continue;
        };
        let (Some(&t0), Some(&t), Some(&t1)) =
            (s.times.get(k - 1), s.times.get(k), s.times.get(k + 1))
        else {
            continue;
        };
        let h = t1 - t0;
        if h.is_nan() || h <= 0.0 {
            continue;
        }
        // Across a cut the difference mixes two chains: an epoch cut off on
        // both sides keeps the filter's prior velocity (at rest: tens of
        // m/s² of bogus acceleration), and a later iteration weighs the frame
        // by the first reconstruction's covariance, which knew no cut.
        if !s.linked(k - 1, k + 1) {
            stats.across_cut += 1;
            continue;
        }
        let accel = (next.velocity - prev.velocity) / h;
        let force = cur
            .orientation
            .inverse_transform_vector(&((accel - gravity) * object.mass));
        let omega = cur.angular_velocity;
        let torque = object.inertia * (next.angular_velocity - prev.angular_velocity) / h
            + omega.cross(&(object.inertia * omega));
        let velocity = cur.air_velocity_body(wind);
        let velocity_rate = (next.air_velocity_body(wind) - prev.air_velocity_body(wind)) / h;
        // Eq. (9) is linear in v_{k+1} - v_{k-1}: Σ_F = (M/h)² Rᵀ Σ_Δv R
        // (the orientation's own uncertainty is neglected).
        let rot = cur.orientation.to_rotation_matrix();
        let force_cov = s
            .velocity_difference_cov
            .get(k)
            .map_or_else(Matrix3::zeros, |c| {
                rot.matrix().transpose() * c * rot.matrix() * (object.mass / h).powi(2)
            });
        let all = [force, torque, velocity, omega, velocity_rate];
        if all.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
            stats.non_finite += 1;
            continue;
        }
        let use_force = force.dot(&velocity) <= 0.0;
        let use_torque = use_force && torque.dot(&omega) <= 0.0;
        stats.frames += 1;
        if !use_force {
            stats.dropped_thrust += 1;
        } else if !use_torque {
            stats.dropped_spin_up += 1;
        }
        out.push(Sample {
            take,
            index: k,
            t,
            kind,
            velocity,
            angular_velocity: omega,
            velocity_rate,
            force,
            torque,
            gravity_body: cur.orientation.inverse_transform_vector(gravity),
            force_cov,
            use_force,
            use_torque,
        });
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use omniad_core::State;

    /// `epochs` of a free fall in vacuum from 3 m/s down at 60 Hz: eq.
    /// (9)'s force is zero on every frame, except where a stencil takes a
    /// velocity the smoother did not link to its neighbours. With
    /// `cut_at`, epoch 0 alone before the cut keeps the filter's prior (at
    /// rest), as MuJoCo's plate's `spin-09` was reconstructed (stop 26).
    pub(crate) fn fall(epochs: usize, cut_at: Option<usize>) -> Smoothed {
        let g = Vector3::new(0.0, 0.0, -9.81);
        let v0 = Vector3::new(0.0, 0.0, -3.0);
        let times: Vec<f64> = (0..epochs).map(|k| k as f64 / 60.0).collect();
        let mut states: Vec<State<f64>> = times
            .iter()
            .map(|&t| {
                let mut s = State::at_rest(v0 * t + g * (0.5 * t * t));
                s.velocity = v0 + g * t;
                s
            })
            .collect();
        let mut cuts = vec![false; times.len()];
        if let Some(k) = cut_at {
            if let (Some(first), Some(c)) = (states.first_mut(), cuts.get_mut(k)) {
                first.velocity = Vector3::zeros();
                *c = true;
            }
        }
        Smoothed {
            times,
            states,
            cuts,
            ..Smoothed::default()
        }
    }

    fn frames(s: &Smoothed) -> (Vec<Sample>, ForceStats) {
        let object = Object {
            name: "plate".into(),
            mass: 0.05,
            inertia: Matrix3::identity() * 1e-4,
            reference_length: 0.3,
            pole: Vector3::z(),
            markers: Vec::new(),
        };
        let mut stats = ForceStats::default();
        let g = Vector3::new(0.0, 0.0, -9.81);
        let out = reconstruct(
            0,
            TakeKind::Drop,
            s,
            &object,
            (&g, &Vector3::zeros()),
            &mut stats,
        );
        (out, stats)
    }

    #[test]
    fn no_frame_differences_states_across_a_cut() {
        let (linked, stats) = frames(&fall(12, None));
        assert_eq!((linked.len(), stats.across_cut), (10, 0));
        assert!(linked.iter().all(|f| f.force.norm() < 1e-9));
        // The cut after epoch 0: frame 1 would difference the prior's rest
        // against 3.3 m/s, a 5 N force on a 50 g body falling freely.
        let (cut, stats) = frames(&fall(12, Some(1)));
        assert_eq!((cut.len(), stats.across_cut), (9, 1));
        assert!(cut.iter().all(|f| f.index >= 2 && f.force.norm() < 1e-9));
    }
}
