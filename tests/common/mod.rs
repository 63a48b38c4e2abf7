//! Helpers shared by the end-to-end tests of the `omniad` binary.
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The binary under test.
pub fn omniad() -> Command {
    Command::new(env!("CARGO_BIN_EXE_omniad"))
}

/// The bundled foam plate.
pub fn plate() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/plate.omni")
}

/// Runs `omniad ARGS` with `stdin` on its standard input.
pub fn run_with_stdin(args: &[&str], stdin: &str) -> Output {
    let mut child = omniad()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes())
        .expect("write");
    child.wait_with_output().expect("wait")
}

/// Lossy UTF-8 text of an output stream.
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
