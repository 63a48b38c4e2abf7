//! One kite model: every bundled kite file survives the serialiser
//! (what the TUI saves loads back to the same spec), and the flight
//! stepper the TUI advances frame by frame is `kite fly`'s batch run.

mod common;

use omniad_kite::flight::{self, FlightOptions};
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
        // Rod ends are inline tables, one `[[rod]]` per rod, as the
        // bundled files write them (not `[rod.from]` sub-tables).
        assert!(!text.contains("[rod."), "{text}");
        assert_eq!(text.matches("[[rod]]").count(), spec.rods.len(), "{text}");
        assert_eq!(text.matches("\nfrom = ").count(), spec.rods.len(), "{text}");
        let out = dir.join("k.toml");
        spec.save(&out).expect("saved");
        assert_eq!(KiteSpec::load(&out).expect("loads"), spec);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn edges_points_diameters_and_awkward_names_round_trip() {
    let text = r#"
name = "t \"q\" = 1"
orientation = [0.0, 40.0, 0.0]

[[primitive]]
name = "a \"cell\""
kind = "box"
size = [0.3, 0.3, 0.3]
rotation = [1e-17, -33.333333333333336, 179.99999999999997]

[[primitive]]
name = "b"
kind = "plate"
size = [0.3, 0.4, 0.0]
position = [0.5, 0.0, 0.0]

[[rod]]
from = { primitive = "a \"cell\"", corner = "+x+y+z" }
to = { primitive = "b", edge = "-x", at = 0.25 }
diameter = 0.003

[[rod]]
from = [0.15, 0.15, 0.15]
to = { primitive = "b", corner = "-x-y" }
"#;
    let spec = KiteSpec::parse(text).expect("parses");
    let written = spec.to_toml().expect("writes");
    assert!(!written.contains("[rod."), "{written}");
    assert!(written.contains("from = [0.15, 0.15, 0.15]"), "{written}");
    assert!(written.contains("diameter = 0.003"), "{written}");
    assert_eq!(
        KiteSpec::parse(&written).expect("reads back"),
        spec,
        "{written}"
    );
}

#[test]
fn stepping_the_flight_is_the_batch_run() {
    let design = common::kite("box-classic");
    let opts = FlightOptions {
        seconds: 2.0,
        ..FlightOptions::default()
    };
    let report = flight::fly(&design, &opts).expect("flies");
    // Launched as `fly` launches it (at rest in the wind at t = 0; the
    // file's attitude is box-classic's mean-wind equilibrium, which the
    // launch leaves for the one in seed 1's gust).
    let mut f = omniad_kite::launch::launch(&design, &opts).expect("starts");
    f.advance_to(opts.seconds - 1e-9);
    let last = report.trace.last().expect("trace");
    let now = f.sample();
    assert_eq!(now.t, last.t);
    assert_eq!(now.position, last.position);
    assert_eq!(now.tension, last.tension);
}
