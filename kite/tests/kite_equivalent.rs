//! Issue 17, stop 19: the gust response at the gusts' amplitude. The
//! small-gust linearisation over-predicts the line's swing at `kite fly`'s
//! 1 m/s gusts; the equivalent (statistical) linearisation
//! (`gusts::response_to`, `kite/src/equivalent.rs`) must size it from the
//! model: the same as the linear one for small gusts, and nearer the
//! flown swing than the linear one at 1 m/s.

mod common;

use omniad_kite::flight::{self, FlightOptions};
use omniad_kite::spec::StringSpec;
use omniad_kite::{check, gusts, launch, linearise};

/// fig15-a (the stop-19 file, a fixture since stop 20) with its string
/// 10 cm higher on the eq. (16) line (a variant the verdict refused on the
/// linear swing, though it flies on most seeds).
fn fig15_a_high() -> omniad_kite::Design {
    let mut d = common::fixture("fig15-a-stop19");
    let offset = check::check(&d, None).unwrap().attachment_offset;
    d.spec.string = StringSpec {
        gamma: None,
        offset: Some(offset + 0.10),
        length: d.spec.string.length,
    };
    d
}

/// The predicted line-elevation σ (linear, equivalent) at gust strength `g`.
fn predicted(d: &omniad_kite::Design, g: f64) -> (f64, f64, Option<usize>) {
    let steady = launch::launch(
        d,
        &FlightOptions {
            gust: 0.0,
            ..FlightOptions::default()
        },
    )
    .unwrap();
    let eq = *steady.state();
    let a = linearise::state_matrix(&steady, &eq);
    let b = linearise::input_matrix(&steady, &eq);
    let r = gusts::response_to(&steady, &eq, &a, &b, None, g);
    (
        r.sigma_elevation_linear_deg,
        r.sigma_elevation_deg,
        r.equivalent_iterations,
    )
}

#[test]
fn small_gusts_keep_the_linear_response() {
    let d = fig15_a_high();
    let (linear, equivalent, iterations) = predicted(&d, 0.01);
    assert!(iterations.is_some());
    assert!(
        (equivalent - linear).abs() < 1e-3 * linear,
        "{linear} vs {equivalent}"
    );
}

#[test]
fn the_swing_at_one_metre_per_second_is_nearer_the_flown_one() {
    let d = fig15_a_high();
    let (linear, equivalent, iterations) = predicted(&d, 1.0);
    assert!(iterations.is_some());
    // The flights' swing: RMS of the line elevation about rest over the
    // judged second half, pooled over seeds 1-3.
    let rest = {
        let steady = launch::launch(
            &d,
            &FlightOptions {
                gust: 0.0,
                ..FlightOptions::default()
            },
        )
        .unwrap();
        steady.line().elevation_deg(steady.state())
    };
    let (mut sum, mut n) = (0.0, 0usize);
    for seed in 1..=3 {
        let opts = FlightOptions {
            seed,
            ..FlightOptions::default()
        };
        let f = flight::fly(&d, &opts).unwrap();
        for s in f.trace.iter().filter(|s| s.t >= opts.seconds / 2.0) {
            sum += (s.elevation_deg - rest).powi(2);
            n += 1;
        }
    }
    let flown = (sum / n.max(1) as f64).sqrt();
    assert!(
        (equivalent - flown).abs() < (linear - flown).abs(),
        "linear {linear:.2}, equivalent {equivalent:.2}, flown {flown:.2}"
    );
    assert!(equivalent < linear, "{linear} vs {equivalent}");
}
