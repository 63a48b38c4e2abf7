//! The paper's fit (§6): `C*(E_k)` per frame, three-nearest-neighbour
//! interpolation (distance `|E - E_k|`) at the centres of a 32 x 16 grid
//! about the pole, SH coefficients by the convolution eqs. (11), (13) as a
//! quadrature over the grid, D by least squares, eq. (12), on K2 (spins).

use crate::fit::context::{sh_and_basis, FitContext};
use crate::fit::coverage::{cell_centre, pole_frame};
use crate::fit::damping::{matrix, omega_map, with_floor};
use crate::fit::model::RawModel;
use crate::input::recording::TakeKind;
use crate::reconstruct::forces::Sample;
use nalgebra::{SMatrix, Vector3};
use omniad_core::coefficients::COVERAGE_CELLS;
use omniad_core::sh::coeff_count;

/// Frames slower than this (m/s) are not used for `C*` (the paper's
/// airspeeds range from 1 to 10 m/s, §3).
pub const MIN_SPEED: f64 = 1.0;

/// Inverse-distance weighted mean of the 3 nearest samples' values.
fn three_nearest(
    points: &[(Vector3<f64>, Vector3<f64>)],
    e: &Vector3<f64>,
) -> Option<Vector3<f64>> {
    let mut best: [(f64, usize); 3] = [(f64::INFINITY, usize::MAX); 3];
    for (i, (d, _)) in points.iter().enumerate() {
        let dist = (e - d).norm();
        if dist < best[2].0 {
            best[2] = (dist, i);
            best.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
    }
    let (mut sum, mut wsum) = (Vector3::zeros(), 0.0);
    for (dist, i) in best {
        let Some((_, value)) = points.get(i) else {
            continue;
        };
        let w = 1.0 / dist.max(1e-9);
        sum += value * w;
        wsum += w;
    }
    (wsum > 0.0).then(|| sum / wsum)
}

/// Eqs. (11)/(13): `c^i_lm = Σ_cells (C*(E_c)·E^i_c) Y_lm(E_c) ΔS_c`.
fn convolve(
    points: &[(Vector3<f64>, Vector3<f64>)],
    ctx: &FitContext,
    degree: usize,
) -> [Vec<f64>; 3] {
    let n = coeff_count(degree);
    let mut out = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let frame = pole_frame(&ctx.pole);
    for cell in 0..COVERAGE_CELLS {
        let (e, area) = cell_centre(&frame, cell);
        let Some(c) = three_nearest(points, &e) else {
            return out;
        };
        let (y, basis) = sh_and_basis(degree, &e, &ctx.pole);
        for (coeffs, b) in out.iter_mut().zip(&basis) {
            let proj = c.dot(b) * area;
            for (a, yk) in coeffs.iter_mut().zip(&y) {
                *a += proj * yk;
            }
        }
    }
    out
}

/// Eq. (12): D from the spin frames (all frames when there are none).
fn fit_damping(samples: &[Sample], ctx: &FitContext) -> [f64; 6] {
    let spins = samples
        .iter()
        .any(|s| s.use_torque && s.kind == TakeKind::Spin);
    let c = 0.5 * ctx.air_density * ctx.reference_length.powi(5);
    let mut ata = SMatrix::<f64, 6, 6>::zeros();
    let mut atb = SMatrix::<f64, 6, 1>::zeros();
    for s in samples
        .iter()
        .filter(|s| s.use_torque && (!spins || s.kind == TakeKind::Spin))
    {
        let a = omega_map(&s.angular_velocity) * (-c * s.angular_velocity.norm());
        ata += a.transpose() * a;
        atb += a.transpose() * s.torque;
    }
    let x = ata
        .cholesky()
        .map(|ch| ch.solve(&atb))
        .unwrap_or_else(SMatrix::zeros);
    let raw: [f64; 6] = std::array::from_fn(|i| x[i]);
    with_floor(&raw, 1e-3)
}

/// The paper's fit.
pub fn fit(samples: &[Sample], ctx: &FitContext, degree: usize) -> RawModel {
    let damping = fit_damping(samples, ctx);
    let d = matrix(&damping);
    let l = ctx.reference_length;
    let drops = samples
        .iter()
        .any(|s| s.use_force && s.kind == TakeKind::Drop);
    let frames: Vec<&Sample> = samples
        .iter()
        .filter(|s| {
            s.use_force && (!drops || s.kind == TakeKind::Drop) && s.velocity.norm() >= MIN_SPEED
        })
        .collect();
    let mut force = Vec::with_capacity(frames.len());
    let mut torque = Vec::with_capacity(frames.len());
    for s in &frames {
        let speed = s.velocity.norm();
        let q = 0.5 * ctx.air_density * speed * speed;
        let e = s.velocity / speed;
        force.push((e, s.force / (q * l * l)));
        if s.use_torque {
            let damp = d
                * s.angular_velocity
                * (0.5 * ctx.air_density * s.angular_velocity.norm() * l.powi(5));
            torque.push((e, (s.torque + damp) / (q * l.powi(3))));
        }
    }
    RawModel {
        alpha: convolve(&force, ctx, degree),
        beta: convolve(&torque, ctx, degree),
        damping,
        spin_coupling: None,
        gravity_coupling: None,
        extension_test: None,
        smoothing: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::synth::{truth_model, ObjectSpec, SynthObject};

    #[test]
    fn paper_fit_approximates_a_dense_exact_sample() {
        let spec = ObjectSpec::of(SynthObject::Plate);
        let truth = truth_model(&spec, 4).expect("model");
        let ctx = FitContext {
            air_density: 1.2,
            reference_length: truth.reference_length(),
            pole: truth.pole(),
        };
        let mut rng = Rng::new(9);
        let mut frames = Vec::new();
        for (i, kind) in (0..6000).map(|i| {
            (
                i,
                if i % 4 == 0 {
                    TakeKind::Spin
                } else {
                    TakeKind::Drop
                },
            )
        }) {
            let velocity = rng.direction() * rng.range(2.0, 6.0);
            let angular_velocity = rng.direction() * rng.range(0.0, 15.0);
            let w = truth.wrench(&velocity, &angular_velocity, 1.2);
            frames.push(Sample {
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
            });
        }
        let model = crate::fit::model::with_raw(&truth, &fit(&frames, &ctx, 4)).expect("model");
        let (mut num, mut den) = (0.0, 0.0);
        for e in omniad_core::quadrature::fibonacci_sphere(200) {
            let (a, b) = (
                model.at_direction(&e).expect("dir"),
                truth.at_direction(&e).expect("dir"),
            );
            num += (a.force - b.force).norm_squared();
            den += b.force.norm_squared();
        }
        // Nearest-neighbour interpolation and a coarse quadrature: a few %.
        assert!(
            (num / den).sqrt() < 0.1,
            "relative error {}",
            (num / den).sqrt()
        );
    }
}
