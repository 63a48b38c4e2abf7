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
        .arg(kite("box-three-cell"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("verdict: stable"),
        "{}",
        text(&out.stdout)
    );
    let out = omniad()
        .args(["kite", "check", "--json", "--wind", "5"])
        .arg(kite("box-three-cell"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["verdict"], "stable");
    assert_eq!(v["static"]["stable"], true);
    assert_eq!(v["modes"]["stable"], true);
    assert!(v["modes"]["modes"].as_array().is_some_and(|m| m.len() >= 6));
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
    assert!(v["outcome"] == "flies" || v["outcome"] == "crashes");
    assert!(v["reason"].is_string());
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

/// Issue 18: every kite output is written atomically (temporary file +
/// rename): an existing file is replaced whole, no temporary file is left
/// behind, and a run that fails before writing leaves the old file alone.
#[test]
fn kite_outputs_replace_files_whole_and_leave_nothing_behind() {
    let dir = std::env::temp_dir().join(format!("omniad-kite-cli-atomic-{}", std::process::id()));
    let fab = dir.join("fab");
    std::fs::create_dir_all(&fab).expect("tmp");
    let junk = "junk\n".repeat(200_000);
    let csv = dir.join("trace.csv");
    for f in [csv.clone(), fab.join("cutlist.txt")] {
        std::fs::write(&f, &junk).expect("junk");
    }
    let out = omniad()
        .args(["kite", "fly", "--seconds", "1", "--csv"])
        .arg(&csv)
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let trace = std::fs::read_to_string(&csv).expect("csv");
    assert!(trace.starts_with("t,x,y,z,") && !trace.contains("junk"));
    let out = omniad()
        .args(["kite", "export", "-o"])
        .arg(&fab)
        .arg(kite("box-classic"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let cut = std::fs::read_to_string(fab.join("cutlist.txt")).expect("cut list");
    assert!(!cut.contains("junk"), "{cut}");
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&fab), ["cutlist.txt", "drawing.svg", "sockets.scad"]);
    assert_eq!(names(&dir), ["fab", "trace.csv"]);
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\nbogus = 1\n").expect("bad kite");
    let out = omniad()
        .args(["kite", "fly", "--csv"])
        .arg(&csv)
        .arg(&bad)
        .output()
        .expect("run");
    assert!(!out.status.success());
    assert_eq!(std::fs::read_to_string(&csv).expect("csv"), trace);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 17: for every bundled design and seeds 1-3 the verdict is
/// `stable` exactly when the 60 s flight in 1 m/s gusts flies. The full
/// 60 s flights are run (a shorter flight changes outcomes: several
/// unstable kites crash after 30 s); in a debug build this is the slow
/// test of the file (about a minute), in release a few seconds.
#[test]
fn verdict_agrees_with_the_flight_for_every_bundled_design() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/kites");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("kites")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 11, "{} designs", files.len());
    let mut table = String::new();
    let mut bad = Vec::new();
    let mut fig15_flying = 0;
    for f in &files {
        let out = omniad()
            .args(["kite", "check", "--json"])
            .arg(f)
            .output()
            .expect("run");
        assert!(out.status.success(), "{}", text(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        let verdict = v["verdict"].as_str().expect("verdict").to_string();
        let name = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        table += &format!("{name:<26} {verdict:<22}");
        let mut flew = 0;
        for seed in ["1", "2", "3"] {
            let out = omniad()
                .args([
                    "kite",
                    "fly",
                    "--json",
                    "--seconds",
                    "60",
                    "--gust",
                    "1",
                    "--seed",
                    seed,
                ])
                .arg(f)
                .output()
                .expect("run");
            assert!(out.status.success(), "{}", text(&out.stderr));
            let r: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
            let outcome = r["outcome"].as_str().expect("outcome").to_string();
            assert!(
                outcome == "flies" || outcome == "crashes",
                "{name} seed {seed}: outcome {outcome}"
            );
            assert!(r["reason"].is_string(), "{name} seed {seed}: no reason");
            for k in [
                "mean_elevation_deg",
                "min_elevation_deg",
                "max_spin",
                "mean_tension",
            ] {
                assert!(r[k].is_number(), "{name} seed {seed}: {k} = {}", r[k]);
            }
            table += &format!(" {outcome:<10}");
            flew += usize::from(outcome == "flies");
            if (verdict == "stable") != (outcome == "flies") {
                bad.push(format!("{name} seed {seed}: {verdict} but {outcome}"));
            }
        }
        table += "\n";
        if name.starts_with("fig15") && verdict == "stable" && flew == 3 {
            fig15_flying += 1;
        }
    }
    assert!(bad.is_empty(), "{bad:?}\n{table}");
    // The acceptance: at least four designs after Fig. 15 that are
    // stable and fly on every seed.
    assert!(
        fig15_flying >= 4,
        "{fig15_flying} Fig. 15 designs fly\n{table}"
    );
}

/// Runs `kite optimise --json --evaluations N` (and `extra` options) on the
/// bundled kite `name` into a fresh temporary folder (tagged `tag`): the
/// folder, the written file and the JSON report.
fn optimise(
    name: &str,
    evaluations: usize,
    extra: &[&str],
    tag: &str,
) -> (PathBuf, PathBuf, serde_json::Value) {
    let dir = std::env::temp_dir().join(format!("omniad-kite-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let out_file = dir.join("opt.toml");
    let out = omniad()
        .args(["kite", "optimise", "--json", "--evaluations"])
        .arg(evaluations.to_string())
        .args(extra)
        .arg("-o")
        .arg(&out_file)
        .arg(kite(name))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v = serde_json::from_slice(&out.stdout).expect("json");
    (dir, out_file, v)
}

/// `kite check` accepts the optimiser's file `out_file`; removes `dir`.
fn checks_and_cleans(dir: &Path, out_file: &Path) {
    let out = omniad()
        .args(["kite", "check", "--json"])
        .arg(out_file)
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let _ = std::fs::remove_dir_all(dir);
}

/// Issue 17: `kite optimise` reports before/after and each change, and
/// writes a kite file that loads; the search never ends worse than the
/// file.
#[test]
fn optimise_writes_a_loadable_kite_and_reports_changes() {
    let (dir, out_file, v) = optimise("box-three-cell", 12, &["--flown", "2"], "opt");
    assert!(v["changes"].is_array());
    let (b, a) = (&v["before"]["objective"], &v["after"]["objective"]);
    assert!(a.as_f64() >= b.as_f64(), "{b} -> {a}");
    // The result is flown on seeds 1-3 and the outcomes reported; a stable
    // kite that flies (box-three-cell) stays one that flies.
    let flights: Vec<&str> = v["flights"]
        .as_array()
        .map(|f| f.iter().filter_map(|o| o.as_str()).collect())
        .unwrap_or_default();
    assert_eq!(flights, ["flies"; 3], "{v}");
    // The nonlinear check flew at most the designs allowed, on its own
    // three seeds, and the result flies on them by a positive margin.
    assert!(v["candidates_flown"].as_u64() <= Some(2), "{v}");
    assert_eq!(v["check_flights"].as_array().map(Vec::len), Some(3), "{v}");
    assert!(v["flight_margin"].as_f64() > Some(0.0), "{v}");
    // Several searches shared the one budget (what the flight check
    // checks comes after it), and the report names the one the result
    // came from.
    let searches = v["searches"].as_array().cloned().unwrap_or_default();
    assert!(searches.len() >= 2, "{v}");
    let spent: u64 = searches
        .iter()
        .filter_map(|s| s["evaluations"].as_u64())
        .sum();
    assert!(spent <= 12, "{v}");
    assert!(
        searches.iter().any(|s| s["name"] == v["search"])
            || v["search"] == "the file or its quarter turns",
        "{v}"
    );
    checks_and_cleans(&dir, &out_file);
}

/// Issue 17: a design flown on the wrong face (`box-classic-closed`: the
/// classic box kite turned a quarter about the vertical, closed side into
/// the wind, the string pushes) has no better neighbour within a compass
/// step; the optimiser starts from the best of the four quarter-turn
/// headings, so even a budget of a few designs leaves the string-pushes
/// region and reports the heading it changed.
#[test]
fn optimise_turns_a_kite_to_the_face_that_meets_the_wind() {
    let (dir, out_file, v) = optimise("box-classic-closed", 6, &["--flown", "0"], "turn");
    assert_eq!(v["before"]["verdict"], "string_pushes", "{v}");
    assert_ne!(v["after"]["verdict"], "string_pushes", "{v}");
    let yaw = v["changes"]
        .as_array()
        .and_then(|c| c.iter().find(|c| c["parameter"] == "orientation.yaw"))
        .unwrap_or_else(|| panic!("no heading change: {v}"));
    let turned = (yaw["after"].as_f64().unwrap_or(0.0) - yaw["before"].as_f64().unwrap_or(0.0))
        .rem_euclid(180.0);
    assert!((turned - 90.0).abs() < 45.0 + 1e-9, "{yaw}");
    // Nothing was flown (`--flown 0`): no flight margin, not a NaN.
    assert!(v["flight_margin"].is_null(), "{v}");
    // The file written has inline rod ends and loads back.
    let written = std::fs::read_to_string(&out_file).expect("written");
    assert!(!written.contains("[rod."), "{written}");
    checks_and_cleans(&dir, &out_file);
}

/// `kite optimise --flown 0` says in words that the check flights were not
/// flown (it printed "margin NaN").
#[test]
fn optimise_without_flights_says_not_flown() {
    let dir = std::env::temp_dir().join(format!("omniad-kite-cli-noflight-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    let out = omniad()
        .args([
            "kite",
            "optimise",
            "--evaluations",
            "2",
            "--flown",
            "0",
            "-o",
        ])
        .arg(dir.join("opt.toml"))
        .arg(kite("box-three-cell"))
        .output()
        .expect("run");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = text(&out.stdout);
    assert!(report.contains("not flown"), "{report}");
    assert!(!report.contains("NaN"), "{report}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Issue 17 acceptance: `kite optimise` turns three different bundled
/// designs that crash (`box-classic`, `box-classic-low-bridle`: their
/// roll-yaw mode grows; `winged-box`: its lateral swing diverges) into
/// designs that fly 60 s in 1 m/s gusts on seeds 1-3 (the optimiser's own
/// flight check flies seeds 101-103 only). It holds (BENCHMARKS, issue
/// 17, "after the merge (stop 18)"), but it is slow: per design the
/// default 600 designs checked and 24 flown (75 flights of 60 s), about
/// 4 min on the 2-core VM; a smaller budget is a different search (at 300
/// box-classic's result crashes on seed 1). Run with
/// `cargo test --release --test kite_cli -- --ignored`.
#[test]
#[ignore = "slow (3 x 600 designs checked, 75 flights): run with --release -- --ignored"]
fn optimise_makes_a_crashing_design_fly() {
    for name in ["box-classic", "box-classic-low-bridle", "winged-box"] {
        let (dir, _, v) = optimise(name, omniad_kite::optimise::DEFAULT_EVALUATIONS, &[], "fly");
        assert_ne!(v["before"]["verdict"], "stable", "{name}: {v}");
        assert_eq!(v["after"]["verdict"], "stable", "{name}: {v}");
        let flights: Vec<&str> = v["flights"]
            .as_array()
            .map(|f| f.iter().filter_map(|o| o.as_str()).collect())
            .unwrap_or_default();
        assert_eq!(flights, ["flies"; 3], "{name}: {v}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
