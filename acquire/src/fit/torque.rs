//! The torque fit (eqs. 6, 8): per frame
//! `T_k = Σ_i E^i_k q_k L³ Σ_lm β^i_lm Y_lm(E_k) − ½ρL⁵ |Ω_k| D Ω_k`,
//! one joint problem in (β, D); D is projected onto positive definite
//! matrices and β refitted.

use crate::error::Result;
use crate::fit::config::LsqConfig;
use crate::fit::context::FitContext;
use crate::fit::damping::with_floor;
use crate::fit::model::with_torque;
use crate::fit::normals::{per_take, solve, total, Normals, Rows};
use crate::fit::smoothing::{cross_validated, regularise, Smoothing, SMOOTHNESS_ORDERS};
use crate::fit::torque_prior::{beta_of, pin_prior, prior_map, with_prior};
pub(crate) use crate::fit::torque_rows::dense_rows;
pub use crate::fit::torque_rows::TorqueFrames;
use crate::fit::torque_rows::{accumulate, torque_rows};
use crate::fit::torque_window::windowed_normals;
use crate::reconstruct::forces::Sample;
use nalgebra::{DMatrix, DVector};
use omniad_core::sh::{coeff_count, MAX_DEGREE};
use omniad_core::Coefficients;

/// The torque fit's normal equations per take and in total, unknowns
/// `(β¹, β², β³, d)` (eqs. 6, 8; unweighted), from the frames `which`
/// selects.
pub(crate) fn torque_normals(
    samples: &[Sample],
    ctx: &FitContext,
    degree: usize,
    which: TorqueFrames,
) -> (Vec<Normals>, Normals) {
    let rows = TorqueRows { ctx, degree };
    let frames = samples
        .iter()
        .filter(|s| which.takes(s))
        .map(|s| (s.take, s));
    let takes = per_take(frames, &rows);
    let total = total(&takes, rows.dim());
    (takes, total)
}

/// The torque fit's rows: unknowns `(β¹, β², β³, d)`, a frame's three
/// [`TorqueRow`]s, unweighted.
struct TorqueRows<'a> {
    ctx: &'a FitContext,
    degree: usize,
}

impl<'a> Rows for TorqueRows<'a> {
    type Frame = &'a Sample;
    type Normals = Normals;

    fn dim(&self) -> usize {
        3 * coeff_count(self.degree) + 6
    }

    fn add(&self, s: &Self::Frame, nt: &mut Normals) {
        let n = coeff_count(self.degree);
        for row in torque_rows(s, self.ctx, self.degree) {
            accumulate(&mut nt.ata, &mut nt.atb, n, &row);
            nt.btb += row.target * row.target;
        }
    }
}

/// The torque fit's smoothness penalty on beta: `cfg.smoothing` of order
/// 1 (the Dirichlet energy), or, when `cfg.cross_validate`, the weight and
/// order of [`crate::fit::smoothing::SMOOTHING_GRID`] x [`SMOOTHNESS_ORDERS`] that
/// predicts held-out takes' torques best. (The torque model steers the
/// reconstructed attitude, and through it the direction E every force
/// frame is filed under: openbox-clean's C_F went from 7.74 % to 7.35 %
/// with a ten times heavier fixed weight, see BENCHMARKS.md.)
pub fn torque_smoothing(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
    which: TorqueFrames,
) -> Smoothing {
    let (takes, total) = torque_normals(samples, ctx, cfg.degree, which);
    torque_penalty(&takes, &total, cfg)
}

/// [`torque_smoothing`] from the torque fit's normal equations.
fn torque_penalty(takes: &[Normals], total: &Normals, cfg: &LsqConfig) -> Smoothing {
    torque_penalty_scored(takes, total, cfg).1
}

/// [`torque_penalty`] with its held-out score (summed squared torque
/// error of the held-out takes, N² m²; infinite without cross-validation).
fn torque_penalty_scored(takes: &[Normals], total: &Normals, cfg: &LsqConfig) -> (f64, Smoothing) {
    let fallback = Smoothing {
        weight: cfg.smoothing,
        order: 1,
    };
    if !cfg.cross_validate {
        return (f64::INFINITY, fallback);
    }
    cross_validated(
        takes,
        takes,
        total,
        &SMOOTHNESS_ORDERS,
        fallback,
        cfg.degree,
    )
}

/// Fits beta and D jointly on the frames `which` selects; also returns
/// the smoothness penalty used ([`torque_smoothing`]).
pub fn fit_torque(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
    which: TorqueFrames,
) -> ([Vec<f64>; 3], [f64; 6], Smoothing) {
    let (takes, total) = torque_normals(samples, ctx, cfg.degree, which);
    let smoothing = torque_penalty(&takes, &total, cfg);
    let (beta, six) = solve_torque(total, cfg, smoothing, None);
    (beta, six, smoothing)
}

/// β and D of the torque fit's normal equations `total` (unknowns
/// `(β¹, β², β³, d)`) smoothed by `smoothing`: D fitted jointly and
/// projected onto positive definite matrices (or fixed at `damping`),
/// then β refitted with D fixed.
pub(crate) fn solve_torque(
    total: Normals,
    cfg: &LsqConfig,
    smoothing: Smoothing,
    damping: Option<[f64; 6]>,
) -> ([Vec<f64>; 3], [f64; 6]) {
    let n = coeff_count(cfg.degree);
    let Normals { mut ata, atb, .. } = total;
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let six = damping.unwrap_or_else(|| {
        let x = solve(&ata, &atb);
        let raw: [f64; 6] = std::array::from_fn(|i| x[3 * n + i]);
        with_floor(&raw, cfg.damping_floor)
    });
    // Refit beta with D fixed: move the damping term to the right-hand side.
    let sub = ata.view((0, 0), (3 * n, 3 * n)).into_owned();
    let cross = ata.view((0, 3 * n), (3 * n, 6)).into_owned();
    let rhs = atb.rows(0, 3 * n).into_owned() - cross * DVector::from_row_slice(&six);
    let beta = solve(&sub, &rhs);
    (
        std::array::from_fn(|i| beta.rows(i * n, n).as_slice().to_vec()),
        six,
    )
}

/// The final model's torque part (β, D) refitted on the refinement's
/// last frames with [`TorqueFrames::NoThrust`], its force part and
/// extensions kept: the reconstruction, and with it C_F, are those of the
/// refinement, whose fits used [`TorqueFrames::Stable`]. `samples` must
/// be net of the model's named effects, as the refinement's fits were.
/// Only the least-squares method has it. The torque is fitted plain or
/// with the centre-of-pressure prior of a degree in [`PRIOR_DEGREES`]
/// ([`crate::fit::torque_prior`]), at its own SH degree N_T from
/// [`torque_degrees`] (`cfg.torque_degree` forces one), whichever
/// cross-validated fit predicts the held-out takes' torques best (plain
/// at N_T = N without cross-validation). An object's torque can need a
/// finer angular resolution than its force (openbox-clean: degree 10
/// took the true states' C_T from 9.6 to 5.8 %, BENCHMARKS.md issue 20,
/// C_T stop 20); the held-out takes, not the truth, say whether the data
/// carry it. Its frames are taken in windows of `cfg.torque_window`
/// ([`crate::fit::torque_window`]: the mean of every other frame's
/// equations about each frame, where the samples' errors telescope).
pub fn refit_final_torque(
    model: &Coefficients<f64>,
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> Result<Coefficients<f64>> {
    let mut best: Option<(f64, LsqConfig, TorqueSolution)> = None;
    for nt in torque_degrees(cfg) {
        let at = LsqConfig {
            degree: nt,
            ..cfg.clone()
        };
        let (score, solution) = best_torque_at_degree(model, samples, ctx, &at);
        if best.as_ref().is_none_or(|b| score < b.0) {
            best = Some((score, at, solution));
        }
    }
    let Some((_, at, solution)) = best else {
        return Ok(model.clone());
    };
    let (beta, damping) = match solution {
        TorqueSolution::Prior(p, total, sm) => solve_with_prior(total, &at, sm, &p),
        TorqueSolution::Plain(total, sm) => solve_torque(total, &at, sm, None),
    };
    with_torque(model, &beta, &damping)
}

/// The torque degrees N_T the final torque fit tries: `cfg.torque_degree`
/// when set, else N and N+2 within [`MAX_DEGREE`] (N alone without
/// cross-validation, which is what chooses). N+4 as a third candidate was
/// measured and not adopted: it tripled the fit's CPU time, and where it
/// won the held-out choice it cost some sets (BENCHMARKS.md issue 20, C_T
/// stop 21).
pub fn torque_degrees(cfg: &LsqConfig) -> Vec<usize> {
    match cfg.torque_degree {
        Some(nt) => vec![nt.min(MAX_DEGREE)],
        None if !cfg.cross_validate => vec![cfg.degree],
        None => [0, 2]
            .iter()
            .map(|d| cfg.degree + d)
            .filter(|&d| d <= MAX_DEGREE)
            .collect(),
    }
}

/// A torque problem ready to solve: the normal equations and smoothing,
/// with the prior's map `P` when it has one.
enum TorqueSolution {
    Plain(Normals, Smoothing),
    Prior(DMatrix<f64>, Normals, Smoothing),
}

/// The best torque fit at `cfg.degree` (plain, or with a prior of a
/// degree in [`PRIOR_DEGREES`]) by the held-out takes' summed squared
/// torque error (N² m²), with that score.
fn best_torque_at_degree(
    model: &Coefficients<f64>,
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
) -> (f64, TorqueSolution) {
    let (takes, total) = final_normals(samples, ctx, cfg);
    let (plain, smoothing) = torque_penalty_scored(&takes, &total, cfg);
    let mut best = (plain, None);
    for k in PRIOR_DEGREES {
        let problem = prior_problem(&takes, &total, model, ctx, cfg, k);
        if problem.2 .0 < best.0 {
            best = (problem.2 .0, Some(problem));
        }
    }
    match best.1 {
        Some((p, total, (_, sm))) => (best.0, TorqueSolution::Prior(p, total, sm)),
        None => (best.0, TorqueSolution::Plain(total, smoothing)),
    }
}

/// The final torque fit's normal equations: on the windows of
/// `cfg.torque_window` frames ([`crate::fit::torque_window`]), or on each
/// frame when that is 1 or the frames are not runs that have windows.
fn final_normals(samples: &[Sample], ctx: &FitContext, cfg: &LsqConfig) -> (Vec<Normals>, Normals) {
    let which = TorqueFrames::NoThrust;
    (cfg.torque_window > 1)
        .then(|| windowed_normals(samples, ctx, cfg.degree, which, cfg.torque_window))
        .flatten()
        .unwrap_or_else(|| torque_normals(samples, ctx, cfg.degree, which))
}

/// Degrees `K` of the centre of pressure `ρ̂(E)` the final torque fit
/// tries ([`crate::fit::torque_prior`]), besides no prior; the one whose
/// cross-validated fit predicts held-out takes' torques best is kept.
const PRIOR_DEGREES: [usize; 3] = [1, 3, 5];

/// The torque fit's normal equations `takes`, `total` carried to the
/// prior of degree `k` ([`crate::fit::torque_prior::with_prior`], `C_F`
/// from `model`): `P`, the total equations, and the cross-validated
/// smoothing with its held-out score.
fn prior_problem(
    takes: &[Normals],
    total: &Normals,
    model: &Coefficients<f64>,
    ctx: &FitContext,
    cfg: &LsqConfig,
    k: usize,
) -> (DMatrix<f64>, Normals, (f64, Smoothing)) {
    let p = prior_map(model, ctx, cfg.degree, k);
    let takes: Vec<Normals> = takes.iter().map(|t| with_prior(t, &p)).collect();
    let mut total = with_prior(total, &p);
    pin_prior(&mut total, p.ncols());
    let scored = torque_penalty_scored(&takes, &total, cfg);
    (p, total, scored)
}

/// [`fit_torque`] with the centre-of-pressure prior of
/// [`crate::fit::torque_prior`] of degree `k` (`C_F` from `model`): the
/// smoothness penalty (cross-validated as in [`fit_torque`]) on the
/// correction to `ρ̂(E) × C_F(E)` only.
pub fn fit_torque_with_prior(
    samples: &[Sample],
    ctx: &FitContext,
    cfg: &LsqConfig,
    which: TorqueFrames,
    model: &Coefficients<f64>,
    k: usize,
) -> ([Vec<f64>; 3], [f64; 6], Smoothing) {
    let (takes, total) = torque_normals(samples, ctx, cfg.degree, which);
    let (p, total, (_, smoothing)) = prior_problem(&takes, &total, model, ctx, cfg, k);
    let (beta, six) = solve_with_prior(total, cfg, smoothing, &p);
    (beta, six, smoothing)
}

/// [`solve_torque`] on the unknowns `(c, d, ρ)` of
/// [`crate::fit::torque_prior::with_prior`]: D fitted jointly and
/// projected onto positive definite matrices, then `(c, ρ)` refitted with
/// D fixed; returns `β = c + P ρ` and D.
pub(crate) fn solve_with_prior(
    total: Normals,
    cfg: &LsqConfig,
    smoothing: Smoothing,
    p: &DMatrix<f64>,
) -> ([Vec<f64>; 3], [f64; 6]) {
    let n = coeff_count(cfg.degree);
    let Normals { mut ata, atb, .. } = total;
    regularise(&mut ata, 3, cfg.degree, smoothing);
    let x = solve(&ata, &atb);
    let raw: [f64; 6] = std::array::from_fn(|i| x[3 * n + i]);
    let six = with_floor(&raw, cfg.damping_floor);
    let keep: Vec<usize> = (0..3 * n).chain(3 * n + 6..ata.nrows()).collect();
    let d: Vec<usize> = (3 * n..3 * n + 6).collect();
    let sub = ata.select_rows(&keep).select_columns(&keep);
    let cross = ata.select_rows(&keep).select_columns(&d);
    let rhs = atb.select_rows(&keep) - cross * DVector::from_row_slice(&six);
    let y = solve(&sub, &rhs);
    // Back to (c, d, ρ) so that beta_of finds ρ last.
    let mut full = DVector::zeros(ata.nrows());
    for (v, &i) in y.iter().zip(&keep) {
        full[i] = *v;
    }
    let beta = beta_of(&full, p);
    (
        std::array::from_fn(|i| beta.rows(i * n, n).as_slice().to_vec()),
        six,
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::fit::lsq::tests::{degree_six, samples};
    use crate::input::recording::TakeKind;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};
    use nalgebra::Vector3;

    /// Relative L2 error of `model`'s `C_T` against `truth`'s over 200
    /// directions spread over the sphere.
    pub(crate) fn torque_coefficient_error(
        model: &Coefficients<f64>,
        truth: &Coefficients<f64>,
    ) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for e in omniad_core::quadrature::fibonacci_sphere(200) {
            let (Some(a), Some(b)) = (model.at_direction(&e), truth.at_direction(&e)) else {
                continue;
            };
            num += (a.torque - b.torque).norm_squared();
            den += b.torque.norm_squared();
        }
        (num / den).sqrt()
    }

    #[test]
    fn the_final_torque_fit_takes_spin_up_frames_not_thrust_frames_and_keeps_the_force() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let (ctx, cfg) = degree_six(&truth);
        let cfg = LsqConfig {
            smoothing: 1e-7,
            cross_validate: false,
            ..cfg
        };
        let mut frames = samples(&truth, 3000, TakeKind::Drop);
        for (i, s) in frames.iter_mut().enumerate() {
            // Half of the directions only in frames that fail the T·Ω test
            // (a spin-up: physics the SH torque allows) ...
            s.use_torque = s.velocity.x < 0.0;
            // ... and some frames that fail the no-thrust test, whose
            // torques are wrong: no fit may take them.
            if i % 7 == 0 {
                s.use_force = false;
                s.use_torque = false;
                s.torque *= -5.0;
            }
        }
        let n = coeff_count(6);
        let start = with_torque(
            &truth,
            &[vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            &[0.0; 6],
        )
        .expect("start");
        let refit = refit_final_torque(&start, &frames, &ctx, &cfg).expect("refit");
        let e = torque_coefficient_error(&refit, &truth);
        assert!(e < 0.02, "C_T error of the final fit {e}");
        let (beta, six, _) = fit_torque(&frames, &ctx, &cfg, TorqueFrames::Stable);
        let stable = with_torque(&truth, &beta, &six).expect("stable");
        let e_stable = torque_coefficient_error(&stable, &truth);
        assert!(e_stable > 5.0 * e, "stable frames only: {e_stable} vs {e}");
        // The force part is the starting model's.
        for e in omniad_core::quadrature::fibonacci_sphere(20) {
            let (Some(a), Some(b)) = (refit.at_direction(&e), start.at_direction(&e)) else {
                panic!("direction {e}");
            };
            assert_eq!(a.force, b.force);
        }
    }

    /// Noisy frames of `truth` in six takes: 1200 frames, torque noise
    /// of a fifth of the torques' RMS.
    fn noisy_takes(truth: &Coefficients<f64>) -> Vec<Sample> {
        let mut frames = samples(truth, 1200, TakeKind::Drop);
        let rms = (frames.iter().map(|s| s.torque.norm_squared()).sum::<f64>()
            / frames.len() as f64)
            .sqrt();
        let mut rng = crate::rng::Rng::new(11);
        for (i, s) in frames.iter_mut().enumerate() {
            s.take = i % 6;
            s.torque += Vector3::new(rng.normal(), rng.normal(), rng.normal()) * (0.2 * rms);
        }
        frames
    }

    /// The final fit's N_T (from N = 6: 6 or 8) follows what the held-out
    /// takes say: a torque with as much at degrees 7-8 as below gets
    /// degree 8; a torque of degree 6 keeps 6 (the extra unknowns only
    /// fit the noise). No truth enters the choice.
    #[test]
    fn the_torque_degree_is_chosen_by_held_out_takes() {
        let coarse = truth_model(&ObjectSpec::of(SynthObject::Box), 6).expect("model");
        let (ctx, cfg) = degree_six(&coarse);
        let mut fine = coarse.with_torque_degree(8).expect("degree 8");
        // As large as the largest coefficient below (a box's torque about
        // its centre is small, its β_00 nearly zero).
        let c = &coarse;
        let size = (0..coeff_count(6))
            .flat_map(|k| (0..3).filter_map(move |i| c.beta(i, k)))
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for k in coeff_count(6)..coeff_count(8) {
            for i in 0..3 {
                let v = size * (((k * 7 + i * 3) % 11) as f64 / 11.0 - 0.5);
                fine.set_beta(i, k, v).expect("in range");
            }
        }
        assert_eq!(torque_degrees(&cfg), vec![6, 8]);
        for (truth, want) in [(&fine, 8), (&coarse, 6)] {
            let frames = noisy_takes(truth);
            let refit = refit_final_torque(truth, &frames, &ctx, &cfg).expect("refit");
            assert_eq!(refit.torque_degree(), want);
            assert_eq!(refit.degree(), 6);
            let e = torque_coefficient_error(&refit, truth);
            assert!(e < 0.1, "C_T error {e} at N_T = {want}");
        }
        // Forced: --torque-degree.
        let forced = LsqConfig {
            torque_degree: Some(10),
            ..cfg
        };
        let frames = noisy_takes(&fine);
        let refit = refit_final_torque(&fine, &frames, &ctx, &forced).expect("refit");
        assert_eq!(refit.torque_degree(), 10);
    }

    #[test]
    fn torque_frames_select_by_the_stability_tests() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 4).expect("model");
        let mut s = samples(&truth, 1, TakeKind::Spin).remove(0);
        for (force, torque) in [(true, true), (true, false), (false, false)] {
            s.use_force = force;
            s.use_torque = torque;
            assert_eq!(TorqueFrames::Stable.takes(&s), torque);
            assert_eq!(TorqueFrames::NoThrust.takes(&s), force);
        }
    }
}
