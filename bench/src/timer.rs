//! The minimum over batches: on a shared machine the minimum of many short
//! batches is the code's cost without interference (BENCHMARKS.md).

use std::time::Instant;

/// Seconds per call of `f`: the minimum over `batches` batches of `calls`
/// calls each.
pub fn per_call(batches: usize, calls: usize, mut f: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..batches {
        let t = Instant::now();
        for _ in 0..calls {
            f();
        }
        best = best.min(t.elapsed().as_secs_f64() / calls as f64);
    }
    best
}
