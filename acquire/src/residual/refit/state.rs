//! The effects a refit round holds in the reconstruction's process model
//! (a steady wind and the object's selected named effects), when two
//! rounds agree, and Aitken's extrapolation of the rounds' fixed-point
//! iteration.

use crate::residual::candidates::Candidate;
use nalgebra::{Matrix3, Vector3};
use omniad_core::effect::{Effect, EffectKind};

/// A wind change below `max(WIND_TOLERANCE, 5 % of |w|)` m/s ends the
/// rounds.
pub const WIND_TOLERANCE: f64 = 0.05;

/// A relative change of a named effect's parameters (Euclidean norm over
/// its parameters; M_a's six) below this ends the rounds.
pub const EFFECT_TOLERANCE: f64 = 0.1;

/// Largest contraction ratio [`accelerate`] extrapolates with (a ratio
/// near 1 would send the estimate far on a noisy step).
pub const MAX_RATIO: f64 = 0.75;

/// The effects of a round's process model.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct StateEffects {
    /// Steady wind, world frame, m/s.
    pub wind: Option<Vector3<f64>>,
    /// The object's named effects (one per kind, in selection order; added
    /// mass symmetric PSD, kg, body frame).
    pub effects: Vec<Effect<f64>>,
}

impl StateEffects {
    pub fn is_empty(&self) -> bool {
        self.wind.is_none() && self.effects.is_empty()
    }

    /// The effect of `kind`, if held.
    pub fn effect(&self, kind: EffectKind) -> Option<&Effect<f64>> {
        self.effects.iter().find(|e| e.kind == kind)
    }

    /// Every effect of `self` is also in `o`, itself or as another
    /// reading of the same term ([`Candidate::excludes`]: added mass or
    /// its coupling, a coupling's rotational lift) (named effects only).
    pub fn kinds_within(&self, o: &Self) -> bool {
        let term = |k: EffectKind| Candidate::Named(k);
        self.effects.iter().all(|e| {
            o.effects
                .iter()
                .any(|f| f.kind == e.kind || term(f.kind).excludes(term(e.kind)))
        })
    }

    /// Same effects, each changed by less than its tolerance.
    pub fn close_to(&self, o: &Self) -> bool {
        let wind = match (self.wind, o.wind) {
            (None, None) => true,
            (Some(a), Some(b)) => (a - b).norm() <= WIND_TOLERANCE.max(0.05 * b.norm()),
            _ => false,
        };
        let same_kinds = self.effects.len() == o.effects.len() && self.kinds_within(o);
        let effects = self.effects.iter().all(|a| {
            o.effect(a.kind).is_some_and(|b| {
                let d = norm_of(
                    a.used_params()
                        .iter()
                        .zip(b.used_params())
                        .map(|(x, y)| x - y),
                );
                d <= EFFECT_TOLERANCE * norm_of(b.used_params().iter().copied())
            })
        });
        wind && same_kinds && effects
    }
}

fn norm_of(v: impl Iterator<Item = f64>) -> f64 {
    v.map(|x| x * x).sum::<f64>().sqrt()
}

/// Symmetric tensor of six parameters (xx, yy, zz, xy, xz, yz) projected
/// onto PSD tensors; `None` when nothing positive is left.
pub(crate) fn psd(six: &[f64]) -> Option<Matrix3<f64>> {
    let s: [f64; 6] = std::array::from_fn(|i| six.get(i).copied().unwrap_or(0.0));
    let m = omniad_core::math::nearest_psd(&omniad_core::math::symmetric_from_six(s));
    (m.iter().all(|x| x.is_finite()) && m.trace() > 0.0).then_some(m)
}

/// The added-mass effect of a PSD tensor.
pub(crate) fn added_mass_effect(m: &Matrix3<f64>) -> Option<Effect<f64>> {
    Effect::new(
        EffectKind::AddedMass,
        &omniad_core::math::six_from_symmetric(m),
    )
}

/// A round's change of each state effect (wind, m/s; each named effect's
/// parameters in its units); empty where the effect is not in both.
#[derive(Clone, Debug, Default)]
pub(crate) struct Steps {
    wind: Vec<f64>,
    effects: Vec<(EffectKind, Vec<f64>)>,
}

impl Steps {
    fn effect(&self, kind: EffectKind) -> Option<&Vec<f64>> {
        self.effects.iter().find(|(k, _)| *k == kind).map(|x| &x.1)
    }
}

pub(crate) fn steps(trial: &StateEffects, next: &StateEffects) -> Steps {
    Steps {
        wind: match (trial.wind, next.wind) {
            (Some(a), Some(b)) => (b - a).iter().copied().collect(),
            _ => Vec::new(),
        },
        effects: next
            .effects
            .iter()
            .filter_map(|b| {
                let a = trial.effect(b.kind)?;
                let d = a
                    .used_params()
                    .iter()
                    .zip(b.used_params())
                    .map(|(x, y)| y - x);
                Some((b.kind, d.collect()))
            })
            .collect(),
    }
}

/// `1/(1 - r)` with `r = (d·d')/|d'|²` clamped to `[-MAX_RATIO,
/// MAX_RATIO]`; 1 without a comparable previous step.
fn factor(d: &[f64], p: Option<&Vec<f64>>) -> f64 {
    let p = match p {
        Some(p) if p.len() == d.len() && !d.is_empty() => p,
        _ => return 1.0,
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let r = dot(d, p) / dot(p, p);
    1.0 / (1.0
        - if r.is_finite() {
            r.clamp(-MAX_RATIO, MAX_RATIO)
        } else {
            0.0
        })
}

/// Aitken's extrapolation of the fixed-point iteration `x -> f(x)` (one
/// round: the state effects found on states reconstructed with `x`),
/// which converges linearly: with successive steps `d = f(x) - x` and
/// `d'` the previous one, the contraction ratio is `r ≈ (d·d')/|d'|²`
/// (clamped to `[-MAX_RATIO, MAX_RATIO]`) and the fixed point
/// `x + d/(1 - r)`; per effect (the wind and each named effect have their
/// own ratios). A negative ratio is an oscillation (box `added_mass=1.0`
/// seed 1: M_a alternating between two values, r ≈ -1), which the step
/// then damps towards the cycle's middle. The first step is plain. M_a is
/// projected onto PSD tensors again.
pub(crate) fn accelerate(
    trial: &StateEffects,
    next: &StateEffects,
    step: &Steps,
    previous: Option<&Steps>,
) -> StateEffects {
    let mut out = next.clone();
    if let (Some(a), Some(b)) = (trial.wind, next.wind) {
        out.wind = Some(a + (b - a) * factor(&step.wind, previous.map(|p| &p.wind)));
    }
    for e in out.effects.iter_mut() {
        let (Some(a), Some(d)) = (trial.effect(e.kind), step.effect(e.kind)) else {
            continue;
        };
        let k = factor(d, previous.and_then(|p| p.effect(e.kind)));
        let x: Vec<f64> = a
            .used_params()
            .iter()
            .zip(d)
            .map(|(a, d)| a + d * k)
            .collect();
        let extrapolated = match e.kind {
            EffectKind::AddedMass => psd(&x).and_then(|m| added_mass_effect(&m)),
            kind => Effect::new(kind, &x),
        };
        if let Some(x) = extrapolated {
            *e = x;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(kind: EffectKind, p: &[f64]) -> Effect<f64> {
        Effect::new(kind, p).expect("effect")
    }

    /// On a linear contraction `f(x) = x* + r (x - x*)` (what a round does
    /// to the wind and M_a, measured r ≈ 0.3-0.6), the second step lands on
    /// the fixed point, for the wind, M_a and a one-parameter effect alike;
    /// M_a stays symmetric PSD; a settled round converges.
    #[test]
    fn aitken_step_finds_the_fixed_point_and_keeps_added_mass_psd() {
        let truth_w = Vector3::new(1.0, 0.0, 0.2);
        let truth_m = Matrix3::from_diagonal(&Vector3::new(3e-5, 1e-5, 6.6e-3));
        let truth_vb = 0.012;
        let r = 0.45;
        let f = |x: &StateEffects| StateEffects {
            wind: x.wind.map(|w| truth_w + (w - truth_w) * r),
            effects: x
                .effects
                .iter()
                .map(|e| match e.kind {
                    EffectKind::AddedMass => {
                        let m = e.added_mass().expect("M_a");
                        added_mass_effect(&(truth_m + (m - truth_m) * r)).expect("M_a")
                    }
                    k => named(k, &[truth_vb + (e.params[0] - truth_vb) * r]),
                })
                .collect(),
        };
        let start_m = Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 2.6e-3));
        let mut x = StateEffects {
            wind: Some(Vector3::new(0.5, 0.01, 0.3)),
            effects: vec![
                added_mass_effect(&start_m).expect("M_a"),
                named(EffectKind::Buoyancy, &[0.008]),
            ],
        };
        let mut previous = None;
        for _ in 0..2 {
            let next = f(&x);
            assert!(!next.close_to(&x));
            let step = steps(&x, &next);
            x = accelerate(&x, &next, &step, previous.as_ref());
            previous = Some(step);
        }
        let w = x.wind.expect("wind");
        let m = x
            .effect(EffectKind::AddedMass)
            .and_then(|e| e.added_mass())
            .expect("M_a");
        let vb = x.effect(EffectKind::Buoyancy).expect("V_b").params[0];
        assert!((w - truth_w).norm() < 1e-9, "{w}");
        assert!((m - truth_m).norm() < 1e-9 * truth_m.norm() + 1e-12, "{m}");
        assert!((vb - truth_vb).abs() < 1e-12, "{vb}");
        assert!(f(&x).close_to(&x));
        // A step that would leave PSD tensors is projected back.
        let tensor = |d: [f64; 3]| StateEffects {
            wind: None,
            effects: vec![
                added_mass_effect(&Matrix3::from_diagonal(&Vector3::from(d))).expect("M_a"),
            ],
        };
        let (start, bad) = (tensor([1e-3, 1e-3, 5e-3]), tensor([-4e-3, 1e-3, 5e-3]));
        let y = accelerate(&start, &bad, &steps(&start, &bad), None);
        let e = y.effects[0]
            .added_mass()
            .expect("M_a")
            .symmetric_eigenvalues();
        assert!(e.min() >= -1e-15, "{e}");
    }

    /// Rounds agree only with the same effects: one more, one fewer or one
    /// changed by more than the tolerance is not close.
    #[test]
    fn close_needs_the_same_effects_within_tolerance() {
        let b = |vb: f64| named(EffectKind::Buoyancy, &[vb]);
        let one = StateEffects {
            wind: None,
            effects: vec![b(0.0100)],
        };
        let near = StateEffects {
            wind: None,
            effects: vec![b(0.0105)],
        };
        let far = StateEffects {
            wind: None,
            effects: vec![b(0.0125)],
        };
        let more = StateEffects {
            wind: None,
            effects: vec![b(0.0100), named(EffectKind::LinearDrag, &[5000.0])],
        };
        assert!(near.close_to(&one) && !far.close_to(&one));
        assert!(!more.close_to(&one) && !one.close_to(&more));
        assert!(one.kinds_within(&more) && !more.kinds_within(&one));
    }

    /// Significant-but-implausible added mass is projected; an all-negative
    /// one gives nothing to try.
    #[test]
    fn psd_projection_of_six_parameters() {
        let m = psd(&[-6e-4, -1.1e-3, 2.6e-3, 0.0, 0.0, 0.0]).expect("positive part");
        assert!((m[(2, 2)] - 2.6e-3).abs() < 1e-12 && m[(0, 0)].abs() < 1e-12);
        assert!(psd(&[-1e-3, -1e-3, -1e-3, 0.0, 0.0, 0.0]).is_none());
    }
}
