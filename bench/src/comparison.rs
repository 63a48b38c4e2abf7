//! One RK4 step of the paper's foam plate under each model of the core's
//! one model selector ([`omniad_core::model`]): vacuum, the Fig. 12
//! comparison models (Kirchhoff added mass, per-element drag and traction,
//! per-element simplified lift and drag) and OmniAD with the degree-8
//! benchmark model, all by the single-body path: what a comparison costs
//! next to the model it is compared with.

use crate::model::{model, moving};
use crate::physics::{plate, DT};
use crate::timer::per_call;
use omniad_core::integrate::rk4_step;
use omniad_core::model::{Model, ModelKind};
use omniad_core::reference::shape::Shape;
use omniad_core::Environment;
use std::hint::black_box;

/// One model's figure.
#[derive(Clone, Copy, Debug)]
pub struct ModelStep {
    /// Which model.
    pub kind: ModelKind,
    /// One f64 RK4 step of one body, ns.
    pub rk4_ns: f64,
}

/// Measures every model of [`ModelKind::ALL`] on the paper's plate
/// ([`Shape::PAPER_PLATE`], the body of [`plate`]).
pub fn measure(quick: bool) -> Vec<ModelStep> {
    let batches = if quick { 20 } else { 400 };
    let (coefficients, body, env) = (model::<f64>(), plate(), Environment::standard());
    let shape = Shape::PAPER_PLATE;
    // Moving and turning, as in flight: every element sees air.
    let s0 = moving();
    ModelKind::ALL
        .iter()
        .filter_map(|&kind| {
            let air = Model::new(kind, Some(&shape), Some(&coefficients), env).ok()?;
            let seconds = per_call(batches, 50, || {
                black_box(rk4_step(&body, &env, &air, 0.0, DT, black_box(&s0)));
            });
            Some(ModelStep {
                kind,
                rk4_ns: seconds * 1e9,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_is_measured() {
        let steps = measure(true);
        let kinds: Vec<ModelKind> = steps.iter().map(|s| s.kind).collect();
        assert_eq!(kinds, ModelKind::ALL.to_vec());
        assert!(steps.iter().all(|s| s.rk4_ns.is_finite() && s.rk4_ns > 0.0));
    }
}
