//! Issue 17: a growing mode that saturates. `box-three-cell` pitched 5°
//! nose-up has a pitch-pendulum mode growing at +0.16/s (the nonlinear
//! flight grows at the same rate), but the growth stops in a small limit
//! cycle well inside the flight's limits and the kite flies on seeds 1-3:
//! the verdict's dynamic test passes, with the cycle reported. The classic box
//! kite's roll-yaw flutter saturates too, but turning faster than the
//! flight's `MAX_SPIN`: it stays `dynamically_unstable` and crashes.

mod common;

use omniad_kite::check::{self, Verdict};
use omniad_kite::flight::{self, FlightOptions, Outcome, MAX_SPIN, MIN_ELEVATION_DEG};
use omniad_kite::spec::StringSpec;

#[test]
fn a_growing_mode_that_saturates_inside_the_limits_flies() {
    let mut design = common::kite("box-three-cell");
    let offset = check::check(&design, None).unwrap().attachment_offset;
    design.spec.orientation[1] += 5.0;
    design.spec.string = StringSpec {
        gamma: None,
        offset: Some(offset),
        length: design.spec.string.length,
    };
    let c = check::check(&design, None).unwrap();
    let report = check::render(&c);
    assert!(
        !c.modes.stable && c.modes.max_growth_rate > 0.05,
        "{report}"
    );
    let cycle = c.modes.limit_cycle.as_ref().expect("a limit cycle");
    assert!(cycle.inside_limits, "{report}");
    assert!(cycle.elevation_deg[0] > MIN_ELEVATION_DEG && cycle.max_spin < MAX_SPIN);
    assert!(c.modes.bounded && c.modes.gusts.is_some(), "{report}");
    // The dynamic test passes; the gust test then decides. This variant
    // flies on 9 of seeds 1-12 but all three of a triple only on 1-3
    // (BENCHMARKS, issue 17, kv2), so whether the gust test passes it
    // depends on the verdict's statistic: `stable` or `gust_sensitive`.
    assert!(
        matches!(c.verdict, Verdict::Stable | Verdict::GustSensitive),
        "{report}"
    );
    let f = flight::fly(&design, &FlightOptions::default()).unwrap();
    assert_eq!(f.outcome, Outcome::Flies, "{}", flight::render(&f));
}

#[test]
fn a_flutter_that_saturates_spinning_is_dynamically_unstable() {
    let c = check::check(&common::kite("box-classic"), None).unwrap();
    let report = check::render(&c);
    let cycle = c.modes.limit_cycle.as_ref().expect("a limit cycle");
    assert!(
        !cycle.inside_limits && cycle.max_spin > MAX_SPIN,
        "{report}"
    );
    assert!(!c.modes.bounded && c.modes.gusts.is_none(), "{report}");
    assert_eq!(c.verdict, Verdict::DynamicallyUnstable, "{report}");
}
