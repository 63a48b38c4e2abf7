//! The fuzz targets' bodies (issue 18): each takes arbitrary bytes and must
//! return without panicking, hanging or allocating without bound, whatever
//! the bytes. `fuzz_targets/*.rs` hand them to libFuzzer
//! (`scripts/fuzz.sh`); `tests/fuzz_corpus.rs` runs them on stable over
//! `fuzz/corpus/<target>/` and simple mutations of it.

use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// The coefficient-file decoder (`omniad_core::file::decode`), in both
/// precisions; a file that decodes must encode again.
pub fn coefficients(data: &[u8]) {
    let _ = omniad_core::file::decode::<f32>(data);
    if let Ok(model) = omniad_core::file::decode::<f64>(data) {
        let mut buf = vec![0u8; omniad_core::file::MAX_FILE_SIZE];
        assert!(
            omniad_core::file::encode(&model, &mut buf).is_ok(),
            "a decoded file must encode again"
        );
    }
}

/// The recording format's track readers (marker and pose CSVs) on a
/// two-marker object: a marker take never spans more than
/// `MAX_TAKE_FRAMES` frames.
pub fn tracks(data: &[u8]) {
    use omniad_acquire::input::recording::Object;
    use omniad_acquire::input::tracks::{parse_markers, parse_poses, MAX_TAKE_FRAMES};
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let object = Object {
        name: "fuzz".into(),
        mass: 0.05,
        inertia: Matrix3::from_diagonal(&Vector3::new(1e-3, 1e-3, 1.5e-3)),
        reference_length: 0.5,
        pole: Vector3::z(),
        markers: vec![
            ("m0".into(), Vector3::new(0.1, 0.0, 0.0)),
            ("m1".into(), Vector3::new(0.0, 0.1, 0.0)),
        ],
    };
    let path = Path::new("fuzz.csv");
    if let Ok(epochs) = parse_markers(path, text, &object, 60.0) {
        assert!(
            epochs.len() as i64 <= MAX_TAKE_FRAMES,
            "take length bounded"
        );
    }
    let _ = parse_poses(path, text);
}

/// The kite file reader (`omniad_kite::spec`): parse, then validate.
pub fn kite_spec(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(spec) = omniad_kite::spec::KiteSpec::parse(text) {
        let _ = spec.validate();
    }
}

/// The firmware's frame deframer: every byte stream splits into frames,
/// each decoded or rejected.
pub fn deframer(data: &[u8]) {
    let mut d = omniad_fw_pipeline::Deframer::new();
    for &b in data {
        let _ = d.push(b);
    }
    let _ = d.finish();
}
