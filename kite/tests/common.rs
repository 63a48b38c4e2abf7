//! Shared test helpers: the shipped library and kite files.
#![allow(dead_code)]

use omniad_kite::{Design, Library};
use std::path::PathBuf;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn library() -> Library {
    Library::load(&repo().join("data/primitives")).expect("shipped primitive library loads")
}

pub fn kite(name: &str) -> Design {
    let path = repo().join("data/kites").join(format!("{name}.toml"));
    Design::load(&path, &library()).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}

/// A kite kept under `kite/tests/fixtures/` (e.g. a bundled design as it
/// was before a change, for tests about that kite's physics).
pub fn fixture(name: &str) -> Design {
    let path = repo()
        .join("kite/tests/fixtures")
        .join(format!("{name}.toml"));
    Design::load(&path, &library()).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}
