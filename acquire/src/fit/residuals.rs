//! Per-frame residuals of a model against reconstructed frames: the public
//! API for residual analysis, and the per-iteration summary of §6.

use crate::reconstruct::forces::Sample;
use nalgebra::Vector3;
use omniad_core::Coefficients;

/// One frame's misfit, body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameResidual {
    /// Take index.
    pub take: usize,
    /// Epoch index in the take.
    pub index: usize,
    /// Time, s.
    pub t: f64,
    /// Unit direction E of V (zero when V = 0).
    pub direction: Vector3<f64>,
    /// |V|, m/s.
    pub speed: f64,
    /// |Ω|, rad/s.
    pub spin: f64,
    /// `F* - F_model`, N.
    pub force: Vector3<f64>,
    /// `T* - T_model`, N m.
    pub torque: Vector3<f64>,
    /// `½ρ|V|²L²`, N: the force scale of eq. (5).
    pub force_scale: f64,
    /// `½ρ|V|²L³`, N m: the torque scale of eq. (6).
    pub torque_scale: f64,
    /// The sample was used by the force fit / torque fit.
    pub used: (bool, bool),
}

/// Residuals of `model` on every sample.
pub fn frame_residuals(
    model: &Coefficients<f64>,
    samples: &[Sample],
    air_density: f64,
) -> Vec<FrameResidual> {
    let l = model.reference_length();
    samples
        .iter()
        .map(|s| {
            let mut w = model.wrench(&s.velocity, &s.angular_velocity, air_density);
            if let Some(g) = model.gravity_coupling() {
                w.force += g.force(&s.gravity_body, air_density, l);
            }
            let speed = s.velocity.norm();
            let q = 0.5 * air_density * speed * speed;
            FrameResidual {
                take: s.take,
                index: s.index,
                t: s.t,
                direction: if speed > 0.0 {
                    s.velocity / speed
                } else {
                    Vector3::zeros()
                },
                speed,
                spin: s.angular_velocity.norm(),
                force: s.force - w.force,
                torque: s.torque - w.torque,
                force_scale: q * l * l,
                torque_scale: q * l * l * l,
                used: (s.use_force, s.use_torque),
            }
        })
        .collect()
}

/// Non-dimensional RMS residuals over used frames:
/// `(sqrt(Σ|ΔF|² / Σ(½ρ|V|²L²)²), sqrt(Σ|ΔT|² / Σ(½ρ|V|²L³)²))`.
pub fn summary(residuals: &[FrameResidual]) -> (f64, f64) {
    let ratio = |num: f64, den: f64| if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    let (mut fnum, mut fden, mut tnum, mut tden) = (0.0, 0.0, 0.0, 0.0);
    for r in residuals {
        if r.used.0 {
            fnum += r.force.norm_squared();
            fden += r.force_scale * r.force_scale;
        }
        if r.used.1 {
            tnum += r.torque.norm_squared();
            tden += r.torque_scale * r.torque_scale;
        }
    }
    (ratio(fnum, fden), ratio(tnum, tden))
}

/// RMS of the force (N) and torque (N m) residual vectors over used frames.
pub fn rms_dimensional(residuals: &[FrameResidual]) -> (f64, f64) {
    let rms = |it: Vec<f64>| {
        if it.is_empty() {
            0.0
        } else {
            (it.iter().sum::<f64>() / it.len() as f64).sqrt()
        }
    };
    (
        rms(residuals
            .iter()
            .filter(|r| r.used.0)
            .map(|r| r.force.norm_squared())
            .collect()),
        rms(residuals
            .iter()
            .filter(|r| r.used.1)
            .map(|r| r.torque.norm_squared())
            .collect()),
    )
}
