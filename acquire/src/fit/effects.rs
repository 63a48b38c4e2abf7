//! The model extensions' terms: effects beyond eqs. (5)-(6), each known
//! only by its regressors. Adding an effect = implementing `Effect`
//! and registering it in `EFFECTS` (and a switch in [`Terms`]); the
//! held-out test and the joint fit with alpha
//! ([`crate::fit::extensions`]) take their rows from here.

use crate::fit::context::FitContext;
use crate::reconstruct::forces::Sample;
use nalgebra::DVector;

/// One force effect linear in its unknowns: component c of its force
/// (body frame, N) is `Σ_f u_{c,f} x_f` over its regressors `x`.
pub(crate) trait Effect: Sync {
    /// Regressors per force component.
    fn width(&self) -> usize;
    /// Appends one frame's regressors `x` to `out`.
    fn regressors(&self, s: &Sample, ctx: &FitContext, out: &mut Vec<f64>);
}

/// The spin coupling (`omniad_core::spin_coupling`):
/// `F_i = ½ρL³ Σ_jk K_ijk Ω_j V_k` (Magnus force, added-mass coupling);
/// regressors `½ρL³ (Ω ⊗ V)` in the layout of `SpinCoupling::k` rows.
pub(crate) struct SpinEffect;

impl Effect for SpinEffect {
    fn width(&self) -> usize {
        9
    }

    fn regressors(&self, s: &Sample, ctx: &FitContext, out: &mut Vec<f64>) {
        let scale = 0.5 * ctx.air_density * ctx.reference_length.powi(3);
        let (w, v) = (s.angular_velocity, s.velocity);
        out.extend((0..9).map(|r| w[r / 3] * v[r % 3] * scale));
    }
}

/// The gravity coupling (`omniad_core::gravity_coupling`):
/// `F = ρL³ G Rᵀg` (buoyancy, added mass); regressors `ρL³ Rᵀg`.
pub(crate) struct GravityEffect;

impl Effect for GravityEffect {
    fn width(&self) -> usize {
        3
    }

    fn regressors(&self, s: &Sample, ctx: &FitContext, out: &mut Vec<f64>) {
        let l3 = ctx.reference_length.powi(3);
        out.extend(s.gravity_body.iter().map(|g| g * ctx.air_density * l3));
    }
}

/// Every registered effect, in regressor order (spin, gravity).
pub(crate) const EFFECTS: [&dyn Effect; 2] = [&SpinEffect, &GravityEffect];

/// A set of extension terms (one switch per entry of `EFFECTS`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Terms {
    /// The spin coupling (9 regressors per force component).
    pub spin: bool,
    /// The gravity coupling (3 regressors per force component).
    pub gravity: bool,
}

impl Terms {
    /// Whether each entry of [`EFFECTS`] is in the set.
    fn switches(self) -> [bool; 2] {
        [self.spin, self.gravity]
    }

    /// The effects in the set, in regressor order.
    pub(crate) fn effects(self) -> impl Iterator<Item = &'static dyn Effect> {
        EFFECTS
            .into_iter()
            .zip(self.switches())
            .filter_map(|(e, on)| on.then_some(e))
    }

    /// Regressors per force component.
    pub fn width(self) -> usize {
        self.effects().map(|e| e.width()).sum()
    }

    /// Indices of these terms' regressors among those of all effects.
    pub(crate) fn rows(self) -> Vec<usize> {
        let mut start = 0;
        let mut rows = Vec::new();
        for (e, on) in EFFECTS.into_iter().zip(self.switches()) {
            if on {
                rows.extend(start..start + e.width());
            }
            start += e.width();
        }
        rows
    }

    /// The candidates tried, singles first.
    pub(crate) const CANDIDATES: [Terms; 3] = [
        Terms {
            spin: true,
            gravity: false,
        },
        Terms {
            spin: false,
            gravity: true,
        },
        Terms {
            spin: true,
            gravity: true,
        },
    ];
}

/// The regressors of one frame for `terms`, effect after effect. Component
/// c of the force is `Σ_f u_{c,f} x_f` for the unknowns `u_c` of that
/// component.
pub(crate) fn regressor(s: &Sample, ctx: &FitContext, terms: Terms) -> DVector<f64> {
    let mut x = Vec::with_capacity(terms.width());
    for e in terms.effects() {
        e.regressors(s, ctx, &mut x);
    }
    DVector::from_vec(x)
}
