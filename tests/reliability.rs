//! End-to-end checks of the reliability promises (issue 18): bad input is a
//! clear error naming the input, endless inputs are refused at once, absurd
//! work is refused up front, and no failed command damages an existing file.

mod common;

use common::{omniad, plate, run_with_stdin};
use std::io::Write;
use std::path::Path;
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
    // A step longer than the run ran none and reported success.
    fails_naming(
        &["simulate", p, "--duration", "1", "--dt", "10"],
        &["--dt", "--duration"],
    );
    // A step that does not divide the run covers at least all of it
    // (rounding simulated 0.7 s of 1 s).
    let out = omniad()
        .args(["simulate", p, "--duration", "1", "--dt", "0.7", "--json"])
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", stderr(&out));
    let json = String::from_utf8_lossy(&out.stdout);
    assert!(json.contains("\"steps\": 2"), "{json}");
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

/// `omniad synth DIR --drops 1 --spins 0`: a one-take set.
fn one_take_set(dir: &Path) -> String {
    let set = dir.join("set").to_str().expect("utf-8 path").to_owned();
    let out = omniad()
        .args(["synth", &set, "--drops", "1", "--spins", "0"])
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", stderr(&out));
    set
}

#[test]
fn a_stray_frame_index_is_refused_at_once_by_fit_and_reconstruct() {
    let dir = tempfile::tempdir().expect("tempdir");
    let set = one_take_set(dir.path());
    let take = Path::new(&set).join("drop-01.csv");
    let mut f = std::fs::OpenOptions::new()
        .append(true)
        .open(&take)
        .expect("open");
    writeln!(f, "4294967295,m0,100,100").expect("append");
    let lines = std::fs::read_to_string(&take)
        .expect("read")
        .lines()
        .count();
    let line = format!("drop-01.csv:{lines}");
    let model = dir.path().join("m.omni");
    let model = model.to_str().expect("utf-8");
    let recon = dir.path().join("r");
    let recon = recon.to_str().expect("utf-8");
    for args in [
        vec!["fit", &set, "-o", model],
        vec!["reconstruct", &set, "-o", recon],
    ] {
        let start = Instant::now();
        fails_naming(&args, &[&line, "4294967295"]);
        assert!(start.elapsed() < Duration::from_secs(10), "{args:?}");
    }
}

#[test]
fn absurd_generator_and_panel_options_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("s");
    let out = out.to_str().expect("utf-8");
    fails_naming(
        &["synth", out, "--drops", "0", "--spins", "0"],
        &["--drops"],
    );
    fails_naming(&["synth", out, "--drops", "100000"], &["--drops"]);
    // A noise that wrote a recording.toml TOML cannot read back.
    fails_naming(&["synth", out, "--noise", "1e20"], &["--noise", "100"]);
    // An inertia that underflows: no file no reader takes is written.
    let tiny = dir.path().join("tiny.omni");
    fails_naming(
        &[
            "panel",
            "--shape",
            "plate",
            "--size",
            "0.3,0.5,0.002",
            "--mass",
            "1e-300",
            "-o",
            tiny.to_str().expect("utf-8"),
        ],
        &["tiny.omni", "no reader"],
    );
    assert!(!tiny.exists());
    for speeds in ["8,5", "5", "5,16", "-1,2", "nan,2", "1,2,3"] {
        fails_naming(&["synth", out, "--throw-speed", speeds], &["--throw-speed"]);
    }
    for size in ["0,0.5,0.02", "0.3,-0.5,0.02", "0.3,0.5,0"] {
        fails_naming(
            &[
                "panel", "--shape", "plate", "--size", size, "--mass", "0.05",
            ],
            &["--size"],
        );
    }
}

#[test]
fn synth_refuses_a_non_empty_folder_unless_forced() {
    let dir = tempfile::tempdir().expect("tempdir");
    let keep = dir.path().join("notes.txt");
    std::fs::write(&keep, "the user's notes").expect("write");
    let out = dir.path().to_str().expect("utf-8");
    fails_naming(
        &["synth", out, "--drops", "1", "--spins", "0"],
        &["--force"],
    );
    assert!(
        !dir.path().join("recording.toml").exists(),
        "nothing written"
    );
    let forced = omniad()
        .args(["synth", out, "--drops", "1", "--spins", "0", "--force"])
        .output()
        .expect("run");
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert!(dir.path().join("recording.toml").exists());
}

#[test]
fn kite_physical_inputs_are_checked_up_front() {
    let kite = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/kites/box-single.toml");
    let kite = kite.to_str().expect("utf-8");
    for wind in ["1e300", "-5", "NaN", "0", "inf"] {
        let wind = format!("--wind={wind}");
        for command in ["check", "trim", "fly"] {
            fails_naming(&["kite", command, kite, &wind], &["--wind"]);
        }
    }
    for seconds in ["1e308", "NaN", "-1", "0"] {
        let start = Instant::now();
        let seconds = format!("--seconds={seconds}");
        fails_naming(&["kite", "fly", kite, &seconds], &["--seconds"]);
        assert!(start.elapsed() < Duration::from_secs(10));
    }
    fails_naming(&["kite", "fly", kite, "--gust", "NaN"], &["--gust"]);
    // The file's own wind has the option's bound (1e308 printed "wind inf
    // m/s" and NaN margins).
    let dir = tempfile::tempdir().expect("tempdir");
    let text = std::fs::read_to_string(kite).expect("kite");
    assert!(text.contains("speed = "), "the test edits the wind speed");
    for speed in ["1e308", "61.0"] {
        let edited: String = text
            .lines()
            .map(|l| {
                if l.trim_start().starts_with("speed = ") {
                    format!("speed = {speed}\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        let path = dir.path().join("windy.toml");
        std::fs::write(&path, edited).expect("write");
        let p = path.to_str().expect("utf-8");
        for command in ["check", "trim"] {
            fails_naming(&["kite", command, p], &["wind.speed", "60"]);
        }
    }
    // A primitive of 1e308 m was "primitive size is zero".
    let huge = text.replacen("size = [0.4, 0.4, 0.3]", "size = [1e308, 0.4, 0.3]", 1);
    assert_ne!(huge, text, "the test edits the first primitive's size");
    let path = dir.path().join("huge.toml");
    std::fs::write(&path, huge).expect("write");
    let p = path.to_str().expect("utf-8");
    fails_naming(&["kite", "check", p], &["primitive[0].size", "1000"]);
}

#[test]
fn import_tracks_refuses_options_that_would_write_malformed_rows() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("xypts.csv");
    std::fs::write(&input, "pt1_cam1_X,pt1_cam1_Y\n1,2\n").expect("write");
    let input = input.to_str().expect("utf-8");
    let out = dir.path().join("out.csv");
    let out = out.to_str().expect("utf-8");
    let base = ["import-tracks", input, "-o", out, "--format", "dltdv"];
    for (extra, needle) in [
        (vec!["--map", "pt1=m,0"], "--map"),
        (vec!["--map", "pt1="], "--map"),
        (vec!["--map", "pt1=m0", "--map", "pt2=m0"], "m0"),
        (vec!["--map", "pt1=m0", "--height", "NaN"], "--height"),
        (vec!["--map", "pt1=m0", "--height", "0"], "--height"),
        (vec!["--map", "pt1=m0", "--height=-720"], "--height"),
        (
            vec!["--map", "pt1=m0", "--min-likelihood", "NaN"],
            "--min-likelihood",
        ),
        (
            vec!["--map", "pt1=m0", "--first-frame", "9223372036854775807"],
            "--first-frame",
        ),
    ] {
        let mut args = base.to_vec();
        args.extend(extra);
        fails_naming(&args, &[needle]);
        assert!(!Path::new(out).exists(), "{args:?} wrote nothing");
    }
}

#[test]
fn a_fit_the_data_cannot_support_names_the_take() {
    // 70 px tracking noise: the first reconstruction is meaningless, and
    // the error says which take and which inputs, not just "non-finite".
    let dir = tempfile::tempdir().expect("tempdir");
    let set = dir.path().join("noisy");
    let set = set.to_str().expect("utf-8");
    let made = omniad()
        .args(["synth", set, "--noise", "70"])
        .output()
        .expect("run");
    assert!(made.status.success(), "{}", stderr(&made));
    let model = dir.path().join("m.omni");
    fails_naming(
        &["fit", set, "-o", model.to_str().expect("utf-8")],
        &["take `drop-0", "recording.toml"],
    );
    assert!(!model.exists(), "nothing written");
}

/// `omniad ... | head` closes the pipe early: the command ends quietly (as
/// Unix filters do), never with a panic message. The read end is closed
/// before the command writes, so its first `println!` meets the closed pipe.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_the_command_quietly() {
    let mut child = omniad()
        .arg("info")
        .arg(plate())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    assert_ne!(out.status.code(), Some(101), "not a panic exit");
}

/// A command's output that is one of its own inputs is refused before any
/// work, through any path, and the input is left byte for byte: `fit -o`
/// over the set's `recording.toml`, `reconstruct -o` the set's own folder
/// (its state CSVs would replace the marker CSVs of the same names), and
/// `import-tracks` onto its own track file.
#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().expect("tempdir");
    let set = one_take_set(dir.path());
    let toml = Path::new(&set).join("recording.toml");
    let take = Path::new(&set).join("drop-01.csv");
    let before = (
        std::fs::read(&toml).expect("toml"),
        std::fs::read(&take).expect("take"),
    );
    let dotted = format!("{set}/./recording.toml");
    for args in [
        vec!["fit", &set, "-o", &dotted],
        vec!["reconstruct", &set, "-o", &set],
    ] {
        let start = Instant::now();
        fails_naming(&args, &["is an input"]);
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "{args:?}: refused late"
        );
    }
    let take_s = take.to_str().expect("utf-8");
    fails_naming(
        &[
            "import-tracks",
            take_s,
            "--format",
            "dltdv",
            "--map",
            "p1=m0",
            "-o",
            take_s,
        ],
        &["is an input", "drop-01.csv"],
    );
    let after = (
        std::fs::read(&toml).expect("toml"),
        std::fs::read(&take).expect("take"),
    );
    assert!(before == after, "an input was changed");
}
