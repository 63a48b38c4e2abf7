//! End to end (issue 20): `omniad simulate --model M --shape plate` under
//! each comparison model of the paper's Fig. 12, `omniad report` on a tiny
//! synthetic set, and the errors of bad model/shape options.

mod common;

use common::{omniad, plate, text};
use serde_json::Value;

/// Mass of the test plate, kg (the paper's 30 x 50 x 2 cm foam plate).
const MASS: f64 = 0.048;
/// Release height of `omniad simulate`'s default start, m.
const HEIGHT: f64 = 6.0;
const G: f64 = 9.81;

/// `omniad simulate --shape plate ... --model MODEL --duration 1 --json`,
/// released flat at rest 6 m up; its JSON summary.
fn fall(model: &str) -> Value {
    let mut cmd = omniad();
    cmd.args(["simulate", "--shape", "plate", "--size", "0.3,0.5,0.02"])
        .args(["--mass", "0.048", "--model", model])
        .args(["--duration", "1", "--json"]);
    if model == "omniad" {
        cmd.arg(plate());
    }
    let out = cmd.output().expect("run omniad");
    assert!(
        out.status.success(),
        "--model {model}: {}",
        text(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON summary")
}

fn height(v: &Value) -> f64 {
    v["final_position_m"][2].as_f64().expect("z")
}

/// Kinetic plus potential energy at the end, J (the start's is m g h).
fn energy(v: &Value) -> f64 {
    v["kinetic_energy_j"].as_f64().expect("kinetic energy") + MASS * G * height(v)
}

#[test]
fn each_model_falls_as_its_physics_says() {
    let start = MASS * G * HEIGHT;
    let vacuum = fall("vacuum");
    assert!((vacuum["duration_s"].as_f64().expect("t") - 1.0).abs() < 1e-9);
    // Free fall: z = h - g t²/2, v = -g t, energy conserved (RK4 is exact
    // for a constant acceleration).
    assert!((height(&vacuum) - (HEIGHT - 0.5 * G)).abs() < 1e-6);
    let vz = vacuum["final_velocity_m_s"][2].as_f64().expect("v_z");
    assert!((vz + G).abs() < 1e-6, "{vz}");
    assert!((energy(&vacuum) - start).abs() < 1e-6 * start);
    // Kirchhoff: the added mass along the plate's normal slows the start
    // of the fall (no dissipation, so the body's energy goes into the air).
    let kirchhoff = fall("kirchhoff");
    assert!(
        height(&kirchhoff) > height(&vacuum) + 0.05,
        "kirchhoff {} vs vacuum {}",
        height(&kirchhoff),
        height(&vacuum)
    );
    // The dissipative models lose energy to the air (a quarter or more of
    // the 2.8 J in the first second, flat); the plate falls slower than in
    // vacuum.
    for model in ["drag-traction", "simplified", "omniad"] {
        let v = fall(model);
        assert!(
            energy(&v) < 0.85 * start,
            "{model}: {} J of {start} J left",
            energy(&v)
        );
        assert!(height(&v) > height(&vacuum), "{model}");
    }
}

/// `omniad ARGS` must fail with a message naming `option`.
fn fails_naming(args: &[&str], option: &str) {
    let out = omniad().args(args).output().expect("run omniad");
    assert!(!out.status.success(), "{args:?} succeeded");
    let err = text(&out.stderr);
    assert!(err.contains(option), "{args:?}: {err}");
}

#[test]
fn bad_model_and_shape_options_are_errors_naming_the_option() {
    let sim = ["simulate", "--duration", "1", "--shape", "plate"];
    fails_naming(&[&sim[..], &["--model", "nope"]].concat(), "--model");
    fails_naming(
        &["simulate", "--duration", "1", "--shape", "disc"],
        "--shape",
    );
    fails_naming(&[&sim[..], &["--size", "0.3,0.5"]].concat(), "--size");
    fails_naming(&[&sim[..], &["--size", "0.3,-0.5,0.02"]].concat(), "--size");
    fails_naming(&[&sim[..], &["--mass", "0"]].concat(), "--mass");
    // A comparison model needs a shape; the default needs a file.
    fails_naming(
        &["simulate", "--duration", "1", "--model", "kirchhoff"],
        "--shape",
    );
}

#[test]
fn report_on_a_tiny_synthetic_set_writes_its_figures_and_model() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let set = tmp.path().join("plate");
    let set_s = set.to_str().expect("utf-8 path");
    let out = omniad()
        .args(["synth", set_s, "--object", "plate", "--seed", "3"])
        .args(["--drops", "3", "--spins", "1"])
        .output()
        .expect("synth");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let dir = tmp.path().join("report");
    let dir_s = dir.to_str().expect("utf-8 path");
    let out = omniad()
        .args(["report", set_s, "-o", dir_s, "--no-sweep"])
        .output()
        .expect("report");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let md = std::fs::read_to_string(dir.join("report.md")).expect("report.md");
    let figures = [
        "fig13-drag.svg",
        "fig13-lift.svg",
        "fig12-side.svg",
        "fig12-height.svg",
    ];
    for f in figures {
        assert!(md.contains(&format!("({f})")), "report.md names {f}");
        let svg = std::fs::read_to_string(dir.join(f)).expect(f);
        assert!(svg.contains("<svg"), "{f}");
    }
    assert!(!dir.join("fig8-error.svg").exists(), "--no-sweep");
    assert!(md.contains("model.omni"), "report.md names the model file");
    let json: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("report.json")).expect("report.json"),
    )
    .expect("report.json parses");
    assert_eq!(json["object"], "plate");
    assert_eq!(json["fig12"].as_array().map(Vec::len), Some(5));
    assert!(json["fig13"][0]["drag_l1"].as_f64().is_some());
    let cf = json["accuracy"]["cf_rel_l2"].as_f64().expect("C_F error");
    assert!(cf.is_finite(), "{cf}");
    // So few spins may leave no direction with 20 torque frames: then the
    // C_T error is null (not a number), never a made-up value.
    let ct_dirs = json["accuracy"]["ct_directions"].as_u64().expect("count");
    let ct = json["accuracy"]["ct_rel_l2"].as_f64();
    assert_eq!(ct.is_some_and(f64::is_finite), ct_dirs > 0, "{ct:?}");
    // The fitted model is a coefficient file the simulator reads.
    let model = dir.join("model.omni");
    let out = omniad()
        .args([
            "simulate",
            model.to_str().expect("utf-8"),
            "--duration",
            "0.1",
        ])
        .arg("--json")
        .output()
        .expect("simulate");
    assert!(out.status.success(), "{}", text(&out.stderr));
}
