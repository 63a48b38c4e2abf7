//! End to end: `omniad flight fit` on the three bundled Kitepower cycles
//! (trained on 1-3, tested on a copy of 3 as cycle 4): the report's
//! fields, the model file, the plots, and that no fitting step sees a test
//! cycle.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bundled() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/flight/kitepower-2019-10-08")
}

/// A folder with the three bundled cycles as training cycles 1-3 and, as
/// test cycle 4, cycle 3's rows passed through `test_rows` (three training
/// cycles are the fewest that leave-one-cycle-out needs; only three may be
/// bundled).
fn four_cycles(test_rows: impl Fn(&str) -> String) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().expect("tempdir");
    for n in 1..=3 {
        let name = format!("20191008_{n:04}.csv");
        std::fs::copy(bundled().join(&name), tmp.path().join(&name)).expect("copy");
    }
    let three = std::fs::read_to_string(bundled().join("20191008_0003.csv")).expect("read");
    std::fs::write(tmp.path().join("20191008_0004.csv"), test_rows(&three)).expect("write");
    tmp
}

fn fit(dir: &Path, extra: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_omniad"))
        .args(["flight", "fit"])
        .arg(dir)
        .args(["--train", "1-3", "--test", "4", "--json"])
        .args(extra)
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("json")
}

fn num(v: &Value, path: &[&str]) -> f64 {
    path.iter()
        .fold(v, |v, k| &v[*k])
        .as_f64()
        .unwrap_or_else(|| panic!("{path:?} is a number: {v}"))
}

#[test]
fn the_report_model_and_plots_of_a_flight_fit() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let model = tmp.path().join("kite.omni");
    let plots = tmp.path().join("plots");
    let set = four_cycles(str::to_owned);
    let r = fit(
        set.path(),
        &[
            "-o",
            model.to_str().expect("path"),
            "--plots",
            plots.to_str().expect("path"),
        ],
    );
    let before = num(&r, &["baseline", "heldout_force_rms"]);
    let after = num(&r, &["after", "heldout_force_rms"]);
    assert!(before > 0.0 && after > 0.0, "{r}");
    assert!(
        after <= before,
        "selection on training cycles must not hurt here: {r}"
    );
    assert!(num(&r, &["baseline", "heldout_tension_rms"]) > 0.0);
    assert!(
        r["candidates"].as_array().is_some_and(|c| c.len() >= 5),
        "{r}"
    );
    // Every candidate, at every step, has its test-cycle error (later
    // steps' were NaN, printed as measured).
    for c in r["candidates"].as_array().expect("candidates") {
        let rms = c["heldout_force_rms"].as_f64();
        assert!(rms.is_some_and(|x| x.is_finite() && x > 0.0), "{c}");
    }
    for name in r["selected"].as_array().expect("selected") {
        let name = name.as_str().expect("name");
        assert!(
            [
                "covariate:depower",
                "covariate:steering",
                "tether_drag",
                "kite_inertia",
                "kcu_swing"
            ]
            .contains(&name),
            "{name}"
        );
    }
    assert_eq!(
        num(&r, &["rows", "test", "read"]),
        1353.0,
        "cycle 4 (cycle 3's copy) has 1353 rows"
    );
    assert!(!r["verdict"].as_str().expect("verdict").is_empty());
    let info = Command::new(env!("CARGO_BIN_EXE_omniad"))
        .arg("info")
        .arg(&model)
        .output()
        .expect("info");
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    let svg = std::fs::read_to_string(plots.join("force-vs-time.svg")).expect("plot");
    assert!(svg.starts_with("<svg") && svg.contains("cycle 4"));
    assert!(plots.join("residual-vs-depower.svg").exists());
}

/// The test cycle is changed beyond recognition (tension tripled); every
/// number that fitting produces must stay the same, only the held-out
/// scores may move.
#[test]
fn no_fitting_step_sees_a_test_cycle() {
    let clean = fit(four_cycles(str::to_owned).path(), &[]);
    let altered = fit(four_cycles(triple_tension).path(), &[]);
    assert_eq!(clean["selected"], altered["selected"]);
    assert_eq!(clean["params"], altered["params"]);
    assert_eq!(clean["confounding"], altered["confounding"]);
    for (a, b) in clean["candidates"]
        .as_array()
        .expect("candidates")
        .iter()
        .zip(altered["candidates"].as_array().expect("candidates"))
    {
        assert_eq!(a["cv_force_rms"], b["cv_force_rms"], "{a} vs {b}");
        assert_eq!(a["param"], b["param"]);
    }
    assert_ne!(
        clean["baseline"], altered["baseline"],
        "the test cycle was changed"
    );
}

fn triple_tension(text: &str) -> String {
    let mut lines = text.lines();
    let header = lines.next().expect("header");
    let col = header
        .split(',')
        .position(|h| h == "ground_tether_force")
        .expect("column");
    let mut out = format!("{header}\n");
    for l in lines {
        let mut f: Vec<String> = l.split(',').map(str::to_owned).collect();
        if let Some(v) = f.get_mut(col) {
            if let Ok(x) = v.parse::<f64>() {
                *v = format!("{}", 3.0 * x);
            }
        }
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

#[test]
fn bad_flight_options_are_errors_naming_them() {
    let run = |extra: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_omniad"))
            .args(["flight", "fit"])
            .arg(bundled())
            .args(extra)
            .output()
            .expect("run");
        assert!(!out.status.success(), "{extra:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    assert!(run(&["--train", "1-2", "--test", "2"]).contains("cycle 2 is both"));
    // Leave-one-cycle-out needs three training cycles: with two, every
    // score was infinite and every gain NaN.
    assert!(run(&["--train", "1-2", "--test", "3"]).contains("at least 3"));
    assert!(run(&["--train", "1-2", "--test", "9"]).contains("_0009.csv"));
    assert!(run(&["--train", "2-1", "--test", "3"]).contains("--train"));
    assert!(run(&["--train", "1-2", "--test", "3", "--mass", "nan"]).contains("mass"));
    assert!(
        run(&["--train", "1-2", "--test", "3", "--tether-diameter=-1"]).contains("tether_diameter")
    );
}
