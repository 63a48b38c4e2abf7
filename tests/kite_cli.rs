//! End-to-end tests of `omniad kite check | trim | fly | export`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn omniad() -> Command {
    Command::new(env!("CARGO_BIN_EXE_omniad"))
}

fn kite(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/kites")
        .join(format!("{name}.toml"))
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn check_prints_verdict_and_json() {
    let out = omniad()
        .args(["kite", "check"])
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("verdict: Stable"),
        "{}",
        text(&out.stdout)
    );
    let out = omniad()
        .args(["kite", "check", "--json", "--wind", "5"])
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["verdict"], "stable");
    assert_eq!(v["pulls_down"], true);
    assert_eq!(v["axes"].as_array().map(Vec::len), Some(3));
    assert!(v["gamma"].is_number() && v["attachment"].is_array() && v["tension_world"].is_array());
}

#[test]
fn check_of_a_bad_file_names_file_and_field() {
    let dir = std::env::temp_dir().join(format!("omniad-kite-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "name = \"x\"\n[[primitive]]\nname = \"a\"\nkind = \"box\"\nsize = [0.3, 0.0, 0.3]\n",
    )
    .expect("write");
    let out = omniad()
        .args(["kite", "check"])
        .arg(&bad)
        .output()
        .expect("run");
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("bad.toml") && err.contains("primitive[0].size"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn trim_fly_and_export_run() {
    let out = omniad()
        .args(["kite", "trim", "--json"])
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["found"], true);

    let dir = std::env::temp_dir().join(format!("omniad-kite-cli-fly-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let csv = dir.join("trace.csv");
    let out = omniad()
        .args([
            "kite",
            "fly",
            "--seconds",
            "5",
            "--gust",
            "1",
            "--seed",
            "3",
            "--json",
            "--csv",
        ])
        .arg(&csv)
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert!(v["outcome"].is_string());
    let trace = std::fs::read_to_string(&csv).expect("csv");
    assert!(trace.starts_with("t,x,y,z,") && trace.lines().count() > 90);

    let out = omniad()
        .args(["kite", "export", "-o"])
        .arg(dir.join("fab"))
        .arg(kite("fig15-a"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    for f in ["sockets.scad", "cutlist.txt", "drawing.svg"] {
        assert!(dir.join("fab").join(f).exists(), "{f}");
    }
    let out = omniad()
        .args(["kite", "fly", "--seconds=-1"])
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(!out.status.success() && text(&out.stderr).contains("--seconds"));
    let _ = std::fs::remove_dir_all(&dir);
}
