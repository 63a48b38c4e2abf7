//! End-to-end checks of the reliability promises (issue 18): bad input is a
//! clear error naming the input, endless inputs are refused at once, absurd
//! work is refused up front, and no failed command damages an existing file.

mod common;

use common::{omniad, plate, run_with_stdin};
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs and requires a failure whose message contains every `needle`.
fn fails_naming(args: &[&str], needles: &[&str]) {
    let out = omniad().args(args).output().expect("run");
    assert!(!out.status.success(), "{args:?} should fail");
    let err = stderr(&out);
    for n in needles {
        assert!(err.contains(n), "{args:?}: error should name {n:?}: {err}");
    }
}

#[cfg(unix)]
#[test]
fn endless_inputs_are_refused_at_once() {
    for args in [
        vec!["info", "/dev/zero"],
        vec!["info", "/dev/urandom"],
        vec!["simulate", "/dev/zero", "--duration", "1"],
    ] {
        let start = Instant::now();
        let out = omniad().args(&args).output().expect("run");
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr(&out).contains("/dev/"), "{args:?}: {}", stderr(&out));
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "{args:?} must not read the device for long"
        );
    }
}

#[test]
fn simulate_refuses_absurd_work_and_physics_naming_the_option() {
    let p = plate();
    let p = p.to_str().expect("utf-8 path");
    fails_naming(
        &["simulate", p, "--duration", "1e308"],
        &["--duration", "steps"],
    );
    fails_naming(
        &["simulate", p, "--duration", "1", "--dt", "1e-300"],
        &["--dt"],
    );
    fails_naming(
        &["simulate", p, "--duration", "1", "--wind", "1e200,0,0"],
        &["--wind"],
    );
    fails_naming(
        &["simulate", p, "--duration", "1", "--velocity", "1e155,0,0"],
        &["--velocity"],
    );
    fails_naming(
        &[
            "simulate",
            p,
            "--duration",
            "1",
            "--angular-velocity",
            "0,1e9,0",
        ],
        &["--angular-velocity"],
    );
    fails_naming(
        &["simulate", p, "--duration", "1", "--air-density", "1e9"],
        &["--air-density"],
    );
}

#[test]
fn simulate_streams_every_row_of_a_long_run() {
    // 1,000 s at 1 ms: a million steps, streamed at 1 Hz: 1,001 rows.
    let out = omniad()
        .args([
            "simulate",
            plate().to_str().expect("path"),
            "--duration",
            "1000",
        ])
        .args(["--rate", "1", "--csv", "--position", "0,0,1e5"])
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", stderr(&out));
    let rows = String::from_utf8_lossy(&out.stdout).lines().count();
    assert_eq!(rows, 1 + 1001, "header and one row a second");
}

#[test]
fn coeffs_eval_accepts_tiny_but_valid_directions() {
    let p = plate();
    let out = run_with_stdin(
        &["coeffs", "eval", p.to_str().expect("path")],
        "ex,ey,ez\n1e-200,0,0\n0,-1e-300,0\n",
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let mut rows = text.lines().skip(1);
    assert!(rows.next().expect("row 1").starts_with("1,0,0,"), "{text}");
    assert!(rows.next().expect("row 2").starts_with("0,-1,0,"), "{text}");
}

#[test]
fn a_coefficient_file_is_replaced_whole_or_not_at_all() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("plate.omni");
    std::fs::write(&out, b"the user's file").expect("write");
    // A failing panel command (bad size) leaves the old file as it was.
    let failed = omniad()
        .args([
            "panel",
            "--shape",
            "plate",
            "--size",
            "nan,0.5,0.02",
            "--mass",
            "0.05",
        ])
        .arg("-o")
        .arg(&out)
        .output()
        .expect("run");
    assert!(!failed.status.success());
    assert_eq!(std::fs::read(&out).expect("read"), b"the user's file");
    // A successful one replaces it and leaves no temporary behind.
    let ok = omniad()
        .args([
            "panel",
            "--shape",
            "plate",
            "--size",
            "0.3,0.5,0.02",
            "--mass",
            "0.05",
        ])
        .args(["--degree", "2", "-o"])
        .arg(&out)
        .output()
        .expect("run");
    assert!(ok.status.success(), "{}", stderr(&ok));
    let info = omniad().arg("info").arg(&out).output().expect("run");
    assert!(info.status.success(), "{}", stderr(&info));
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names.len(), 1, "no temporary left: {names:?}");
}

#[test]
fn tui_telemetry_that_does_not_load_is_an_error_not_ignored() {
    let out = omniad()
        .args(["tui", "--telemetry", "/no/such/telemetry.csv"])
        .stdin(Stdio::null())
        .output()
        .expect("run");
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("--telemetry /no/such/telemetry.csv"), "{err}");
}
