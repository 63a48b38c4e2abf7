//! Issue 18, one test per class of bad input the readers must refuse (or,
//! for other encodings, accept): bounded frame indices, impossible
//! recording sets, CSV encodings (tracker imports: `input::import`'s
//! tests). Each error names the file and the line or field.

use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::input::state_csv::read_states;
use omniad_acquire::synth::write::generate;
use omniad_acquire::synth::{SynthConfig, SynthObject};
use std::path::Path;

/// A small synthetic set (two drops) in `dir`.
fn set(dir: &Path) {
    let cfg = SynthConfig {
        object: SynthObject::Plate,
        seed: 7,
        takes: (2, 0),
        ..SynthConfig::default()
    };
    generate(dir, &cfg).expect("synth");
}

fn edit(path: &Path, f: impl FnOnce(String) -> String) {
    let text = std::fs::read_to_string(path).expect("read");
    std::fs::write(path, f(text)).expect("write");
}

/// The load error of the set in `dir` after `f` edits its recording.toml.
fn toml_error(f: impl FnOnce(String) -> String) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    set(dir.path());
    edit(&dir.path().join("recording.toml"), f);
    RecordingSet::load(dir.path())
        .expect_err("must be refused")
        .to_string()
}

fn assert_names(e: &str, needles: &[&str]) {
    for n in needles {
        assert!(e.contains(n), "error should name {n:?}: {e}");
    }
}

#[test]
fn frame_indices_are_bounded_naming_file_line_and_value() {
    for (row, value) in [
        ("4294967295,m0,100,100", "4294967295"),
        ("1000000,m0,100,100", "1000000"),
        ("99999999999,m0,100,100", "99999999999"),
    ] {
        let dir = tempfile::tempdir().expect("tempdir");
        set(dir.path());
        let take = dir.path().join("drop-01.csv");
        edit(&take, |t| format!("{t}{row}\n"));
        let lines = std::fs::read_to_string(&take)
            .expect("read")
            .lines()
            .count();
        let start = std::time::Instant::now();
        let e = RecordingSet::load(dir.path())
            .expect_err("stray row")
            .to_string();
        assert!(start.elapsed().as_secs() < 5, "refused at once");
        assert_names(&e, &["drop-01.csv", &format!(":{lines}:"), value]);
    }
}

#[test]
fn impossible_sets_are_refused_naming_the_field_or_take() {
    let cases: [(&str, &str, &[&str]); 7] = [
        ("width = 720", "width = 0", &["camera.width"]),
        ("fps = 60", "fps = 1e-6", &["camera.fps"]),
        (
            "distortion = [-0.05,",
            "distortion = [1e6,",
            &["camera.distortion"],
        ),
        (
            "inertia = [[0.0010016, 0, 0], [0, 0.00036159999999999995, 0], [0, 0, 0.00136]]",
            "inertia = [[0.001, 0, 0], [0, 0.001, 0], [0, 0, 0.003]]",
            &["object.inertia", "triangle"],
        ),
        (
            "m1 = [-0.135, 0.225, 0.01]",
            "m1 = [0.135, 0.225, 0.01]",
            &["object.markers.m1", "m0"],
        ),
        (
            "name = \"drop-02\"",
            "name = \"DROP-01\"",
            &["take[1].name", "drop-01", "DROP-01"],
        ),
        ("name = \"drop-02\"", "name = \"../x\"", &["take[1].name"]),
    ];
    for (from, to, needles) in cases {
        let e = toml_error(|t| {
            assert!(t.contains(from), "fixture holds {from:?}");
            t.replacen(from, to, 1)
        });
        assert_names(&e, needles);
    }
}

#[test]
fn markers_behind_the_camera_at_the_initial_pose_are_refused_naming_the_take() {
    // The camera looks along world +y from y = -7: y = -20 is behind it.
    let e = toml_error(|t| {
        let start = t.find("initial_position = [").expect("a marker take");
        let end = start + t[start..].find('\n').expect("line end");
        format!("{}initial_position = [0, -20, 0]{}", &t[..start], &t[end..])
    });
    assert_names(&e, &["take[0]", "drop-01", "behind the camera"]);
}

#[test]
fn csv_files_with_bom_crlf_or_cr_read_like_plain_ones() {
    let dir = tempfile::tempdir().expect("tempdir");
    set(dir.path());
    let plain = RecordingSet::load(dir.path()).expect("load");
    let truth = dir.path().join("truth/drop-01.csv");
    let states = read_states(&truth).expect("states");
    for (bom, eol) in [
        ("\u{feff}", "\n"),
        ("", "\r\n"),
        ("\u{feff}", "\r\n"),
        ("", "\r"),
    ] {
        for f in ["drop-01.csv", "drop-02.csv", "truth/drop-01.csv"] {
            let p = dir.path().join(f);
            edit(&p, |t| {
                let t = t.trim_start_matches('\u{feff}').replace("\r\n", "\n");
                format!("{bom}{}", t.replace(['\r', '\n'], "\n").replace('\n', eol))
            });
        }
        let again = RecordingSet::load(dir.path()).expect("load");
        assert_eq!(again.takes, plain.takes, "{eol:?}");
        assert_eq!(read_states(&truth).expect("states"), states, "{eol:?}");
    }
}
