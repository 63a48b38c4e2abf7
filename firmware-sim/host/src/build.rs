//! Building the firmware: `cargo build --release --bins` in the firmware
//! workspace, with its own target directory and none of the caller's
//! cargo settings (a harness started by `cargo test` or `cargo run` must
//! not pass on its host target or flags to the thumbv7em build).

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The firmware's target triple (`firmware-sim/.cargo/config.toml`).
const TARGET: &str = "thumbv7em-none-eabihf";

/// Variables cargo sets for (or a user sets around) the calling build that
/// would change the firmware's.
const CALLER_SETTINGS: [&str; 5] = [
    "CARGO_TARGET_DIR",
    "CARGO_BUILD_TARGET",
    "RUSTFLAGS",
    "CARGO_ENCODED_RUSTFLAGS",
    "CARGO_BUILD_RUSTFLAGS",
];

/// The firmware workspace: `explicit`, else `$OMNIAD_FIRMWARE_DIR`, else
/// the `firmware-sim/` this crate was built from.
pub fn firmware_dir(explicit: Option<&Path>) -> PathBuf {
    explicit
        .map(Path::to_path_buf)
        .or_else(|| std::env::var_os("OMNIAD_FIRMWARE_DIR").map(PathBuf::from))
        .unwrap_or_else(|| {
            let host = Path::new(env!("CARGO_MANIFEST_DIR"));
            host.parent().unwrap_or(host).to_path_buf()
        })
}

/// Builds the firmware (release, both binaries) in `dir/target`. The
/// error carries cargo's output, which says so when the target is not
/// installed.
pub fn build_firmware(dir: &Path) -> Result<()> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(dir)
        .args(["build", "--release", "--bins", "--target-dir"])
        .arg(dir.join("target"));
    for var in CALLER_SETTINGS {
        cmd.env_remove(var);
    }
    let out = cmd
        .output()
        .context("cannot run cargo to build the firmware")?;
    if !out.status.success() {
        bail!(
            "firmware build failed in {}:\n{}",
            dir.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(())
}

/// Where [`build_firmware`] puts binary `bin`.
pub(crate) fn elf_path(dir: &Path, bin: &str) -> PathBuf {
    dir.join("target").join(TARGET).join("release").join(bin)
}
