//! The model extensions' terms (effects beyond eqs. 5-6) and their
//! regressors.

use crate::fit::context::FitContext;
use crate::reconstruct::forces::Sample;
use nalgebra::DVector;

/// A set of extension terms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Terms {
    /// The spin coupling (9 regressors per force component).
    pub spin: bool,
    /// The gravity coupling (3 regressors per force component).
    pub gravity: bool,
}

impl Terms {
    /// Regressors per force component.
    pub fn width(self) -> usize {
        9 * usize::from(self.spin) + 3 * usize::from(self.gravity)
    }

    /// Indices of these terms' regressors among those of both terms.
    pub(crate) fn rows(self) -> Vec<usize> {
        let spin = (0..9).filter(|_| self.spin);
        let gravity = (9..12).filter(|_| self.gravity);
        spin.chain(gravity).collect()
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

/// The regressors of one frame for `terms`: `½ρL³ (Ω ⊗ V)` (in the layout
/// of `SpinCoupling::k` rows), then `ρL³ Rᵀg`. Component c of the force is
/// `Σ_f u_{c,f} x_f` for the unknowns `u_c` of that component.
pub(crate) fn regressor(s: &Sample, ctx: &FitContext, terms: Terms) -> DVector<f64> {
    let l3 = ctx.reference_length.powi(3);
    let mut x = Vec::with_capacity(terms.width());
    if terms.spin {
        let scale = 0.5 * ctx.air_density * l3;
        let (w, v) = (s.angular_velocity, s.velocity);
        x.extend((0..9).map(|r| w[r / 3] * v[r % 3] * scale));
    }
    if terms.gravity {
        x.extend(s.gravity_body.iter().map(|g| g * ctx.air_density * l3));
    }
    DVector::from_vec(x)
}
