//! Runs N force+torque evaluations at degree 8 (f32) for instruction
//! counting: `valgrind --tool=callgrind target/release/examples/eval_loop 100000`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{Matrix3, Vector3};
use omniad_core::Coefficients;
use std::hint::black_box;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000);
    let mut m = Coefficients::<f32>::zeros(8, Vector3::z(), 0.58).expect("valid");
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            m.set_alpha(i, k, ((k * 7 + i * 3) % 11) as f32 * 0.01 - 0.05)
                .unwrap();
            m.set_beta(i, k, ((k * 5 + i) % 7) as f32 * 0.001).unwrap();
        }
    }
    m.set_damping(&(Matrix3::identity() * 0.02)).unwrap();
    let mut acc = 0.0f32;
    for i in 0..n {
        let v = Vector3::new(0.3 + (i % 7) as f32 * 0.01, -1.2, -3.1);
        let w = m.wrench(black_box(&v), black_box(&Vector3::new(0.5, 0.1, -0.7)), 1.2);
        acc += w.force.x + w.torque.z;
    }
    println!("{acc}");
}
