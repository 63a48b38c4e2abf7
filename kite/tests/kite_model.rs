//! One kite model: every bundled kite file survives the serialiser
//! (what the TUI saves loads back to the same spec), and the flight
//! stepper the TUI advances frame by frame is `kite fly`'s batch run.

mod common;

use omniad_kite::flight::{self, Flight, FlightOptions};
use omniad_kite::KiteSpec;

fn bundled() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(common::repo().join("data/kites"))
        .expect("data/kites")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    files
}

#[test]
fn every_bundled_kite_round_trips_through_the_serialiser() {
    let dir = std::env::temp_dir().join(format!("omniad-kite-model-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for path in bundled() {
        let spec = KiteSpec::load(&path).expect("bundled kite loads");
        let text = spec.to_toml().expect("serialises");
        assert_eq!(KiteSpec::parse(&text).expect("reads back"), spec, "{text}");
        let out = dir.join("k.toml");
        spec.save(&out).expect("saved");
        assert_eq!(KiteSpec::load(&out).expect("loads"), spec);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn stepping_the_flight_is_the_batch_run() {
    let design = common::kite("box-classic");
    let opts = FlightOptions {
        seconds: 2.0,
        ..FlightOptions::default()
    };
    let report = flight::fly(&design, &opts).expect("flies");
    let mut f = Flight::new(design, &opts).expect("starts");
    f.advance_to(opts.seconds - 1e-9);
    let last = report.trace.last().expect("trace");
    let now = f.sample();
    assert_eq!(now.t, last.t);
    assert_eq!(now.position, last.position);
    assert_eq!(now.tension, last.tension);
}
