//! Force+torque evaluation at N = 8 (f32, f64), one body and eight
//! (batch, one per lane), and one RK4 step (one body, eight).
//! Run: `cargo bench -p omniad-core --bench aero`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix3, Vector3};
use omniad_core::batch::{rk4_lanes, StateLanes};
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::AirForces;
use omniad_core::{Coefficients, Environment, LaneScalar, RigidBody, State};

/// A degree-8 model with every coefficient non-zero (values are arbitrary
/// but deterministic: the cost does not depend on them).
fn model<T: LaneScalar>() -> Coefficients<T> {
    let mut m =
        Coefficients::zeros(8, Vector3::z(), T::of_f64(0.58)).unwrap_or_else(|_| unreachable());
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            let v = T::of_f64(((k * 7 + i * 3) % 11) as f64 * 0.01 - 0.05);
            let _ = m.set_alpha(i, k, v);
            let _ = m.set_beta(i, k, v * T::of_f64(0.1));
        }
    }
    let _ = m.set_damping(&(Matrix3::identity() * T::of_f64(0.02)));
    m
}

fn unreachable() -> ! {
    std::process::abort()
}

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
    let m = model::<f64>();
    let body = RigidBody::new(
        0.048,
        Matrix3::from_diagonal(&Vector3::new(1.0e-3, 3.6e-4, 1.36e-3)),
    )
    .unwrap_or_else(|_| unreachable());
    let env = Environment::standard();
    let forces = AirForces {
        model: &m,
        environment: env,
    };
    let mut s = State::at_rest(Vector3::new(0.0, 0.0, 6.0));
    s.velocity = Vector3::new(0.2, 0.1, -2.0);
    s.angular_velocity = Vector3::new(1.0, 0.5, -0.3);
    c.bench_function("rk4_step_n8_f64", |b| {
        b.iter(|| rk4_step(&body, &env, &forces, 0.0, black_box(1e-3), black_box(&s)))
    });
}

/// Eight bodies per call (one per lane): divide by 8 for the per-body
/// figure.
fn bench_batch<T: LaneScalar>(c: &mut Criterion, name: &str) {
    let m = model::<T>();
    let lanes = |base: [f64; 3], step: f64| {
        base.map(|b| {
            omniad_core::lanes::Lanes(std::array::from_fn(|i| T::of_f64(b + step * i as f64)))
        })
    };
    let v = lanes([0.3, -1.2, -3.1], 0.05);
    let w = lanes([0.5, 0.1, -0.7], 0.02);
    c.bench_function(name, |b| {
        b.iter(|| m.wrench_lanes(black_box(&v), black_box(&w), T::of_f64(1.2)))
    });
}

/// One RK4 step of eight bodies (f64), one per lane.
fn bench_rk4_lanes(c: &mut Criterion) {
    let m = model::<f64>();
    let body = RigidBody::new(
        0.048,
        Matrix3::from_diagonal(&Vector3::new(1.0e-3, 3.6e-4, 1.36e-3)),
    )
    .unwrap_or_else(|_| unreachable());
    let env = Environment::standard();
    let mut s = State::at_rest(Vector3::new(0.0, 0.0, 6.0));
    s.velocity = Vector3::new(0.2, 0.1, -2.0);
    s.angular_velocity = Vector3::new(1.0, 0.5, -0.3);
    let mut lanes = [StateLanes::splat(&s)];
    c.bench_function("rk4_step_8_bodies_n8_f64", |b| {
        b.iter(|| {
            let mut l = lanes;
            rk4_lanes(&m, &body, &env, black_box(1e-3), 1, &mut l);
            lanes = black_box(l);
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
