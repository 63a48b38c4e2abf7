//! Cross-fitted reconstruction models: in the refinement, each take is
//! reconstructed with the force model fitted to the OTHER takes' frames.
//!
//! Why: a take's reconstruction error (a slow depth wander along the line
//! of sight, BENCHMARKS.md stops 10-12) enters alpha through its frames;
//! reconstructed again with that alpha as the process model, the take is
//! pulled back towards its own error, and the next fit returns most of it
//! (the refinement's slow mode, largest eigenvalue 0.6-0.9). With the
//! take's own frames left out of the model it is filtered with, the
//! feedback of take-specific errors is cut; what the takes share still
//! refines. This is cross-fitting (sample splitting) as in
//! leave-one-out estimation; the model written out is still the fit to
//! every take.
//!
//! The fold fits reuse the full fit's chosen smoothness penalty (no
//! cross-validation inside a fold), its frame weights and its beta, D and
//! extensions: only alpha is refitted, on the frames net of the kept
//! extensions' force, from the full normal equations minus the take's.

use crate::fit::config::LsqConfig;
use crate::fit::context::FitContext;
use crate::fit::force::fit_force_leaving_out_each_take;
use crate::fit::model::FitSmoothing;
use crate::reconstruct::forces::Sample;
use omniad_core::Coefficients;

/// Per take `0..takes`: `fitted` with alpha refitted without that take's
/// frames (`frames` net of the named effects, as fitted; the kept
/// extensions' force is taken off them too). Empty (every take then uses
/// `fitted`) when the fit chose no smoothing (the paper's method).
pub(super) fn per_take_models(
    fitted: &Coefficients<f64>,
    frames: &[Sample],
    takes: usize,
    ctx: &FitContext,
    lsq: &LsqConfig,
    smoothing: Option<FitSmoothing>,
) -> Vec<Coefficients<f64>> {
    let Some(s) = smoothing else {
        return Vec::new();
    };
    let frames = net_of_extensions(fitted, frames, ctx.air_density);
    let cfg = LsqConfig {
        degree: usize::from(fitted.degree()),
        ..lsq.clone()
    };
    let folds = fit_force_leaving_out_each_take(&frames, ctx, &cfg, s.force);
    (0..takes)
        .map(|j| match folds.iter().find(|(id, _)| *id == j) {
            // A take whose frames are the only usable ones keeps the full
            // model (nothing would be left to fit).
            Some((_, alpha)) if folds.len() > 1 => with_alpha(fitted, alpha),
            _ => fitted.clone(),
        })
        .collect()
}

/// `frames` with the force of `model`'s extensions (spin and gravity
/// coupling, fitted jointly with alpha) taken off: what alpha alone
/// describes. Air of density `air_density`, kg/m³.
fn net_of_extensions(
    model: &Coefficients<f64>,
    frames: &[Sample],
    air_density: f64,
) -> Vec<Sample> {
    let (spin, gravity) = (model.spin_coupling(), model.gravity_coupling());
    let mut out = frames.to_vec();
    if spin.is_none() && gravity.is_none() {
        return out;
    }
    // The zero-alpha model's wrench is the spin coupling's force alone
    // (plus beta's torque, unused here).
    let mut bare = model.clone();
    for i in 0..3 {
        for k in 0..bare.coeff_count() {
            let _ = bare.set_alpha(i, k, 0.0);
        }
    }
    let l = model.reference_length();
    for f in &mut out {
        f.force -= bare
            .wrench(&f.velocity, &f.angular_velocity, air_density)
            .force;
        if let Some(g) = gravity {
            f.force -= g.force(&f.gravity_body, air_density, l);
        }
    }
    out
}

/// `model` with its alpha replaced.
fn with_alpha(model: &Coefficients<f64>, alpha: &[Vec<f64>; 3]) -> Coefficients<f64> {
    let mut m = model.clone();
    for (i, a) in alpha.iter().enumerate() {
        for (k, v) in a.iter().enumerate().take(m.coeff_count()) {
            // In range by construction (same degree); a failure leaves the
            // full fit's value.
            let _ = m.set_alpha(i, k, *v);
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::lsq::tests::samples;
    use crate::fit::smoothing::Smoothing;
    use crate::input::recording::TakeKind;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use nalgebra::Vector3;

    /// Mean |C_F - C_F*| over a spread of directions.
    fn error(m: &Coefficients<f64>, truth: &Coefficients<f64>) -> f64 {
        let mut rng = crate::rng::Rng::new(5);
        let mut sum = 0.0;
        for _ in 0..200 {
            let e: Vector3<f64> = rng.direction();
            let (Some(a), Some(b)) = (m.at_direction(&e), truth.at_direction(&e)) else {
                return f64::INFINITY;
            };
            sum += (a.force - b.force).norm();
        }
        sum / 200.0
    }

    #[test]
    fn a_take_is_reconstructed_with_a_model_free_of_its_own_error() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 6).unwrap();
        let l = truth.reference_length();
        // Take 0's forces carry a constant body-frame error (a slow
        // reconstruction error); takes 1-4 are exact; take 5 has no frames.
        let frames: Vec<Sample> = samples(&truth, 1500, TakeKind::Drop)
            .into_iter()
            .enumerate()
            .map(|(i, mut s)| {
                s.take = i % 5;
                if s.take == 0 {
                    let q = 0.5 * 1.2 * s.velocity.norm_squared() * l * l;
                    s.force += Vector3::new(0.1, -0.05, 0.2) * q;
                }
                s
            })
            .collect();
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: l,
            pole: truth.pole(),
        };
        let light = Smoothing {
            weight: 1e-6,
            order: 2,
        };
        let smoothing = Some(FitSmoothing {
            force: light,
            torque: light,
        });
        let models = per_take_models(&truth, &frames, 6, &ctx, &LsqConfig::default(), smoothing);
        assert_eq!(models.len(), 6);
        let own = error(&models[0], &truth);
        let other = error(&models[1], &truth);
        assert!(own < 0.05 * other, "take 0: {own}, take 1: {other}");
        // Every other take's model carries part of take 0's error.
        for m in &models[1..5] {
            assert!(error(m, &truth) > 10.0 * own);
        }
        // A take without frames keeps the full model.
        assert!(error(&models[5], &truth) < 1e-12);
        // No smoothing chosen (the paper's method): no per-take models.
        assert!(per_take_models(&truth, &frames, 6, &ctx, &LsqConfig::default(), None).is_empty());
    }
}
