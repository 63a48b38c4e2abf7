//! Force+torque evaluation at N = 8 (f32, f64), one body and eight
//! (batch, one per lane), and one RK4 step (one body, eight).
//! Run: `cargo bench -p omniad-core --bench aero`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nalgebra::Vector3;
use omniad_core::batch::{rk4_lanes, StateLanes};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Environment, LaneScalar};

/// The model and inputs of `omniad bench` (one definition for both).
#[path = "../../bench/src/model.rs"]
mod model;
use model::{body, lanes, model, moving};

fn bench_eval<T: LaneScalar>(c: &mut Criterion, name: &str) {
    let m = model::<T>();
    let v = Vector3::new(T::of_f64(0.3), T::of_f64(-1.2), T::of_f64(-3.1));
    let w = Vector3::new(T::of_f64(0.5), T::of_f64(0.1), T::of_f64(-0.7));
    let rho = T::of_f64(1.2);
    c.bench_function(name, |b| {
        b.iter(|| m.wrench(black_box(&v), black_box(&w), rho))
    });
}

/// The parts of one evaluation: the SH sums alone (eqs. 7-8 before the
/// basis) and the direction coefficients (sums + basis).
fn bench_parts(c: &mut Criterion) {
    let m = model::<f32>();
    let e = Vector3::new(0.3f32, -1.2, -3.1).normalize();
    c.bench_function("sh_sums_n8_f32", |b| b.iter(|| m.sh_sums(black_box(&e))));
    c.bench_function("direction_coefficients_n8_f32", |b| {
        b.iter(|| m.at_unit_direction(black_box(&e)))
    });
}

fn bench_rk4(c: &mut Criterion) {
    let (m, body, env, s) = (model::<f64>(), body(), Environment::standard(), moving());
    let forces = AirForces {
        model: &m,
        environment: env,
    };
    c.bench_function("rk4_step_n8_f64", |b| {
        b.iter(|| rk4_step(&body, &env, &forces, 0.0, black_box(1e-3), black_box(&s)))
    });
}

/// Eight bodies per call (one per lane): divide by 8 for the per-body
/// figure.
fn bench_batch<T: LaneScalar>(c: &mut Criterion, name: &str) {
    let m = model::<T>();
    let (v, w) = (
        lanes::<T>([0.3, -1.2, -3.1], 0.05),
        lanes::<T>([0.5, 0.1, -0.7], 0.02),
    );
    c.bench_function(name, |b| {
        b.iter(|| m.wrench_lanes(black_box(&v), black_box(&w), T::of_f64(1.2)))
    });
}

/// One RK4 step of eight bodies (f64), one per lane.
fn bench_rk4_lanes(c: &mut Criterion) {
    let (m, body, env) = (model::<f64>(), body(), Environment::standard());
    let mut group = [StateLanes::splat(&moving())];
    c.bench_function("rk4_step_8_bodies_n8_f64", |b| {
        b.iter(|| {
            let mut l = group;
            rk4_lanes(&m, &body, &env, black_box(1e-3), 1, &mut l);
            group = black_box(l);
        })
    });
}

fn benches(c: &mut Criterion) {
    bench_batch::<f32>(c, "force_torque_8_bodies_n8_f32");
    bench_batch::<f64>(c, "force_torque_8_bodies_n8_f64");
    bench_rk4_lanes(c);
    bench_eval::<f32>(c, "force_torque_n8_f32");
    bench_eval::<f64>(c, "force_torque_n8_f64");
    bench_parts(c);
    bench_rk4(c);
}

criterion_group!(aero, benches);
criterion_main!(aero);
