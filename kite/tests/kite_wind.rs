//! The gust model: seeded, zero-mean gusts with the documented strengths.

use omniad_kite::wind::{Wind, RATIOS};

#[test]
fn gusts_have_the_documented_statistics() {
    let g = 1.5;
    let w = Wind::new(5.0, g, 42);
    let n = 200_000;
    let dt = 0.05; // 10 000 s: many periods of the slowest mode
    let mut sum = [0.0; 3];
    let mut sq = [0.0; 3];
    for i in 0..n {
        let v = w.at(i as f64 * dt) - w.mean;
        for k in 0..3 {
            sum[k] += v[k];
            sq[k] += v[k] * v[k];
        }
    }
    for k in 0..3 {
        let mean = sum[k] / n as f64;
        let std = (sq[k] / n as f64 - mean * mean).sqrt();
        assert!(mean.abs() < 0.1 * g, "component {k} mean {mean}");
        assert!(
            (std - g * RATIOS[k]).abs() < 0.1 * g * RATIOS[k],
            "component {k} std {std}"
        );
    }
    // Same seed, same wind; other seed, other wind; no gust, steady.
    assert_eq!(Wind::new(5.0, g, 42).at(3.7), w.at(3.7));
    assert_ne!(Wind::new(5.0, g, 43).at(3.7), w.at(3.7));
    assert_eq!(Wind::new(5.0, 0.0, 1).at(12.0), w.mean);
}
