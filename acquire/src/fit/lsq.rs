//! The default fit (§6, improved): regularised linear least squares of
//! alpha, beta and D directly on the reconstructed frames, in force space.
//!
//! Per frame k with dynamic pressure `q_k = ½ρ|V_k|²` and basis `E^i_k`:
//! `F_k·E^i_k = q_k L² Σ_lm α^i_lm Y_lm(E_k)` (eqs. 5, 7) — one problem in
//! `(α¹, α², α³)`, each frame's three residuals weighted by the inverse of
//! its reconstruction uncertainty (generalised least squares, see
//! `force_weights`) — and
//! `T_k = Σ_i E^i_k q_k L³ Σ_lm β^i_lm Y_lm(E_k) - ½ρL⁵ |Ω_k| D Ω_k` (eqs. 6, 8),
//! one joint problem in (β, D). Smoothness: Tikhonov on a Sobolev-type norm
//! `Σ l(l+1) (l(l+1)/(N(N+1)))^(p-1) c_lm²` scaled by the data, its weight
//! and order `p` chosen for each of the two problems by leave-one-take-out
//! cross-validation ([`crate::fit::select`]). D is projected onto positive definite
//! matrices and β refitted; `C_F(E)·E < 0` (no thrust, §5) is enforced on a
//! dense direction grid by penalty rows. The pieces: [`crate::fit::force`],
//! [`crate::fit::torque`], [`crate::fit::smoothing`], [`crate::fit::weights`],
//! [`crate::fit::thrust`], [`crate::fit::extensions`].

use crate::fit::config::LsqConfig;
use crate::fit::context::FitContext;
use crate::fit::model::{FitSmoothing, RawModel};
use crate::fit::torque::{fit_torque, TorqueFrames};
use crate::reconstruct::forces::Sample;

/// The full least-squares fit.
pub fn fit(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> RawModel {
    let force = crate::fit::extensions::fit_force_and_extensions(samples, ctx, cfg);
    let (beta, damping, torque) = fit_torque(samples, ctx, cfg, TorqueFrames::Stable);
    RawModel {
        alpha: force.alpha,
        beta,
        damping,
        spin_coupling: force.spin,
        gravity_coupling: force.gravity,
        extension_test: force.test,
        smoothing: Some(FitSmoothing {
            force: force.smoothing,
            torque,
        }),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::fit::context::sh_and_basis;
    use crate::fit::force::{fit_force, force_smoothing};
    use crate::fit::smoothing::SMOOTHNESS_ORDERS;
    use crate::input::recording::TakeKind;
    use crate::rng::Rng;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use nalgebra::Vector3;
    use omniad_core::gravity_coupling::GravityCoupling;
    use omniad_core::sh::coeff_count;
    use omniad_core::spin_coupling::SpinCoupling;

    /// Exact samples of a known model at random directions and spins.
    pub(crate) fn samples(
        model: &omniad_core::Coefficients<f64>,
        n: usize,
        kind: TakeKind,
    ) -> Vec<Sample> {
        let mut rng = Rng::new(3);
        (0..n)
            .map(|i| {
                let velocity = rng.direction() * rng.range(2.0, 6.0);
                let angular_velocity = rng.direction() * rng.range(0.0, 15.0);
                let w = model.wrench(&velocity, &angular_velocity, 1.2);
                Sample {
                    take: 0,
                    index: i,
                    t: 0.0,
                    kind,
                    velocity,
                    angular_velocity,
                    velocity_rate: nalgebra::Vector3::zeros(),
                    force: w.force,
                    torque: w.torque,
                    gravity_body: nalgebra::Vector3::new(0.0, 0.0, -9.81),
                    force_cov: nalgebra::Matrix3::zeros(),
                    use_force: true,
                    use_torque: true,
                }
            })
            .collect()
    }

    #[test]
    fn recovers_a_known_model_from_exact_frames() {
        let spec = ObjectSpec::of(SynthObject::Box);
        let truth = truth_model(&spec, 6).expect("model");
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: truth.reference_length(),
            pole: truth.pole(),
        };
        let frames = samples(&truth, 3000, TakeKind::Drop);
        let raw = fit(
            &frames,
            &ctx,
            &LsqConfig {
                degree: 6,
                smoothing: 1e-7,
                ..LsqConfig::default()
            },
        );
        let model = crate::fit::model::with_raw(&truth, &raw).expect("model");
        let (mut num, mut den) = (0.0, 0.0);
        for e in omniad_core::quadrature::fibonacci_sphere(200) {
            let (a, b) = (
                model.at_direction(&e).expect("dir"),
                truth.at_direction(&e).expect("dir"),
            );
            num += (a.force - b.force).norm_squared() + (a.torque - b.torque).norm_squared();
            den += b.force.norm_squared();
        }
        assert!(
            (num / den).sqrt() < 0.02,
            "relative error {}",
            (num / den).sqrt()
        );
        assert!(
            (model.damping() - truth.damping()).norm() < 0.05 * truth.damping().norm(),
            "{} vs {}",
            model.damping(),
            truth.damping()
        );
    }

    /// Frames of `truth` spread over five takes, each take's forces off by
    /// a take-constant body-frame vector of size `offset` x the force scale.
    fn takes_with_offsets(truth: &omniad_core::Coefficients<f64>, offset: f64) -> Vec<Sample> {
        let mut rng = Rng::new(9);
        let bias: Vec<Vector3<f64>> = (0..5).map(|_| rng.direction() * offset).collect();
        samples(truth, 1500, TakeKind::Drop)
            .into_iter()
            .enumerate()
            .map(|(i, mut s)| {
                s.take = i % 5;
                let q = 0.5 * 1.2 * s.velocity.norm_squared() * truth.reference_length().powi(2);
                s.force += bias.get(s.take).copied().unwrap_or_default() * q;
                s
            })
            .collect()
    }

    /// Exact frames of `truth` spread over six takes (cross-validation
    /// needs takes), with a little noise so that the fit is not exact.
    fn six_takes(truth: &omniad_core::Coefficients<f64>) -> Vec<Sample> {
        let mut rng = Rng::new(17);
        let mut frames = samples(truth, 3000, TakeKind::Drop);
        for (i, s) in frames.iter_mut().enumerate() {
            s.take = i % 6;
            s.gravity_body = rng.direction() * 9.81;
            if let Some(g) = truth.gravity_coupling() {
                s.force += g.force(&s.gravity_body, 1.2, truth.reference_length());
            }
            s.force += rng.direction() * 1e-3;
        }
        frames
    }

    /// The fit context of `model` at ρ = 1.2 and a degree-6 fit.
    pub(crate) fn degree_six(model: &omniad_core::Coefficients<f64>) -> (FitContext, LsqConfig) {
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: model.reference_length(),
            pole: model.pole(),
        };
        let cfg = LsqConfig {
            degree: 6,
            ..LsqConfig::default()
        };
        (ctx, cfg)
    }

    #[test]
    fn gravity_coupling_is_found_when_present_and_only_then() {
        let plain = truth_model(&ObjectSpec::of(SynthObject::Plate), 6).expect("model");
        let (ctx, cfg) = degree_six(&plain);
        assert_eq!(fit(&six_takes(&plain), &ctx, &cfg).gravity_coupling, None);
        // Buoyancy of 2.4 litres.
        let buoyant = GravityCoupling::buoyancy(2.4e-3, plain.reference_length());
        let mut floated = plain.clone();
        floated
            .set_gravity_coupling(Some(buoyant))
            .expect("coupling");
        let raw = fit(&six_takes(&floated), &ctx, &cfg);
        assert_eq!(raw.spin_coupling, None);
        let g = raw.gravity_coupling.expect("gravity coupling kept");
        assert!((g.g - buoyant.g).abs().max() < 1e-3, "G {}", g.g);
    }

    #[test]
    fn spin_coupling_is_found_when_present_and_only_then() {
        let spec = ObjectSpec::of(SynthObject::Plate);
        let plain = truth_model(&spec, 6).expect("model");
        let (ctx, cfg) = degree_six(&plain);
        assert_eq!(fit(&six_takes(&plain), &ctx, &cfg).spin_coupling, None);
        let mut spun = plain.clone();
        let magnus = SpinCoupling::magnus(0.02);
        spun.set_spin_coupling(Some(magnus)).expect("coupling");
        let raw = fit(&six_takes(&spun), &ctx, &cfg);
        let k = raw.spin_coupling.expect("coupling kept");
        for (got, want) in k.k.iter().flatten().zip(magnus.k.iter().flatten()) {
            assert!((got - want).abs() < 1e-3, "K {:?}", k.k);
        }
        // Alpha is the plain model's: the coupling took its share.
        let alpha = &raw.alpha[0];
        for (k, got) in alpha.iter().enumerate().take(coeff_count(6)) {
            let truth = plain.alpha(0, k).expect("alpha");
            assert!((got - truth).abs() < 2e-3, "alpha1[{k}] {got} vs {truth}");
        }
        let off = LsqConfig {
            extensions: false,
            ..cfg
        };
        assert_eq!(fit(&six_takes(&spun), &ctx, &off).spin_coupling, None);
    }

    #[test]
    fn cross_validation_smooths_noisy_takes_more() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let (ctx, cfg) = degree_six(&truth);
        for order in SMOOTHNESS_ORDERS {
            let cfg = LsqConfig {
                smoothness_order: Some(order),
                ..cfg.clone()
            };
            let clean = force_smoothing(&takes_with_offsets(&truth, 0.0), &ctx, &cfg);
            let noisy = force_smoothing(&takes_with_offsets(&truth, 0.5), &ctx, &cfg);
            assert_eq!((clean.order, noisy.order), (order, order));
            assert!(clean.weight <= 1e-3, "clean frames smoothed by {clean:?}");
            assert!(
                noisy.weight > clean.weight,
                "noisy {noisy:?} <= clean {clean:?}"
            );
        }
        // Left to choose, it picks one of the orders offered.
        let chosen = force_smoothing(&takes_with_offsets(&truth, 0.5), &ctx, &cfg);
        assert!(SMOOTHNESS_ORDERS.contains(&chosen.order), "{chosen:?}");
    }

    #[test]
    fn never_fits_thrust() {
        // Frames whose drag points along E (thrust) must not produce C_F·E >= 0.
        let spec = ObjectSpec::of(SynthObject::Plate);
        let truth = truth_model(&spec, 4).expect("model");
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: truth.reference_length(),
            pole: truth.pole(),
        };
        let mut frames = samples(&truth, 500, TakeKind::Drop);
        for s in &mut frames {
            s.force = -s.force;
        }
        let cfg = LsqConfig {
            degree: 4,
            ..LsqConfig::default()
        };
        let alpha = fit_force(&frames, &ctx, &cfg);
        for e in omniad_core::quadrature::fibonacci_sphere(500) {
            let (y, _) = sh_and_basis(4, &e, &ctx.pole);
            let drag: f64 = y.iter().zip(&alpha[0]).map(|(a, b)| a * b).sum();
            assert!(drag < 0.0, "C_F·E = {drag} at {e:?}");
        }
    }
}
