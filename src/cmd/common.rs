//! Helpers shared by commands: reading coefficient files with errors that
//! name the file.

use anyhow::Result;
use omniad_acquire::{omni_file, Error};
use omniad_core::Coefficients;
use std::path::Path;

/// Reads and decodes a `.omni` file in f64, naming the file in any error
/// ([`omni_file::read`]: at most the format's maximum size is read).
pub fn read_coefficients(path: &Path) -> Result<Coefficients<f64>> {
    omni_file::read(path).map_err(|e| match e {
        Error::Io { path, source } => {
            anyhow::Error::new(source).context(format!("cannot read {}", path.display()))
        }
        other => anyhow::anyhow!("{other}"),
    })
}

/// Encodes and writes a `.omni` file atomically (an existing file is
/// replaced only by a complete new one; [`omni_file::write`]).
pub fn write_coefficients(path: &Path, model: &Coefficients<f64>) -> Result<()> {
    omni_file::write(path, model).map_err(|e| anyhow::anyhow!("{e}"))
}

/// An error before any work when `output` is one of the files the command
/// reads (`inputs`): its result would replace the user's data even when
/// it succeeds (`omniad_io::refuse_input`).
pub fn refuse_input<P: AsRef<Path>>(output: &Path, inputs: &[P]) -> Result<()> {
    omniad_io::refuse_input(output, inputs).map_err(|e| anyhow::anyhow!("{e}"))
}
