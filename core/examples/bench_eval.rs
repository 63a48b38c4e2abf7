//! Force + torque evaluation time at N = 8, robust to a busy machine: the
//! minimum and the median over many short batches (the minimum is what
//! the code costs when nothing else interrupts it). Prints JSON.
//!
//! `cargo run --release -p omniad-core --example bench_eval [BATCHES]`
#![allow(clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{Matrix3, Vector3};
use omniad_core::lanes::{Lanes, LANES};
use omniad_core::{Coefficients, LaneScalar};
use std::hint::black_box;
use std::time::Instant;

/// Same model as `benches/aero.rs`: every coefficient non-zero.
fn model<T: LaneScalar>(portable: bool) -> Coefficients<T> {
    let mut m = Coefficients::zeros(8, Vector3::z(), T::of_f64(0.58)).expect("valid");
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            let v = T::of_f64(((k * 7 + i * 3) % 11) as f64 * 0.01 - 0.05);
            m.set_alpha(i, k, v).unwrap();
            m.set_beta(i, k, v * T::of_f64(0.1)).unwrap();
        }
    }
    m.set_damping(&(Matrix3::identity() * T::of_f64(0.02)))
        .unwrap();
    m.set_portable(portable);
    m
}

/// (minimum, median) nanoseconds per evaluation.
fn time<T: LaneScalar>(m: &Coefficients<T>, batches: usize) -> (f64, f64) {
    const PER_BATCH: usize = 2_000;
    let v = Vector3::new(T::of_f64(0.3), T::of_f64(-1.2), T::of_f64(-3.1));
    let w = Vector3::new(T::of_f64(0.5), T::of_f64(0.1), T::of_f64(-0.7));
    let mut per_eval: Vec<f64> = (0..batches)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..PER_BATCH {
                black_box(m.wrench(black_box(&v), black_box(&w), T::of_f64(1.2)));
            }
            start.elapsed().as_secs_f64() * 1e9 / PER_BATCH as f64
        })
        .collect();
    per_eval.sort_by(f64::total_cmp);
    (per_eval[0], per_eval[per_eval.len() / 2])
}

/// (minimum, median) nanoseconds per body of the batch (eight bodies per
/// call, one per lane).
fn time_batch<T: LaneScalar>(m: &Coefficients<T>, batches: usize) -> (f64, f64) {
    const PER_BATCH: usize = 250;
    let lanes = |base: [f64; 3], step: f64| {
        base.map(|b| Lanes(std::array::from_fn(|i| T::of_f64(b + step * i as f64))))
    };
    let (v, w) = (
        lanes([0.3, -1.2, -3.1], 0.05),
        lanes([0.5, 0.1, -0.7], 0.02),
    );
    let mut per_body: Vec<f64> = (0..batches)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..PER_BATCH {
                black_box(m.wrench_lanes(black_box(&v), black_box(&w), T::of_f64(1.2)));
            }
            start.elapsed().as_secs_f64() * 1e9 / (PER_BATCH * LANES) as f64
        })
        .collect();
    per_body.sort_by(f64::total_cmp);
    (per_body[0], per_body[per_body.len() / 2])
}

fn main() {
    let batches: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000);
    let rows = [
        ("f32", time(&model::<f32>(false), batches)),
        ("f32_portable", time(&model::<f32>(true), batches)),
        ("f64", time(&model::<f64>(false), batches)),
        (
            "f32_batch_per_body",
            time_batch(&model::<f32>(false), batches),
        ),
        (
            "f64_batch_per_body",
            time_batch(&model::<f64>(false), batches),
        ),
    ];
    let body: Vec<String> = rows
        .iter()
        .map(|(name, (min, median))| {
            format!("\"{name}\": {{\"min_ns\": {min:.1}, \"median_ns\": {median:.1}}}")
        })
        .collect();
    println!(
        "{{\"benchmark\": \"force_torque_n8\", \"batches\": {batches}, \"evaluations_per_batch\": 2000, {}}}",
        body.join(", ")
    );
}
