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

/// The residual report of a set made by `omniad synth SET SYNTH_ARGS`,
/// and the names it selects.
fn residual_of_synth(synth_args: &str) -> (serde_json::Value, Vec<String>) {
    let tmp = tempfile::tempdir().expect("tempdir");
    let set = tmp.path().join("set");
    let set_s = set.to_str().expect("utf-8");
    let mut args = vec!["synth", set_s];
    args.extend(synth_args.split(' '));
    omniad(&args);
    let r = residual(set_s, &[]);
    let names = r["selected"]
        .as_array()
        .expect("selected")
        .iter()
        .filter_map(|n| n.as_str().map(str::to_owned))
        .collect();
    (r, names)
}

/// The report's candidate `effect` tried at selection step `step`.
fn candidate<'a>(r: &'a serde_json::Value, effect: &str, step: u64) -> &'a serde_json::Value {
    r["candidates"]
        .as_array()
        .expect("candidates")
        .iter()
        .find(|c| c["effect"] == effect && c["step"] == step)
        .unwrap_or_else(|| panic!("{effect} tried at step {step}: {r:#}"))
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
    let kept = candidate(&r, "buoyancy", 0);
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
    // Refit around the effect: the buoyancy found is held in the
    // reconstruction's process model of the next round, and that round's
    // states select it again.
    let refit = &r["refit"];
    let held = refit["rounds"][1]["effects"]["buoyancy"][0].as_f64();
    assert!(
        held.is_some_and(|h| (h - 0.012).abs() < 0.15 * 0.012),
        "refit rounds: {refit:#}"
    );
    assert_eq!(refit["rounds"][1]["selected"][0], "buoyancy", "{refit:#}");
    assert_eq!(refit["confirmed"], true, "{refit:#}");
    assert_item7_keys(&r);
    // The share of a force beyond C_F's reach: a force linear in V is
    // nearly |V|² times a function of direction over the speeds each
    // direction is flown at (C_F takes most of it), gravity seen from the
    // body is not; a one-parameter effect's share does not depend on its
    // fitted value.
    let beyond = |e: &str| {
        let b = candidate(&r, e, 0)["beyond_cf"].as_f64();
        b.unwrap_or_else(|| panic!("{e}: beyond_cf missing: {r:#}"))
    };
    let (drag, lift) = (beyond("linear_drag"), beyond("buoyancy"));
    assert!(
        (0.0..=1.0).contains(&drag) && (0.0..=1.0).contains(&lift) && drag < 0.5 * lift,
        "beyond C_F: linear drag {drag}, buoyancy {lift}"
    );
    assert!(plots.join("residual-vs-spin.svg").exists());
    // The per-frame residuals behind the figures: both models, every
    // analysed frame, and the base model's RMS is the report's.
    let table = std::fs::read_to_string(plots.join("residual-frames.csv")).expect("frames csv");
    let rms = rms_of(&table, "base,");
    assert!(
        (rms - before).abs() < 1e-6 * before.max(1e-12) + 1e-9,
        "residual-frames.csv base RMS {rms}, report {before}"
    );
    let first = rms_of(&table, "first_round,");
    let first_report = r["first_round_baseline"]["heldout_force_rms"]
        .as_f64()
        .expect("first round");
    assert!(
        (first - first_report).abs() < 1e-6 * first_report + 1e-9,
        "residual-frames.csv first-round RMS {first}, report {first_report}"
    );
    let extended = table.lines().filter(|l| l.starts_with("extended,")).count();
    assert_eq!(
        extended as u64,
        r["frames"].as_u64().expect("frames"),
        "{table:.300}"
    );
    // Before and after are scored on the same frames: row for row, the
    // same takes, times and measured forces.
    let frame_keys = |prefix: &str| -> Vec<String> {
        table
            .lines()
            .filter_map(|l| l.strip_prefix(prefix))
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                [&f[..2], &f[11..14]].concat().join(",")
            })
            .collect()
    };
    assert_eq!(frame_keys("base,"), frame_keys("extended,"));
    // The generating model itself (`truth/model.omni`, held as it is) on
    // the same frames: buoyancy's force lies far beyond what C_F can take
    // over, so the exactly right model leaves much less than the base.
    let truth_rms = r["truth_model"]["heldout_force_rms"]
        .as_f64()
        .expect("truth_model");
    assert!(
        truth_rms < 0.7 * before,
        "truth model {truth_rms} N, base {before} N"
    );
    let info = omniad(&["info", model.to_str().expect("utf-8")]);
    assert!(info.contains("buoyancy"), "{info}");

    let clean = tmp.path().join("clean");
    let clean_s = clean.to_str().expect("utf-8");
    let mut args = vec!["synth", clean_s];
    args.extend_from_slice(&common);
    omniad(&args);
    let r = residual(clean_s, &[]);
    assert_eq!(r["selected"], serde_json::json!([]), "{r:#}");
    // Nothing selected, so no refit: the truth is scored on the first
    // round's frames, which is what `--coeffs truth/model.omni` scores it
    // on as a given baseline (the same states; nothing of it fitted).
    let truth = clean.join("truth/model.omni");
    let given = residual(clean_s, &["--coeffs", truth.to_str().expect("utf-8")]);
    let (a, b) = (
        r["truth_model"]["heldout_force_rms"]
            .as_f64()
            .expect("truth"),
        given["baseline"]["heldout_force_rms"]
            .as_f64()
            .expect("given"),
    );
    assert!(
        (a - b).abs() <= 1e-9 * b,
        "truth_model {a} N, --coeffs {b} N"
    );
    // C_F error "before" is the given model's: nothing is selected on top
    // of it, so it is the "after" model too (it was the first round's own
    // fit, 8 % off, while "after" said 0 %).
    assert_eq!(given["selected"], serde_json::json!([]), "{given:#}");
    let cf = &given["cf_error_vs_truth"];
    assert!(cf["before"].is_number(), "{cf:#}");
    assert_eq!(cf["before"], cf["after"], "{cf:#}");
}

/// Runs omniad expecting failure; returns stderr.
fn omniad_fails(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_omniad"))
        .args(args)
        .output()
        .expect("run omniad");
    assert!(!out.status.success(), "omniad {args:?} succeeded");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// RMS of the residual columns (the last three) of the rows of a
/// residual-frames.csv `table` that start with `prefix`.
fn rms_of(table: &str, prefix: &str) -> f64 {
    let squares: Vec<f64> = table
        .lines()
        .filter(|l| l.starts_with(prefix))
        .map(|l| {
            let r: Vec<f64> = l
                .split(',')
                .skip(15)
                .map(|v| v.parse().expect("number"))
                .collect();
            r.iter().map(|v| v * v).sum::<f64>()
        })
        .collect();
    (squares.iter().sum::<f64>() / squares.len().max(1) as f64).sqrt()
}

/// Item 7's keys, all present.
fn assert_item7_keys(r: &serde_json::Value) {
    for side in ["baseline", "first_round_baseline", "after"] {
        for k in ["heldout_force_rms", "heldout_torque_rms"] {
            assert!(r[side][k].as_f64().is_some(), "{side}.{k} missing: {r:#}");
        }
    }
    assert!(r["selected"].is_array(), "selected missing");
    // Before and after on the same frames (this set's rounds build them).
    assert_eq!(r["baseline_frames"], "final_round", "{r:#}");
    assert_eq!(
        r["selected_params"].as_array().map(|a| a.len()),
        r["selected"].as_array().map(|a| a.len()),
        "a parameter list per selected effect: {r:#}"
    );
    let cands = r["candidates"].as_array().expect("candidates");
    assert!(!cands.is_empty());
    for c in cands {
        for k in ["effect", "heldout_force_rms", "heldout_torque_rms"] {
            assert!(!c[k].is_null(), "candidate key {k} missing: {c:#}");
        }
        assert!(
            c["params"].is_array() && c["uncertainty"].is_array(),
            "{c:#}"
        );
    }
    for k in ["base_m", "extended_m"] {
        assert!(
            r["resimulation"][k].as_f64().is_some(),
            "resimulation.{k}: {r:#}"
        );
    }
    // Every take analysed is re-simulated on its own, and the set's RMS
    // is the takes' frames pooled: it lies within their range.
    let takes = r["resimulation"]["takes"].as_array().expect("takes");
    assert!(!takes.is_empty(), "{r:#}");
    for k in ["base_m", "extended_m"] {
        let each: Vec<f64> = takes.iter().filter_map(|t| t[k].as_f64()).collect();
        assert_eq!(each.len(), takes.len(), "{k}: {takes:#?}");
        let all = r["resimulation"][k].as_f64().expect("rms");
        let (lo, hi) = each
            .iter()
            .fold((f64::MAX, 0.0f64), |(lo, hi), &e| (lo.min(e), hi.max(e)));
        assert!(lo <= all && all <= hi, "{k}: {all} outside [{lo}, {hi}]");
    }
}

/// `--coeffs FILE`: the panel model of the synthetic plate (the generator's
/// own aerodynamics) as the base model of a buoyant plate set: buoyancy is
/// what it lacks; bad files are refused naming the file, writing nothing.
#[test]
fn residual_with_given_coeffs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let set = tmp.path().join("buoyant");
    let set_s = set.to_str().expect("utf-8");
    omniad(&[
        "synth",
        set_s,
        "--object",
        "plate",
        "--seed",
        "5",
        "--drops",
        "6",
        "--spins",
        "4",
        "--effect",
        "buoyancy=4",
    ]);
    let path = |n: &str| tmp.path().join(n).to_str().expect("utf-8").to_owned();
    let (plate, boxm) = (path("plate.omni"), path("box.omni"));
    omniad(&[
        "panel",
        "--shape",
        "plate",
        "--size",
        "0.3,0.5,0.02",
        "--mass",
        "0.048",
        "-o",
        &plate,
    ]);
    omniad(&[
        "panel",
        "--shape",
        "box",
        "--size",
        "0.3,0.4,0.2",
        "--mass",
        "0.04",
        "-o",
        &boxm,
    ]);
    let r = residual(set_s, &["--coeffs", &plate]);
    assert_item7_keys(&r);
    assert_eq!(r["baseline_model"], "given", "{r:#}");
    let floor = r["markers_only_force_noise_rms"]
        .as_f64()
        .expect("markers-only noise");
    assert!(floor > 0.0 && floor.is_finite(), "noise floor {floor}");
    assert_eq!(r["selected"][0], "buoyancy", "{r:#}");
    // A held model: nothing takes an effect's force over.
    assert!(candidate(&r, "buoyancy", 0)["beyond_cf"].is_null(), "{r:#}");
    let vb = candidate(&r, "buoyancy", 0)["params"][0]
        .as_f64()
        .expect("V_b");
    assert!(
        (vb - 0.012).abs() < 0.15 * 0.012,
        "V_b {vb} (synthesised 0.012)"
    );

    let (out, plots) = (path("ext.omni"), path("plots"));
    let garbage = path("garbage.omni");
    std::fs::write(&garbage, b"not a coefficient file").expect("write");
    let missing = path("missing.omni");
    for (file, extra, says) in [
        (&garbage, None, ""),
        (&missing, None, "cannot read"),
        (&boxm, None, "pole"),
        (&plate, Some("4"), "degree"),
    ] {
        let mut args = vec![
            "residual", set_s, "--coeffs", file, "-o", &out, "--plots", &plots,
        ];
        if let Some(d) = extra {
            args.extend(["--degree", d]);
        }
        let err = omniad_fails(&args);
        assert!(err.contains(file.as_str()) && err.contains(says), "{err}");
        assert!(!std::path::Path::new(&out).exists() && !std::path::Path::new(&plots).exists());
    }
}

/// Refit around the effect: a wind found on states reconstructed without
/// it is put into the process model and the takes are filtered again;
/// the wind after the refits is much nearer the truth than the first
/// round's linear estimate (which the first, windless states bias; the
/// wind search on those states starts from it too), and it is reported,
/// not stored in the object's model.
#[test]
fn residual_refilters_with_the_wind_it_finds() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // Not "windy": the model file records its source folder.
    let set = tmp.path().join("set");
    let set_s = set.to_str().expect("utf-8");
    omniad(&[
        "synth", set_s, "--object", "plate", "--seed", "3", "--drops", "6", "--spins", "4",
        "--wind", "1,0,0",
    ]);
    let model = tmp.path().join("extended.omni");
    let r = residual(set_s, &["-o", model.to_str().expect("utf-8")]);
    let names = r["selected"].as_array().expect("selected");
    assert!(names.iter().any(|n| n == "wind"), "{r:#}");
    let refit = &r["refit"];
    assert!(refit["refits"].as_u64().expect("refits") >= 1, "{refit:#}");
    let vec3 = |v: &serde_json::Value| -> [f64; 3] {
        std::array::from_fn(|i| v[i].as_f64().expect("wind component"))
    };
    let err = |w: [f64; 3]| ((w[0] - 1.0).powi(2) + w[1].powi(2) + w[2].powi(2)).sqrt();
    let first = match &refit["wind_search"]["linear"] {
        serde_json::Value::Null => &refit["wind_before_refilter"],
        linear => linear,
    };
    let before = err(vec3(first));
    let after = err(vec3(&r["wind"]));
    assert!(
        after < 0.25 && after < 0.5 * before,
        "wind error {before:.3} m/s before the refilter, {after:.3} after: {refit:#}"
    );
    let info = omniad(&["info", model.to_str().expect("utf-8")]);
    assert!(!info.contains("wind"), "{info}");
}

/// A wind the first round's linear candidate cannot reach: in 2.5 m/s
/// the one Gauss-Newton step from no wind points up (0, -0.3, 1.3 m/s)
/// and nothing was selected (held-out force 0.50 N, C_F 54 % off). The
/// wind search starts from the best horizontal wind and descends the
/// held-out error (`residual/refit/wind_search.rs`); measured: start
/// (2, 0, 0), wind after the refits (2.51, 0.03, 0.03) m/s, held-out force
/// 0.499 -> 0.043 N, C_F 53.6 -> 6.8 %.
#[test]
fn residual_finds_a_wind_beyond_the_linear_candidates_reach() {
    let (r, names) =
        residual_of_synth("--object plate --seed 3 --drops 6 --spins 4 --wind 2.5,0,0");
    let search = &r["refit"]["wind_search"];
    assert_eq!(search["accepted"], true, "{search:#}");
    let start: Vec<f64> = (0..3)
        .map(|i| search["start"][i].as_f64().expect("start"))
        .collect();
    assert!(
        start[2].abs() < 1e-9 && start[0] > 0.0,
        "a horizontal start: {start:?}"
    );
    assert_eq!(names.first().map(String::as_str), Some("wind"), "{names:?}");
    let w: Vec<f64> = (0..3)
        .map(|i| r["wind"][i].as_f64().expect("wind"))
        .collect();
    let err = ((w[0] - 2.5).powi(2) + w[1].powi(2) + w[2].powi(2)).sqrt();
    assert!(err < 0.3, "wind {w:?} vs (2.5, 0, 0)");
    let before = r["baseline"]["heldout_force_rms"].as_f64().expect("before");
    let after = r["after"]["heldout_force_rms"].as_f64().expect("after");
    assert!(
        after <= 0.5 * before,
        "held-out force {before} -> {after} N"
    );
    let cf = r["cf_error_vs_truth"]["after"].as_f64().expect("C_F error");
    assert!(cf < 0.10, "C_F {:.1} % off the truth", cf * 100.0);
}

/// Issue 15, added mass: on a plate whose air carries Kirchhoff added
/// mass (and nothing else), the selection keeps added mass and is *not*
/// also given buoyancy or the gravity coupling: with added mass those
/// reproduce the measured force itself (`identify.rs`) and would trade
/// against C_F's scale (before the check: buoyancy V_b 0.0159 m³, five
/// times the plate's volume, and C_F 63 % off on this set). Bound on C_F
/// after: measured 5.5 % (seed 1), 4.0 % (seed 2); 10 % is the issue's
/// acceptance.
#[test]
fn added_mass_is_not_also_given_buoyancy() {
    let (r, names) = residual_of_synth("--object plate --seed 1 --effect added_mass=0.3");
    assert_eq!(
        names.first().map(String::as_str),
        Some("added_mass"),
        "{r:#}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n == "buoyancy" || n == "gravity_coupling"),
        "{names:?}"
    );
    let refused = candidate(&r, "buoyancy", 1);
    let why = refused["rejected"].as_str().unwrap_or("");
    assert!(why.contains("not identifiable"), "{refused:#}");
    let cf = r["cf_error_vs_truth"]["after"].as_f64().expect("C_F error");
    assert!(cf < 0.10, "C_F {:.1} % off the truth after", cf * 100.0);
}

/// An added mass the first states hide: on plate `added_mass=0.3` seed 5
/// the first round's states (reconstructed without the acceleration
/// reaction) give M_a (-3.2, -3.8, -0.3) g against the truth (0.0, 0.0,
/// 6.6) g, nothing positive to try, and before the markers' likelihood
/// probe the generic blocks were kept (C_F 13.2 % off). The probe picks a
/// scale of the inertia-equivalent box's potential-flow tensor and the
/// rounds confirm added mass. Measured: scale 0.25 (zz 5.5 g), M_a zz 4.7
/// g, C_F 8.5 -> 5.1 %, held-out ratio 0.26 (the truth's 0.34).
#[test]
fn an_added_mass_the_first_states_hide_is_found_by_the_markers() {
    let (r, names) = residual_of_synth("--object plate --seed 5 --effect added_mass=0.3");
    let probe = &r["refit"]["added_mass_probe"];
    assert!(probe["chosen"].as_f64().is_some(), "{probe:#}");
    assert_eq!(names, ["added_mass"], "{r:#}");
    let zz = r["selected_params"][0][2].as_f64().expect("M_a zz");
    assert!((0.0033..0.0099).contains(&zz), "M_a zz {zz} (truth 0.0066)");
    let cf = r["cf_error_vs_truth"]["after"].as_f64().expect("C_F error");
    assert!(cf < 0.10, "C_F {:.1} % off the truth after", cf * 100.0);
    let ratio = r["after"]["heldout_force_rms"].as_f64().unwrap_or(f64::NAN)
        / r["baseline"]["heldout_force_rms"]
            .as_f64()
            .unwrap_or(f64::NAN);
    assert!(ratio <= 0.5, "held-out ratio {ratio}");
}

/// Air whose added mass has no acceleration reaction (a stateless fluid
/// model's, such as MuJoCo's ellipsoid model): the coupling alone explains
/// it, ahead of added mass (whose `-M_a dV/dt` columns it does not have)
/// and of the 27-number spin coupling; M_a's large (normal) entry comes
/// out near the synthesised one (the inscribed ellipsoid's, 0.022 kg).
#[test]
fn added_mass_without_acceleration_reaction_is_the_coupling() {
    let (r, names) = residual_of_synth("--object plate --seed 1 --effect added_mass_coupling=1");
    assert_eq!(
        names.first().map(String::as_str),
        Some("added_mass_coupling"),
        "{r:#}"
    );
    assert!(!names.iter().any(|n| n == "added_mass"), "{names:?}");
    // The markers' likelihood judged the coupling against added mass and
    // kept it: the rounds start from the coupling's refinement, which the
    // probe made (the path that reuses it rather than fitting it again).
    let probe = &r["refit"]["added_mass_probe"];
    assert!(probe["chosen"].is_null(), "{probe:#}");
    assert!(
        probe["rival"]["log_likelihood"].as_f64().is_some(),
        "{probe:#}"
    );
    let kept = r["candidates"]
        .as_array()
        .expect("candidates")
        .iter()
        .find(|c| c["effect"] == "added_mass_coupling" && c["rejected"].is_null())
        .expect("kept");
    let zz = kept["params"][2].as_f64().expect("M_a zz");
    assert!((zz / 0.022 - 1.0).abs() < 0.2, "M_a zz {zz}");
}
