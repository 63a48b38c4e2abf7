//! Issue 17: the verdict's gust test. `fig15-b` with its string 10 cm
//! lower on the eq. (16) line hangs at about 23° line elevation with every
//! mode decaying (the modes alone call it stable), but the linear response
//! to `kite fly`'s 1 m/s gusts takes the line below the flight's 15°: the
//! verdict is `gust_sensitive`, and the 60 s gusty flight indeed does not
//! stay up (seeds 1-3 all crash; BENCHMARKS, issue 17). The file itself
//! keeps its margin and flies. (The fig15 kites here are the stop-19
//! files, kept as fixtures: the bundled ones are 1.5x them since stop 20.)

mod common;

use omniad_kite::check::{self, Verdict};
use omniad_kite::flight::{self, FlightOptions, Outcome, MIN_ELEVATION_DEG};
use omniad_kite::spec::StringSpec;

/// The string attached `offset` (m) along the eq. (16) line.
fn move_string(design: &mut omniad_kite::Design, offset: f64) {
    design.spec.string = StringSpec {
        gamma: None,
        offset: Some(offset),
        length: design.spec.string.length,
    };
}

#[test]
fn a_low_hanging_variant_is_gust_sensitive_and_crashes() {
    let mut design = common::fixture("fig15-b-stop19");
    let file = check::check(&design, None).unwrap();
    let g = file.modes.gusts.as_ref().expect("file: every mode decays");
    assert!(g.ok && g.min_elevation_deg > MIN_ELEVATION_DEG, "{g:?}");
    assert_eq!(file.verdict, Verdict::Stable);

    move_string(&mut design, file.attachment_offset - 0.10);
    let c = check::check(&design, None).unwrap();
    assert!(c.modes.stable, "{}", check::render(&c));
    let g = c.modes.gusts.as_ref().expect("every mode decays");
    assert!(!g.ok && g.margin < 0.0, "{g:?}");
    assert!(g.min_elevation_deg < MIN_ELEVATION_DEG, "{g:?}");
    assert_eq!(c.verdict, Verdict::GustSensitive, "{}", check::render(&c));
    let f = flight::fly(
        &design,
        &FlightOptions {
            seed: 2,
            ..FlightOptions::default()
        },
    )
    .unwrap();
    assert_eq!(f.outcome, Outcome::Crashes, "{}", flight::render(&f));
}

/// `fig15-d` with its string 10 cm lower hangs at 24° with every mode
/// decaying, but its equilibrium falls with the wind speed (20° at 5.5
/// m/s, 13° at 6) and folds, and its gusty flight dives into the ground.
/// Either the gust response's extremes or the discrete gusts must refuse
/// it (which one depends on the verdict's statistic, `gusts` module doc);
/// that the discrete lull alone refuses it is `strong_gust`'s unit test.
/// The file itself passes both.
#[test]
fn a_kite_that_dives_in_a_strong_gust_is_gust_sensitive_and_crashes() {
    let mut design = common::fixture("fig15-d-stop19");
    let file = check::check(&design, None).unwrap();
    let strong = file
        .modes
        .strong_gust
        .as_ref()
        .expect("linear gust test passes");
    assert!(strong.ok, "{}", check::render(&file));
    assert_eq!(file.verdict, Verdict::Stable);

    move_string(&mut design, file.attachment_offset - 0.10);
    let c = check::check(&design, None).unwrap();
    let report = check::render(&c);
    assert!(c.modes.stable, "{report}");
    let low = c.modes.gusts.as_ref().is_some_and(|g| !g.ok);
    let strong = c
        .modes
        .strong_gust
        .as_ref()
        .is_some_and(|g| !g.ok && g.motion.elevation_deg[0] < MIN_ELEVATION_DEG);
    assert!(low || strong, "{report}");
    assert_eq!(c.verdict, Verdict::GustSensitive, "{report}");
    let f = flight::fly(&design, &FlightOptions::default()).unwrap();
    assert_eq!(f.outcome, Outcome::Crashes, "{}", flight::render(&f));
}

/// The optimiser's winged box (`tests/fixtures/winged-box-optimised.toml`,
/// BENCHMARKS issue 17, kv2) rests 42° to the side of the wind with every
/// mode damped (ζ ≥ 0.19) and a linear gust response inside the limits,
/// and a stronger along-wind gust leaves it at rest; but in a lull its
/// line tension falls, it yaws, the line goes slack and it rolls over at
/// 2-3 rad/s. The discrete-gust test flies lulls and the crosswind and
/// vertical components too: `gust_sensitive`, and the gusty flight indeed
/// spins out.
#[test]
fn a_kite_that_rolls_over_in_a_lull_is_gust_sensitive_and_crashes() {
    let path = common::repo().join("kite/tests/fixtures/winged-box-optimised.toml");
    let design = omniad_kite::Design::load(&path, &common::library()).unwrap();
    let c = check::check(&design, None).unwrap();
    let report = check::render(&c);
    assert!(c.modes.stable, "{report}");
    assert!(c.modes.gusts.as_ref().is_some_and(|g| g.ok), "{report}");
    let strong = c.modes.strong_gust.as_ref().expect("discrete gusts flown");
    assert!(!strong.ok, "{report}");
    // Not the stronger along-wind gust the test used to fly alone.
    assert!(
        strong.component != "along-wind" || strong.amplitude < 0.0,
        "{report}"
    );
    assert_eq!(c.verdict, Verdict::GustSensitive, "{report}");
    let f = flight::fly(&design, &FlightOptions::default()).unwrap();
    assert_eq!(f.outcome, Outcome::Crashes, "{}", flight::render(&f));
}

/// Issue 17, stop 21: fig15-c (the bundled file) with its string 10 cm
/// lower rests 21° to the side of the wind with every mode decaying, and
/// its gust responses, linear and flown through the discrete gusts, stay
/// inside the limits (lowest line 32° and 28.5°); yet its gusty flights
/// dive into the ground on seeds 1-3. Its equilibrium branch ends (a
/// fold) 1.27 m/s above the mean wind, inside the longest gust's
/// +1.32 m/s: the discrete-gust test refuses it for that. The file's
/// branch reaches every gust's peak wind.
#[test]
fn a_kite_whose_equilibrium_ends_inside_the_gusts_is_gust_sensitive() {
    let mut design = common::kite("fig15-c");
    let file = check::check(&design, None).unwrap();
    assert_eq!(file.verdict, Verdict::Stable, "{}", check::render(&file));
    let g = file
        .modes
        .strong_gust
        .as_ref()
        .expect("discrete gusts flown");
    assert!(g.ok && g.branch_ends.is_none(), "{g:?}");

    move_string(&mut design, file.attachment_offset - 0.10);
    let c = check::check(&design, None).unwrap();
    assert!(c.modes.stable, "{}", check::render(&c));
    let g = c.modes.strong_gust.as_ref().expect("discrete gusts flown");
    let ends = g.branch_ends.expect("the branch ends");
    assert!(!g.ok && g.component == "along-wind", "{g:?}");
    assert!(ends > 0.5 && ends < g.amplitude, "{g:?}");
    assert!(g.motion.inside_limits, "the flown gust alone passes: {g:?}");
    assert_eq!(c.verdict, Verdict::GustSensitive, "{}", check::render(&c));
    let f = flight::fly(&design, &FlightOptions::default()).unwrap();
    assert_eq!(f.outcome, Outcome::Crashes, "{}", flight::render(&f));
}
