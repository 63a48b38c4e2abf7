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
pub const ALL: [Candidate; 9] = [
    Candidate::Named(EffectKind::AddedMass),
    Candidate::Named(EffectKind::AddedMassCoupling),
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
        matches!(
            self,
            Self::Named(EffectKind::AddedMass | EffectKind::AddedMassCoupling) | Self::Wind
        )
    }

    /// Whether `self` and `other` are one term and never enter a design
    /// together: added mass and its coupling share M_a (the coupling is
    /// added mass without the acceleration reaction), and a rotational
    /// lift is the coupling's isotropic part (`ρL³c (Ω × V)` is the
    /// coupling of `M_a = -ρL³c I`), so its column lies in the coupling's.
    pub fn excludes(self, other: Candidate) -> bool {
        use EffectKind::{AddedMass, AddedMassCoupling, RotationalLift};
        let pair = |a: EffectKind, b: EffectKind| {
            (self == Self::Named(a) && other == Self::Named(b))
                || (self == Self::Named(b) && other == Self::Named(a))
        };
        pair(AddedMass, AddedMassCoupling) || pair(AddedMassCoupling, RotationalLift)
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

/// How far below zero a fitted M_a's smallest eigenvalue may dip, as a
/// fraction of its largest, before it is not positive semi-definite (a
/// noisy small direction, such as a plate's edgewise added mass).
pub const PSD_DIP: f64 = 0.25;

/// Smallest and largest eigenvalue of the symmetric tensor of six
/// parameters `[xx, yy, zz, xy, xz, yz]`.
fn eigen_range(p: &[f64]) -> (f64, f64) {
    let six: [f64; 6] = std::array::from_fn(|i| p.get(i).copied().unwrap_or(0.0));
    let e = omniad_core::math::symmetric_from_six(six).symmetric_eigenvalues();
    (e.min(), e.max())
}

/// A fitted added-mass coupling tensor `A` (force `-Ω × (A V)`) read as
/// the least added mass and rotational lift that make it. Its isotropic
/// part is not the data's to split (`-Ω × (m V)` is the rotational lift of
/// `c = -m/(ρL³)`, see [`EffectKind::AddedMassCoupling`]), so the rule is
/// parsimony: a smallest eigenvalue within [`PSD_DIP`] of the largest is
/// noise and `A` is the added mass; below that, `A = M_a - ρL³ c I` with
/// the least lift `c = -λ_min(A)/(ρL³)` that leaves `M_a` positive
/// semi-definite. On MuJoCo's plate (its ellipsoid's in-plane added
/// masses are 0.1 and 0.05 g) the least lift is its Magnus force's
/// `C_M ρ Vol`, since the true M_a has a near-zero eigenvalue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplingSplit {
    /// M_a, kg, `[xx, yy, zz, xy, xz, yz]`.
    pub added_mass: [f64; 6],
    /// Rotational lift c (dimensionless, >= 0; 0 when `A` is the added
    /// mass).
    pub lift: f64,
}

impl CouplingSplit {
    /// The split of `A` (six parameters) for an object of reference
    /// length `l` (m) in air of density `rho` (kg/m³).
    pub fn of(a: &[f64], rho: f64, l: f64) -> Self {
        let added_mass: [f64; 6] = std::array::from_fn(|i| a.get(i).copied().unwrap_or(0.0));
        let (lo, hi) = eigen_range(&added_mass);
        let scale = rho * l.powi(3);
        if lo >= -PSD_DIP * hi.max(0.0) || !scale.is_finite() || scale <= 0.0 {
            return Self {
                added_mass,
                lift: 0.0,
            };
        }
        let mut m = added_mass;
        for d in m.iter_mut().take(3) {
            *d -= lo;
        }
        Self {
            added_mass: m,
            lift: -lo / scale,
        }
    }
}

/// Physical plausibility of fitted parameters `p` of `candidate` for an
/// object of reference length L (m) in air of density ρ, or why not: a
/// value no such air can have is a misattribution of something else, not
/// physics to report. Bounds (L bounds the body: it fits in a box of
/// diagonal L, whose volume is at most `L³/√27`):
/// * buoyancy: `0 <= V_b <= L³/√27`;
/// * added mass: positive semi-definite (smallest eigenvalue at least
///   -[`PSD_DIP`] of the largest: a noisy small direction may dip) and
///   largest eigenvalue at most `ρ L³` (a disk of diameter L has `ρL³/3`);
/// * added-mass coupling: read as [`CouplingSplit`], its M_a within the
///   same bound and its rotational lift within rotational lift's;
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
            let (lo, hi) = eigen_range(p);
            if hi <= 0.0 || lo < -PSD_DIP * hi {
                return Err(format!(
                    "M_a eigenvalues [{lo:.3e}, {hi:.3e}] kg: not positive semi-definite"
                ));
            }
            if hi > rho * l.powi(3) {
                return Err(format!("largest M_a {hi:.3e} kg above ρL³"));
            }
        }
        Candidate::Named(EffectKind::AddedMassCoupling) => {
            let split = CouplingSplit::of(p, rho, l);
            let (_, hi) = eigen_range(&split.added_mass);
            if hi > rho * l.powi(3) {
                return Err(format!("largest M_a {hi:.3e} kg above ρL³"));
            }
            if split.lift > 2.0 {
                return Err(format!("its rotational lift c = {:.3} above 2", split.lift));
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

#[cfg(test)]
mod tests {
    use super::*;
    use omniad_core::effect::EffectInputs;

    /// MuJoCo's plate with its Magnus coefficient at 5: the coupling of its
    /// ellipsoid's added mass (0.11, 0.05, 21.85 g) less the Magnus force's
    /// `C_M ρ Vol` (5 x 1.88 g) in every direction. The split gives back
    /// the lift (to the smallest added mass, 0.05 g) and an M_a with one
    /// zero eigenvalue, and the two effects together are the fitted force;
    /// a tensor within the PSD dip (default C_M = 1: -1.8 g against 20 g)
    /// is left whole.
    #[test]
    fn a_coupling_splits_into_the_least_lift_and_a_psd_added_mass() {
        let (rho, l) = (1.2, 0.583);
        let magnus = 5.0 * 0.00188;
        let a = [
            0.00011 - magnus,
            0.00005 - magnus,
            0.02185 - magnus,
            0.0,
            0.0,
            0.0,
        ];
        let split = CouplingSplit::of(&a, rho, l);
        let c_true = magnus / (rho * l * l * l);
        assert!((split.lift - (magnus - 0.00005) / (rho * l * l * l)).abs() < 1e-12);
        assert!((split.lift / c_true - 1.0).abs() < 0.05, "{split:?}");
        let (lo, _) = eigen_range(&split.added_mass);
        assert!(lo.abs() < 1e-12, "{split:?}");
        let x = EffectInputs {
            velocity: Vector3::new(0.3, -1.2, -2.0),
            angular_velocity: Vector3::new(4.0, -2.0, 0.5),
            gravity: Vector3::zeros(),
            velocity_rate: Vector3::new(1.0, 2.0, 3.0),
            air_density: rho,
            reference_length: l,
        };
        let wrench = |k: EffectKind, p: &[f64]| Effect::new(k, p).map(|e| e.wrench(&x).force);
        let whole = wrench(EffectKind::AddedMassCoupling, &a).expect("A");
        let parts = wrench(EffectKind::AddedMassCoupling, &split.added_mass).expect("M_a")
            + wrench(EffectKind::RotationalLift, &[split.lift]).expect("c");
        assert!(
            (whole - parts).norm() < 1e-12 * whole.norm(),
            "{whole} vs {parts}"
        );
        assert!(plausible(Candidate::Named(EffectKind::AddedMassCoupling), &a, rho, l).is_ok());
        let noisy = [
            0.00011 - 0.00188,
            0.00005 - 0.00188,
            0.02185 - 0.00188,
            0.0,
            0.0,
            0.0,
        ];
        let kept = CouplingSplit::of(&noisy, rho, l);
        assert_eq!((kept.added_mass, kept.lift), (noisy, 0.0));
    }

    #[test]
    fn one_term_never_shares_a_design() {
        use EffectKind::{AddedMass, AddedMassCoupling, Buoyancy, RotationalLift};
        let n = Candidate::Named;
        assert!(n(AddedMass).excludes(n(AddedMassCoupling)));
        assert!(n(RotationalLift).excludes(n(AddedMassCoupling)));
        assert!(!n(AddedMass).excludes(n(RotationalLift)));
        assert!(!n(Buoyancy).excludes(n(AddedMassCoupling)));
        assert!(!n(AddedMass).excludes(n(AddedMass)));
    }
}
