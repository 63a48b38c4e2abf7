//! End-to-end tests of `omniad info`, `coeffs eval`, `simulate`, `panel`, `lab`.

mod common;

use common::{omniad, plate, run_with_stdin, text};
use std::path::Path;

#[test]
fn info_prints_text_and_json() {
    let out = omniad().arg("info").arg(plate()).output().expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("degree N:          8"));
    let out = omniad()
        .arg("info")
        .arg(plate())
        .arg("--json")
        .output()
        .expect("run");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["degree"], 8);
    assert_eq!(v["provenance"]["method"], "projection");
    let cd = v["axis_drag_coefficient"]["+z"].as_f64().expect("number");
    assert!(cd > 0.4 && cd < 0.6, "broadside drag {cd}");
}

#[test]
fn info_on_a_corrupt_file_names_the_file_and_the_problem() {
    let dir = tempfile::tempdir().expect("tmp");
    let bad = dir.path().join("broken.omni");
    let mut bytes = std::fs::read(plate()).expect("read");
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    std::fs::write(&bad, &bytes).expect("write");
    let out = omniad().arg("info").arg(&bad).output().expect("run");
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("broken.omni") && err.contains("CRC mismatch"),
        "{err}"
    );
    let out = omniad()
        .arg("info")
        .arg(dir.path().join("missing.omni"))
        .output()
        .expect("run");
    assert!(text(&out.stderr).contains("missing.omni"));
}

#[test]
fn coeffs_eval_normalises_and_matches_the_library() {
    let out = run_with_stdin(
        &["coeffs", "eval", plate().to_str().expect("utf8")],
        "ex,ey,ez\n0,0,2\n1,1,0\n\n0.2,-0.3,0.9\n",
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let mut lines = stdout.lines();
    assert_eq!(lines.next(), Some("ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 3);
    assert_eq!(&rows[0][..3], &[0.0, 0.0, 1.0]);
    assert!((rows[1][0] - 0.5f64.sqrt()).abs() < 1e-15);
    // Moving along +z through still air: drag pushes toward -z.
    assert!(rows[0][5] < -0.4, "{:?}", rows[0]);
    let bytes = std::fs::read(plate()).expect("read");
    let model: omniad_core::Coefficients<f64> = omniad_core::file::decode(&bytes).expect("decode");
    let e = nalgebra::Vector3::new(0.2, -0.3, 0.9).normalize();
    let c = model.at_unit_direction(&e);
    let row = &rows[2];
    assert!((row[3] - c.force.x).abs() < 1e-15 && (row[8] - c.torque.z).abs() < 1e-15);
}

#[test]
fn coeffs_eval_rejects_bad_rows_with_their_line_number() {
    let p = plate();
    let p = p.to_str().expect("utf8");
    for (input, needle) in [
        ("ex,ey,ez\n0,0,1\n0,zero,1\n", "line 3: field ey"),
        ("ex,ey,ez\n0,0,1\n0,0\n", "line 3: expected 3 fields"),
        ("ex,ey,ez\n0,0,0\n", "line 2: direction"),
        ("ex,ey,ez\nNaN,0,1\n", "line 2: field ex"),
        ("x,y,z\n0,0,1\n", "line 1: expected header"),
        ("", "empty input"),
    ] {
        let out = run_with_stdin(&["coeffs", "eval", p], input);
        assert!(!out.status.success(), "accepted {input:?}");
        assert!(out.stdout.is_empty(), "partial output for {input:?}");
        let err = text(&out.stderr);
        assert!(err.contains(needle), "{input:?}: {err}");
    }
}

#[test]
fn simulate_writes_a_trajectory_that_falls() {
    let out = omniad()
        .arg("simulate")
        .arg(plate())
        .args([
            "--duration",
            "1",
            "--rate",
            "10",
            "--csv",
            "--orientation",
            "0.95,0.3,0,0",
        ])
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines[0], "t,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    assert_eq!(lines.len(), 1 + 11, "t = 0, 0.1, ..., 1.0");
    let last: Vec<f64> = lines[lines.len() - 1]
        .split(',')
        .map(|x| x.parse().expect("number"))
        .collect();
    assert!((last[0] - 1.0).abs() < 1e-9);
    // Fell, but less than in vacuum (4.905 m).
    assert!(last[3] < 6.0 && last[3] > 6.0 - 4.905, "z = {}", last[3]);
    let q = (last[4] * last[4] + last[5] * last[5] + last[6] * last[6] + last[7] * last[7]).sqrt();
    assert!((q - 1.0).abs() < 1e-12);
}

#[test]
fn simulate_rejects_bad_options() {
    for args in [
        vec!["--duration", "-1"],
        vec!["--duration", "1", "--dt", "0"],
        vec!["--duration", "1", "--position", "1,2"],
        vec!["--duration", "1", "--orientation", "0,0,0,0"],
    ] {
        let out = omniad()
            .arg("simulate")
            .arg(plate())
            .args(&args)
            .output()
            .expect("run");
        assert!(!out.status.success(), "accepted {args:?}");
        assert!(!text(&out.stderr).is_empty());
    }
}

#[test]
fn panel_regenerates_the_bundled_plate() {
    let dir = tempfile::tempdir().expect("tmp");
    let out_file = dir.path().join("plate.omni");
    let out = omniad()
        .args([
            "panel",
            "--shape",
            "plate",
            "--size",
            "0.30,0.50,0.02",
            "--mass",
            "0.048",
            "--degree",
            "8",
            "--name",
            "foam plate 30x50x2 cm",
            "-o",
        ])
        .arg(&out_file)
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let decode = |p: &Path| -> omniad_core::Coefficients<f64> {
        omniad_core::file::decode(&std::fs::read(p).expect("read")).expect("decode")
    };
    let (fresh, bundled) = (decode(&out_file), decode(&plate()));
    assert_eq!(
        (fresh.name(), fresh.degree(), fresh.body),
        (bundled.name(), bundled.degree(), bundled.body)
    );
    // Rounding-level differences are allowed (the quadrature may be
    // reordered); anything larger means data/plate.omni is stale.
    for k in 0..fresh.coeff_count() {
        for i in 0..3 {
            let (a, b) = (
                fresh.alpha(i, k).expect("k"),
                bundled.alpha(i, k).expect("k"),
            );
            let (c, d) = (fresh.beta(i, k).expect("k"), bundled.beta(i, k).expect("k"));
            assert!(
                (a - b).abs() < 1e-12 && (c - d).abs() < 1e-12,
                "coefficient {i},{k} differs: regenerate data/plate.omni"
            );
        }
    }
    assert!((fresh.damping() - bundled.damping()).norm() < 1e-12);
}

#[test]
fn lab_lists_its_measurements_and_names_a_missing_set() {
    let out = omniad().args(["lab", "--help"]).output().expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let help = text(&out.stdout);
    for m in [
        "accept",
        "depth",
        "diag",
        "forcenoise",
        "missing-terms",
        "mixfit",
        "torquesplit",
        "truthfit",
    ] {
        assert!(help.contains(m), "{m} missing from {help}");
    }
    let dir = tempfile::tempdir().expect("tmp");
    let missing = dir.path().join("no-such-set");
    let runs: [&[&str]; 2] = [&["accept", "--iterations", "1"], &["torquesplit"]];
    for args in runs {
        let out = omniad()
            .arg("lab")
            .arg(args[0])
            .arg(&missing)
            .args(&args[1..])
            .output()
            .expect("run");
        assert!(!out.status.success(), "lab {args:?}");
        assert!(
            text(&out.stderr).contains("no-such-set"),
            "{}",
            text(&out.stderr)
        );
    }
}

#[test]
fn info_lists_named_effects() {
    use omniad_core::effect::{Effect, EffectKind};
    let mut m =
        omniad_core::file::decode::<f64>(&std::fs::read(plate()).expect("read")).expect("plate");
    m.set_effect(Effect::new(EffectKind::Buoyancy, &[0.002]).expect("effect"))
        .expect("set");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("buoyant.omni");
    let mut buf = vec![0u8; omniad_core::file::MAX_FILE_SIZE];
    let n = omniad_core::file::encode(&m, &mut buf).expect("encode");
    std::fs::write(&path, &buf[..n]).expect("write");
    let out = omniad().arg("info").arg(&path).output().expect("run");
    assert!(
        text(&out.stdout).contains("effect:            buoyancy [0.002"),
        "{}",
        text(&out.stdout)
    );
    let out = omniad()
        .args(["info", "--json"])
        .arg(&path)
        .output()
        .expect("run");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["effects"][0]["effect"], "buoyancy");
}
