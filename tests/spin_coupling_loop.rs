//! The spin-coupling extension end to end: `omniad synth` a plate whose air
//! also pushes with a Magnus force (`--effect magnus=0.02`: `½ρL³ 0.02
//! Ω × V`, outside eqs. 5-6), `omniad fit` it with the extension allowed
//! and not, and check that the fit finds the effect's size, fits the
//! frames better with it, stores it in the file and `omniad info` shows it.

use std::process::Command;

fn omniad(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_omniad"))
        .args(args)
        .output()
        .expect("run omniad");
    assert!(
        out.status.success(),
        "omniad {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).expect("JSON report")
}

fn last_force_residual(report: &serde_json::Value) -> f64 {
    report["iterations"]
        .as_array()
        .and_then(|its| its.iter().rfind(|i| i["rejected"] == false))
        .and_then(|i| i["force_residual"].as_f64())
        .expect("a kept iteration")
}

#[test]
fn fit_finds_a_magnus_force_and_fits_better_with_it() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let set = tmp.path().join("magnus");
    let set_s = set.to_str().expect("utf-8 path");
    omniad(&[
        "synth",
        set_s,
        "--object",
        "plate",
        "--effect",
        "magnus=0.02",
        "--seed",
        "3",
    ]);
    let with = tmp.path().join("with.omni");
    let without = tmp.path().join("without.omni");
    let on = json(&omniad(&[
        "fit",
        set_s,
        "-o",
        with.to_str().expect("utf-8"),
        "--json",
    ]));
    let off = json(&omniad(&[
        "fit",
        set_s,
        "-o",
        without.to_str().expect("utf-8"),
        "--spin-coupling",
        "off",
        "--json",
    ]));
    let magnus = on["spin_coupling"]["magnus_scale"]
        .as_f64()
        .expect("spin coupling kept");
    assert!(
        (0.014..=0.026).contains(&magnus),
        "Magnus part {magnus} (synthesised 0.02)"
    );
    assert!(off["spin_coupling"].is_null());
    let (r_on, r_off) = (last_force_residual(&on), last_force_residual(&off));
    assert!(
        r_on < 0.85 * r_off,
        "force residual with the coupling {r_on}, without {r_off}"
    );
    let info = json(&omniad(&["info", with.to_str().expect("utf-8"), "--json"]));
    let stored = info["spin_coupling"]["magnus_scale"]
        .as_f64()
        .expect("stored");
    assert!((stored - magnus).abs() < 1e-6 * magnus.abs().max(1.0));
    let plain = json(&omniad(&[
        "info",
        without.to_str().expect("utf-8"),
        "--json",
    ]));
    assert!(plain["spin_coupling"].is_null());
}
