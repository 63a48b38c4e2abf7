//! Regenerates the golden coefficient files:
//! `cargo run -p omniad-core --example make_golden`
//! (writes `core/tests/golden/v1.omni`).
#![allow(clippy::expect_used)]

#[path = "../tests/golden/model.rs"]
mod model;

fn main() {
    let m = model::golden_model();
    let mut buf = [0u8; omniad_core::file::MAX_FILE_SIZE];
    let n = omniad_core::file::encode(&m, &mut buf).expect("encodes");
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/v1.omni");
    std::fs::write(path, buf.get(..n).expect("within buffer")).expect("writable");
    println!("wrote {path} ({n} bytes)");
}
