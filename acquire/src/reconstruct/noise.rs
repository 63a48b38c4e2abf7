//! The process noise of the filter (§5) and its schedule over the
//! refinement: the unexplained wrench a random walk with no model, a
//! Gauss-Markov process once a model is fitted.

use crate::input::recording::RecordingSet;

/// Process noise of the filter (1 sigma per axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProcessNoise {
    /// White acceleration per step, m/s².
    pub accel: f64,
    /// White angular acceleration per step, rad/s².
    pub angular_accel: f64,
    /// Random walk of the unexplained force, N/√s.
    pub force_walk: f64,
    /// Random walk of the unexplained torque, N m/√s.
    pub torque_walk: f64,
    /// Correlation time of the unexplained wrench, s (`f64::INFINITY`: a
    /// random walk; see `Process::bias_time`).
    pub bias_time: f64,
    /// Turn of the air's direction over which the unexplained torque
    /// decorrelates, rad (`f64::INFINITY`: its correlation time is
    /// `bias_time`; see `Process::torque_bias_time`).
    pub torque_turn: f64,
}

impl ProcessNoise {
    /// The same unexplained wrench with correlation time `bias_time` (s)
    /// and the same stationary RMS `walk·sqrt(τ_b/2)`: the walks scale by
    /// `sqrt(τ_b/bias_time)`. Both times must be finite and positive.
    pub fn with_bias_time(self, bias_time: f64) -> Self {
        let k = (self.bias_time / bias_time).sqrt();
        Self {
            force_walk: self.force_walk * k,
            torque_walk: self.torque_walk * k,
            bias_time,
            ..self
        }
    }
}

impl ProcessNoise {
    /// The noise of an air wrench `k` times larger: every sigma and walk
    /// times `k` (a take whose air carries a strong undeclared effect, see
    /// `reconstruct::first`); the correlation time is kept.
    pub fn scaled(self, k: f64) -> Self {
        Self {
            accel: self.accel * k,
            angular_accel: self.angular_accel * k,
            force_walk: self.force_walk * k,
            torque_walk: self.torque_walk * k,
            ..self
        }
    }
}

/// Scales of the object: a gravity-sized force `M|g|`, the torque of that
/// force at `L/2`, and the time `τ = sqrt(L/|g|)` to fall through one
/// reference length from rest (the time scale of the air's wrench changing).
pub(crate) fn scales(set: &RecordingSet) -> (f64, f64, f64) {
    let g = set.world.gravity.norm().max(1.0);
    let l = set.object.reference_length;
    let force = set.object.mass * g;
    (force, 0.5 * force * l, (l / g).sqrt())
}

/// Correlation time of the unexplained wrench once a model is fitted, in
/// units of the object's time scale `τ` (see `next_noise`): 2 keeps the
/// driving walk `RMS/sqrt(τ)` of a random walk, so only the decay is new.
pub const BIAS_TIME_SCALES: f64 = 2.0;

/// Process noise with no aerodynamic model: the unexplained wrench may
/// change by its full scale over `τ` (a random walk: the air's wrench has a
/// non-zero mean the filter must find); white noise of 10 % of the scales.
pub fn initial_noise(set: &RecordingSet) -> ProcessNoise {
    let (force, torque, tau) = scales(set);
    let i_max = set.object.inertia.symmetric_eigen().eigenvalues.max();
    ProcessNoise {
        accel: 0.1 * force / set.object.mass,
        angular_accel: 0.1 * torque / i_max,
        force_walk: force / tau.sqrt(),
        torque_walk: torque / tau.sqrt(),
        bias_time: f64::INFINITY,
        torque_turn: f64::INFINITY,
    }
}

/// The next iteration's process noise: with a fitted model the unexplained
/// wrench is the fit's residual, a zero-mean first-order Gauss-Markov
/// process (not a random walk) with correlation time [`BIAS_TIME_SCALES`]`·τ`
/// and stationary RMS the fit's RMS residual wrench; its driving walk
/// (`RMS·sqrt(2/τ_b)` = `RMS/sqrt(τ)`) is clamped between `floor` and 1
/// times the no-model walks. A random walk lets a slowly drifting depth
/// error (the poorly observed direction of §5's marker updates) pass as
/// unexplained force; the decay bounds that drift. The white noise is kept.
/// `torque_turn` (rad, `f64::INFINITY`: off) makes the unexplained torque's
/// correlation time shrink with the spin (`Process::torque_bias_time`).
pub(crate) fn next_noise(
    set: &RecordingSet,
    first: ProcessNoise,
    rms: (f64, f64),
    (floor, torque_turn): (f64, f64),
) -> ProcessNoise {
    let (_, _, tau) = scales(set);
    let bias_time = BIAS_TIME_SCALES * tau;
    let k = (2.0 / bias_time).sqrt();
    ProcessNoise {
        force_walk: (rms.0 * k).clamp(floor * first.force_walk, first.force_walk),
        torque_walk: (rms.1 * k).clamp(floor * first.torque_walk, first.torque_walk),
        bias_time,
        torque_turn,
        ..first
    }
}
