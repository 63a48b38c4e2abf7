//! Issue 17, stop 20: the four designs after Fig. 15 are `stable` and fly
//! 60 s in 1 m/s gusts on every seed of 1-12, seed 10 included: its
//! along-wind gust stays ~2.1 m/s below the mean for 8 s (t = 25-33 s, the
//! lowest 4 % of 8 s lulls of the gust model; `examples/lulls.rs`), below
//! the stop-19 designs' flying wind, and they sank under 15° of line
//! elevation. The stop-19 files are kept as fixtures: one of them still
//! sinks there, so the test would catch the lull going missing.

mod common;

use omniad_kite::check::{self, Verdict};
use omniad_kite::flight::{self, FlightOptions, Outcome};

fn fly(design: &omniad_kite::Design, seed: u64) -> flight::FlightReport {
    let opts = FlightOptions {
        seconds: 60.0,
        gust: 1.0,
        seed,
        ..FlightOptions::default()
    };
    flight::fly(design, &opts).unwrap()
}

#[test]
fn the_fig15_designs_are_stable_and_fly_on_seeds_1_to_12() {
    let mut crashed = Vec::new();
    for name in ["fig15-a", "fig15-b", "fig15-c", "fig15-d"] {
        let design = common::kite(name);
        let c = check::check(&design, None).unwrap();
        assert_eq!(c.verdict, Verdict::Stable, "{}", check::render(&c));
        for seed in 1..=12 {
            let f = fly(&design, seed);
            if f.outcome != Outcome::Flies {
                crashed.push(format!("{name} seed {seed}: {}", f.reason));
            }
        }
    }
    assert!(crashed.is_empty(), "{crashed:?}");
}

#[test]
fn the_stop_19_design_sinks_in_seed_10s_lull() {
    let f = fly(&common::fixture("fig15-d-stop19"), 10);
    assert_eq!(f.outcome, Outcome::Crashes, "{}", flight::render(&f));
    // It sinks in the lull (the line falls, taut, without turning), not by
    // spin or a ground strike.
    assert!(
        f.crash_time.is_none() && f.max_spin < 1.0,
        "{}",
        flight::render(&f)
    );
    assert!(f.min_elevation_deg < flight::MIN_ELEVATION_DEG);
    let low = f
        .trace
        .iter()
        .min_by(|a, b| a.elevation_deg.total_cmp(&b.elevation_deg))
        .unwrap();
    assert!(
        (25.0..40.0).contains(&low.t) && low.wind[0] < 4.0,
        "lowest line at {:.1} s in {:.2} m/s",
        low.t,
        low.wind[0]
    );
}
