//! Puts memory.x on the linker path and generates the default coefficient
//! file (`kite.omni`, see omniad-fw-pipeline's `kite` module) that the
//! firmware embeds in flash.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");

    let model = omniad_fw_pipeline::kite::default_model().expect("default kite model");
    let mut buf = vec![0u8; omniad_core::file::MAX_FILE_SIZE];
    let n = omniad_core::file::encode(&model, &mut buf).expect("encode kite model");
    fs::write(out.join("kite.omni"), &buf[..n]).expect("write kite.omni");
}
