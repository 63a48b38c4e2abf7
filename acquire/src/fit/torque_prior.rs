//! A physical prior for the torque fit: the air's torque about the centre
//! of mass as the moment of the fitted force about a centre of pressure
//! that moves with the air's direction, plus an SH correction shrunk
//! toward zero.
//!
//! Any distribution of surface forces with resultant `F` has, about the
//! centre of mass, the moment `r_cp × F` of a point `r_cp` on its line of
//! action plus a couple along `F` (Poinsot's central axis); for a
//! lifting surface the centre of pressure moves with the angle of attack
//! (a flat plate's from the quarter chord toward mid-chord as the angle
//! grows: Anderson, *Fundamentals of Aerodynamics*, §1.6 and §4.7;
//! Hoerner, *Fluid-Dynamic Lift*, ch. 3). In the coefficients of eqs.
//! (5)-(8) (`F = ½ρ|V|²L² C_F(E)`, `T = ½ρ|V|²L³ C_T(E)`, body frame):
//! `C_T(E) = ρ̂(E) × C_F(E) + ΔC_T(E)`, `ρ̂ = r_cp / L` dimensionless,
//! written in real SH of a low degree `K`
//! (`ρ̂(E) = Σ_{j, s} ρ_js Y_s(E) e_j`, `s` up to `(K+1)²`).
//!
//! The fit: `β = P ρ + c` with `P` the least-squares projection of each
//! `Y_s(E) e_j × C_F(E)` onto eq. (8)'s degree-N space (`C_F` the model's
//! fitted force, so the prior costs no extra data), `ρ` free (a few dozen
//! numbers the torque samples fix well) and the smoothness penalty on the
//! correction `c` alone, its weight and order chosen by leave-one-take-out
//! as the plain fit's: a Gaussian prior on `β` centred on the physically
//! structured mean `P ρ` instead of on zero (ridge / Tikhonov toward a
//! prior mean, e.g. Hastie, Tibshirani & Friedman, *The Elements of
//! Statistical Learning*, §3.4.1 and ex. 3.6). Where the data say little,
//! the torque falls back on the centre of pressure rather than on zero.
//! Measured in BENCHMARKS.md (issue 20, C_T stop 20).

use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::normals::Normals;
use nalgebra::{DMatrix, DVector, Vector3};
use omniad_core::sh::coeff_count;
use omniad_core::Coefficients;

/// Directions the projection `P` is computed on (several per unknown of a
/// degree-8 β block, so the projection is well posed).
const PROJECTION_DIRECTIONS: usize = 2000;

/// `P`: column `j·m + s` holds the β coefficients (three blocks of
/// `coeff_count(degree)`, basis `E^i`) of `Y_s(E) e_j × C_F(E)`, `m =
/// coeff_count(k)`, projected by least squares over
/// [`PROJECTION_DIRECTIONS`] Fibonacci directions; `C_F` is `model`'s.
pub(crate) fn prior_map(
    model: &Coefficients<f64>,
    ctx: &FitContext,
    degree: usize,
    k: usize,
) -> DMatrix<f64> {
    let (n, m) = (coeff_count(degree), coeff_count(k));
    let dirs: Vec<Vector3<f64>> =
        omniad_core::quadrature::fibonacci_sphere(PROJECTION_DIRECTIONS).collect();
    let mut y = DMatrix::zeros(dirs.len(), n);
    // g[i]: row = direction, column = prior function (j, s), value along E^i.
    let mut g = [(); 3].map(|_| DMatrix::zeros(dirs.len(), 3 * m));
    for (row, e) in dirs.iter().enumerate() {
        let (sh, basis) = sh_and_basis(degree, e, &ctx.pole);
        for (col, v) in sh.iter().enumerate() {
            y[(row, col)] = *v;
        }
        let (low, _) = sh_and_basis(k, e, &ctx.pole);
        let cf = model
            .at_direction(e)
            .map_or_else(Vector3::zeros, |c| c.force);
        for j in 0..3 {
            let moment = Vector3::ith(j, 1.0).cross(&cf);
            for (s, ys) in low.iter().enumerate() {
                for (i, b) in basis.iter().enumerate() {
                    g[i][(row, j * m + s)] = ys * moment.dot(b);
                }
            }
        }
    }
    let yty = y.transpose() * &y;
    let mut p = DMatrix::zeros(3 * n, 3 * m);
    for (i, gi) in g.iter().enumerate() {
        let rhs = y.transpose() * gi;
        let x = yty
            .clone()
            .cholesky()
            .map_or_else(|| DMatrix::zeros(n, 3 * m), |c| c.solve(&rhs));
        p.view_mut((i * n, 0), (n, 3 * m)).copy_from(&x);
    }
    p
}

/// Normal equations in `(β, d)` (β three blocks, then D's six) carried to
/// the unknowns `(c, d, ρ)` of `β = c + P ρ`: with `M = [[I, 0, P], [0, I,
/// 0]]`, `MᵀAᵀAM`, `MᵀAᵀb`, `bᵀb` unchanged.
pub(crate) fn with_prior(nt: &Normals, p: &DMatrix<f64>) -> Normals {
    let (dim, extra) = (nt.ata.nrows(), p.ncols());
    let mut mm = DMatrix::zeros(dim, dim + extra);
    mm.view_mut((0, 0), (dim, dim))
        .copy_from(&DMatrix::identity(dim, dim));
    mm.view_mut((0, dim), (p.nrows(), extra)).copy_from(p);
    let mt = mm.transpose();
    Normals {
        ata: &mt * &nt.ata * &mm,
        atb: &mt * &nt.atb,
        btb: nt.btb,
    }
}

/// Adds to the `extra` last unknowns (the prior's `ρ`) a ridge of
/// `1e-8` x their mean data weight: `ρ̂` along `C_F` gives no moment, so
/// part of `ρ`'s space is (nearly) unobserved.
pub(crate) fn pin_prior(nt: &mut Normals, extra: usize) {
    let dim = nt.ata.nrows();
    let from = dim.saturating_sub(extra);
    let scale = (from..dim).map(|i| nt.ata[(i, i)]).sum::<f64>() / extra.max(1) as f64;
    let ridge = if scale > 0.0 { 1e-8 * scale } else { 1e-12 };
    for i in from..dim {
        nt.ata[(i, i)] += ridge;
    }
}

/// `β = c + P ρ` from a solution `x = (c, d, ρ)` of `3n + 6 + 3m`
/// unknowns: the β part only (three blocks).
pub(crate) fn beta_of(x: &DVector<f64>, p: &DMatrix<f64>) -> DVector<f64> {
    let n3 = p.nrows();
    let rho = x.rows(x.len() - p.ncols(), p.ncols());
    x.rows(0, n3) + p * rho
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::config::LsqConfig;
    use crate::fit::lsq::tests::{degree_six, samples};
    use crate::fit::model::with_torque;
    use crate::fit::torque::{fit_torque, refit_final_torque, TorqueFrames};
    use crate::input::recording::TakeKind;
    use crate::rng::Rng;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};

    /// `truth` with its torque replaced by `ρ̂(E) × C_F(E)` of degree 1
    /// (`ρ` fixed numbers), projected by [`prior_map`]; and `ρ̂` itself.
    fn centre_of_pressure_model(
        truth: &Coefficients<f64>,
        ctx: &FitContext,
    ) -> (Coefficients<f64>, impl Fn(&Vector3<f64>) -> Vector3<f64>) {
        let degree = usize::from(truth.degree());
        let p = prior_map(truth, ctx, degree, 1);
        let rho = DVector::from_fn(12, |i, _| 0.05 * ((i * 7 % 5) as f64 - 2.0));
        let beta = &p * &rho;
        let n = coeff_count(degree);
        let blocks = std::array::from_fn(|i| beta.rows(i * n, n).as_slice().to_vec());
        let model = with_torque(truth, &blocks, &[0.0; 6]).expect("model");
        let pole = ctx.pole;
        let r = move |e: &Vector3<f64>| {
            let (y, _) = sh_and_basis(1, e, &pole);
            Vector3::from_fn(|j, _| (0..4).map(|s| rho[j * 4 + s] * y[s]).sum::<f64>())
        };
        (model, r)
    }

    /// Away from the pole (where eq. 8's basis `E²`, `E³` turns and the
    /// projection converges slowly) the projected prior is the moment
    /// `ρ̂(E) × C_F(E)`, and closer the higher the degree.
    #[test]
    fn the_prior_map_is_the_moment_of_the_force_about_the_centre_of_pressure() {
        let truth = truth_model(&ObjectSpec::of(SynthObject::Plate), 6).expect("model");
        let (ctx, _) = degree_six(&truth);
        let errors: Vec<f64> = [6u8, 12]
            .iter()
            .map(|&d| {
                let (model, r) = centre_of_pressure_model(&truth.with_degree(d).expect("d"), &ctx);
                let (mut num, mut den) = (0.0, 0.0);
                for e in omniad_core::quadrature::fibonacci_sphere(300) {
                    if e.dot(&ctx.pole).abs() > 0.8 {
                        continue;
                    }
                    let c = model.at_direction(&e).expect("direction");
                    let want = r(&e).cross(&c.force);
                    num += (c.torque - want).norm_squared();
                    den += want.norm_squared();
                }
                assert!(den > 0.0);
                (num / den).sqrt()
            })
            .collect();
        assert!(errors[0] < 0.1 && errors[1] < 0.6 * errors[0], "{errors:?}");
    }

    #[test]
    fn the_prior_beats_the_plain_fit_on_noisy_torques_of_a_centre_of_pressure_body() {
        let plate = truth_model(&ObjectSpec::of(SynthObject::Plate), 6).expect("model");
        let (ctx, cfg) = degree_six(&plate);
        let cfg = LsqConfig {
            extensions: false,
            ..cfg
        };
        let (truth, _) = centre_of_pressure_model(&plate, &ctx);
        let mut frames = samples(&truth, 600, TakeKind::Drop);
        let rms = (frames.iter().map(|s| s.torque.norm_squared()).sum::<f64>()
            / frames.len() as f64)
            .sqrt();
        let mut rng = Rng::new(5);
        for (i, s) in frames.iter_mut().enumerate() {
            s.take = i % 6;
            s.torque += Vector3::new(rng.normal(), rng.normal(), rng.normal()) * (0.3 * rms);
        }
        let error = |m: &Coefficients<f64>| {
            let (mut num, mut den) = (0.0, 0.0);
            for e in omniad_core::quadrature::fibonacci_sphere(300) {
                let (a, b) = (
                    m.at_direction(&e).expect("d"),
                    truth.at_direction(&e).expect("d"),
                );
                num += (a.torque - b.torque).norm_squared();
                den += b.torque.norm_squared();
            }
            (num / den).sqrt()
        };
        let with_prior = refit_final_torque(&truth, &frames, &ctx, &cfg).expect("refit");
        let (beta, six, _) = fit_torque(&frames, &ctx, &cfg, TorqueFrames::NoThrust);
        let plain = with_torque(&truth, &beta, &six).expect("plain");
        let (a, b) = (error(&with_prior), error(&plain));
        assert!(a < 0.7 * b, "C_T error with the prior {a}, plain {b}");
    }
}
