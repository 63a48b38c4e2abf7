//! End to end (issue 15): `omniad residual` names the effect a synthetic
//! set's air carries (here buoyancy at four times the plate's box volume),
//! stores it in the extended model, writes figures, and selects nothing
//! on the same air without it.

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

fn residual(set: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["residual", set, "--json"];
    args.extend_from_slice(extra);
    serde_json::from_str(&omniad(&args)).expect("JSON report")
}

#[test]
fn residual_names_buoyancy_and_clean_air_gets_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let with = tmp.path().join("buoyant");
    let with_s = with.to_str().expect("utf-8");
    let common = [
        "--object", "plate", "--seed", "3", "--drops", "6", "--spins", "4",
    ];
    let mut args = vec!["synth", with_s, "--effect", "buoyancy=4"];
    args.extend_from_slice(&common);
    omniad(&args);
    let truth = std::fs::read_to_string(with.join("truth/model.toml")).expect("truth");
    assert!(truth.contains("[parameters]\nbuoyancy = [0.012"), "{truth}");

    let model = tmp.path().join("extended.omni");
    let plots = tmp.path().join("plots");
    let r = residual(
        with_s,
        &[
            "-o",
            model.to_str().expect("utf-8"),
            "--plots",
            plots.to_str().expect("utf-8"),
        ],
    );
    assert_eq!(r["selected"][0], "buoyancy", "{r:#}");
    let kept = r["candidates"]
        .as_array()
        .expect("candidates")
        .iter()
        .find(|c| c["effect"] == "buoyancy" && c["step"] == 0)
        .expect("buoyancy tried");
    let vb = kept["params"][0].as_f64().expect("V_b");
    assert!(
        (vb - 0.012).abs() < 0.15 * 0.012,
        "V_b {vb} (synthesised 0.012)"
    );
    let before = r["baseline"]["heldout_force_rms"].as_f64().expect("before");
    let after = r["after"]["heldout_force_rms"].as_f64().expect("after");
    assert!(
        after < 0.7 * before,
        "held-out force RMS {before} -> {after}"
    );
    assert!(r["resimulation"]["extended_m"].as_f64().is_some());
    assert!(plots.join("residual-vs-spin.svg").exists());
    let info = omniad(&["info", model.to_str().expect("utf-8")]);
    assert!(info.contains("buoyancy"), "{info}");

    let clean = tmp.path().join("clean");
    let clean_s = clean.to_str().expect("utf-8");
    let mut args = vec!["synth", clean_s];
    args.extend_from_slice(&common);
    omniad(&args);
    let r = residual(clean_s, &[]);
    assert_eq!(r["selected"], serde_json::json!([]), "{r:#}");
}
