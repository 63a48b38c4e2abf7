//! How rare is a seed's lull? (issue 17, stop 20: why every flying design
//! crashed on seed 10.) `kite fly`'s along-wind gust `u(t)` ([`Wind`],
//! G = 1 m/s at 5 m/s mean wind) sampled every 0.1 s over 0-60 s on seeds
//! 1..=N: per seed the lowest `u`, the lowest 4 s and 8 s running means
//! (a kite sinks when the wind stays low for its pendulum's time, a few
//! seconds, not at a single instant), and the lowest `u` over the judged
//! 30-60 s. Prints each statistic's mean and lower quantiles over the N
//! seeds, the values of seeds 1-20, and the fraction of seeds whose value
//! is at least as extreme as seed 10's.
//! `cargo run --release -p omniad-kite --example lulls -- 5000`

use omniad_kite::wind::Wind;

const NAMES: [&str; 4] = [
    "lowest u",
    "lowest 4 s mean",
    "lowest 8 s mean",
    "lowest u, 30-60 s",
];

/// The four statistics of one seed, m/s (gust only, the mean removed).
fn lulls(seed: u64) -> [f64; 4] {
    let wind = Wind::new(5.0, 1.0, seed);
    let u: Vec<f64> = (0..=600)
        .map(|i| wind.at(i as f64 * 0.1).x - wind.mean.x)
        .collect();
    let running_min = |n: usize| {
        u.windows(n)
            .map(|w| w.iter().sum::<f64>() / n as f64)
            .fold(f64::INFINITY, f64::min)
    };
    let judged = u.iter().skip(300).copied().fold(f64::INFINITY, f64::min);
    let lowest = u.iter().copied().fold(f64::INFINITY, f64::min);
    [lowest, running_min(40), running_min(80), judged]
}

fn main() -> anyhow::Result<()> {
    let n: u64 = std::env::args().nth(1).map_or(Ok(5000), |s| s.parse())?;
    anyhow::ensure!(n >= 20, "give at least 20 seeds");
    let all: Vec<[f64; 4]> = (1..=n).map(lulls).collect();
    for (k, name) in NAMES.iter().enumerate() {
        let mut v: Vec<f64> = all.iter().map(|s| s[k]).collect();
        let seed10 = v[9];
        let listed: Vec<String> = (1..=20).map(|s| format!("{s}:{:+.2}", v[s - 1])).collect();
        v.sort_by(f64::total_cmp);
        let q = |p: f64| v[((p * n as f64) as usize).min(v.len() - 1)];
        let mean = v.iter().sum::<f64>() / n as f64;
        let rank = v.iter().filter(|&&x| x <= seed10).count() as f64 / n as f64;
        println!(
            "{name:<18} mean {mean:+.2}  1% {:+.2}  5% {:+.2}  10% {:+.2}  median {:+.2} m/s; \
             seed 10 {seed10:+.2} ({:.1} % of seeds as low)",
            q(0.01),
            q(0.05),
            q(0.10),
            q(0.5),
            100.0 * rank
        );
        println!("  seeds 1-20: {}", listed.join(" "));
    }
    Ok(())
}
