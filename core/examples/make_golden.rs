//! Regenerates the golden coefficient files:
//! `cargo run -p omniad-core --example make_golden`
//! (writes `core/tests/golden/v1.omni` and `v1-torque6.omni`, a torque
//! of its own degree).
#![allow(clippy::expect_used)]

#[path = "../tests/golden/model.rs"]
mod model;

fn main() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden");
    for (m, name) in [
        (model::golden_model(), "v1.omni"),
        (model::golden_torque_model(), "v1-torque6.omni"),
    ] {
        let mut buf = [0u8; omniad_core::file::MAX_FILE_SIZE];
        let n = omniad_core::file::encode(&m, &mut buf).expect("encodes");
        let path = format!("{dir}/{name}");
        std::fs::write(&path, buf.get(..n).expect("within buffer")).expect("writable");
        println!("wrote {path} ({n} bytes)");
    }
}
