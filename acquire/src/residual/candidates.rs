//! The candidates of the residual analysis: each named effect of the
//! core's library ([`omniad_core::effect`], columns = the effect at unit
//! parameters), a steady `wind` of the recording, and last the two
//! generic blocks (spin and gravity coupling: structure no named effect
//! explains). Every candidate is linear in its parameters, so one frame's
//! contribution is a force matrix and a torque matrix (body frame, 3 x
//! width) times the parameters.

use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, UnitQuaternion, Vector3};
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::Coefficients;

/// A candidate effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Candidate {
    /// A named effect of the core's library.
    Named(EffectKind),
    /// A steady wind `w` (world frame, m/s) the recording's air moved
    /// with, linearised about no wind: the base model's wrench change for
    /// a unit wind along world axis i is `-∂(F, T)/∂V · Rᵀ e_i` (central
    /// differences of the model).
    Wind,
    /// The generic spin coupling `½ρL³ K:(Ω ⊗ V)`, 27 numbers.
    SpinCoupling,
    /// The generic gravity coupling `ρL³ G Rᵀg`, 9 numbers.
    GravityCoupling,
}

/// Every candidate, named effects first, the generic blocks last.
pub const ALL: [Candidate; 8] = [
    Candidate::Named(EffectKind::AddedMass),
    Candidate::Named(EffectKind::RotationalLift),
    Candidate::Named(EffectKind::PropellerThrust),
    Candidate::Named(EffectKind::Buoyancy),
    Candidate::Wind,
    Candidate::Named(EffectKind::LinearDrag),
    Candidate::SpinCoupling,
    Candidate::GravityCoupling,
];

impl Candidate {
    /// The name in reports and JSON (the library's names, `wind`,
    /// `spin_coupling`, `gravity_coupling`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Named(k) => k.name(),
            Self::Wind => "wind",
            Self::SpinCoupling => "spin_coupling",
            Self::GravityCoupling => "gravity_coupling",
        }
    }

    /// Parameters.
    pub fn width(self) -> usize {
        match self {
            Self::Named(k) => k.param_count(),
            Self::Wind => 3,
            Self::SpinCoupling => 27,
            Self::GravityCoupling => 9,
        }
    }

    /// A generic block (loses to a named effect that fits as well).
    pub fn generic(self) -> bool {
        matches!(self, Self::SpinCoupling | Self::GravityCoupling)
    }

    /// Whether it acts on the torque (its torque columns are not zero).
    pub fn has_torque(self) -> bool {
        matches!(self, Self::Named(EffectKind::AddedMass) | Self::Wind)
    }
}

/// What the columns of a frame need besides the frame.
pub(crate) struct ColumnContext<'a> {
    /// ρ, kg/m³.
    pub air_density: f64,
    /// L, m.
    pub reference_length: f64,
    /// The base model (for the wind's linearisation).
    pub model: &'a Coefficients<f64>,
}

/// The force and torque columns (body frame, 3 x width each) of
/// `candidate` at frame `s` with attitude `q` (body -> world).
pub(crate) fn columns(
    candidate: Candidate,
    s: &Sample,
    q: &UnitQuaternion<f64>,
    ctx: &ColumnContext<'_>,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let w = candidate.width();
    let (mut f, mut t) = (DMatrix::zeros(3, w), DMatrix::zeros(3, w));
    let (rho, l) = (ctx.air_density, ctx.reference_length);
    match candidate {
        Candidate::Named(kind) => {
            let x = s.effect_inputs(rho, l);
            for j in 0..w {
                let e = Effect::<f64>::unit(kind, j).wrench(&x);
                f.set_column(j, &e.force);
                t.set_column(j, &e.torque);
            }
        }
        Candidate::Wind => {
            for i in 0..3 {
                let d = q.inverse_transform_vector(&Vector3::ith(i, 1.0));
                let h = 1e-3 * s.velocity.norm().max(1.0);
                let at = |v: Vector3<f64>| ctx.model.wrench(&v, &s.angular_velocity, rho);
                let (p, m) = (at(s.velocity + d * h), at(s.velocity - d * h));
                f.set_column(i, &(-(p.force - m.force) / (2.0 * h)));
                t.set_column(i, &(-(p.torque - m.torque) / (2.0 * h)));
            }
        }
        Candidate::SpinCoupling => {
            // Unknown i*9 + j*3 + k: K_ijk, force component i.
            let scale = 0.5 * rho * l.powi(3);
            for c in 0..27 {
                let (i, j, k) = (c / 9, (c / 3) % 3, c % 3);
                f[(i, c)] = scale * s.angular_velocity[j] * s.velocity[k];
            }
        }
        Candidate::GravityCoupling => {
            // Unknown i*3 + j: G_ij.
            for c in 0..9 {
                let (i, j) = (c / 3, c % 3);
                f[(i, c)] = rho * l.powi(3) * s.gravity_body[j];
            }
        }
    }
    (f, t)
}

/// Physical plausibility of fitted parameters `p` of `candidate` for an
/// object of reference length L (m) in air of density ρ, or why not: a
/// value no such air can have is a misattribution of something else, not
/// physics to report. Bounds (L bounds the body: it fits in a box of
/// diagonal L, whose volume is at most `L³/√27`):
/// * buoyancy: `0 <= V_b <= L³/√27`;
/// * added mass: positive semi-definite (smallest eigenvalue at least
///   -25 % of the largest: a noisy small direction may dip) and largest
///   eigenvalue at most `ρ L³` (a disk of diameter L has `ρL³/3`);
/// * linear drag: `k >= 0`;
/// * rotational lift: `|c| <= 2` (a spinning sphere's lift coefficient
///   stays below 1);
/// * propeller thrust: `|K| <= 10`;
/// * wind: `|w| <= 10 m/s` (a throw indoors or a calm day outside).
pub fn plausible(candidate: Candidate, p: &[f64], rho: f64, l: f64) -> Result<(), String> {
    if p.iter().any(|v| !v.is_finite()) {
        return Err("non-finite parameters".into());
    }
    let first = p.first().copied().unwrap_or(0.0);
    match candidate {
        Candidate::Named(EffectKind::Buoyancy) => {
            let max = l.powi(3) / 27f64.sqrt();
            if !(0.0..=max).contains(&first) {
                return Err(format!("V_b = {first:.3e} m³ outside [0, {max:.3e}]"));
            }
        }
        Candidate::Named(EffectKind::AddedMass) => {
            let six: [f64; 6] = std::array::from_fn(|i| p.get(i).copied().unwrap_or(0.0));
            let m = omniad_core::math::symmetric_from_six(six);
            let e = m.symmetric_eigenvalues();
            let (lo, hi) = (e.min(), e.max());
            if hi <= 0.0 || lo < -0.25 * hi {
                return Err(format!(
                    "M_a eigenvalues [{lo:.3e}, {hi:.3e}] kg: not positive semi-definite"
                ));
            }
            if hi > rho * l.powi(3) {
                return Err(format!("largest M_a {hi:.3e} kg above ρL³"));
            }
        }
        Candidate::Named(EffectKind::LinearDrag) if first < 0.0 => {
            return Err(format!("k = {first:.3e} < 0 (drag that pushes)"));
        }
        Candidate::Named(EffectKind::RotationalLift) if first.abs() > 2.0 => {
            return Err(format!("|c| = {:.3} above 2", first.abs()));
        }
        Candidate::Named(EffectKind::PropellerThrust) => {
            let n = p.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 10.0 {
                return Err(format!("|K| = {n:.3} above 10"));
            }
        }
        Candidate::Wind => {
            let n = p.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 10.0 {
                return Err(format!("|w| = {n:.2} m/s above 10"));
            }
        }
        _ => {}
    }
    Ok(())
}
