//! Helpers shared by commands: reading coefficient files with errors that
//! name the file.

use anyhow::{Context, Result};
use omniad_core::{file, Coefficients};
use std::path::Path;

/// Reads and decodes a `.omni` file in f64, naming the file in any error.
/// Reads at most the format's maximum size, so a device or a huge file is
/// an error at once, not gigabytes read before the header check.
pub fn read_coefficients(path: &Path) -> Result<Coefficients<f64>> {
    let bytes = omniad_io::read_capped(path, file::MAX_FILE_SIZE)
        .with_context(|| format!("cannot read {}", path.display()))?;
    file::decode::<f64>(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// Encodes and writes a `.omni` file atomically (an existing file is
/// replaced only by a complete new one; [`omniad_acquire::omni_file`]).
pub fn write_coefficients(path: &Path, model: &Coefficients<f64>) -> Result<()> {
    omniad_acquire::omni_file::write(path, model).map_err(|e| anyhow::anyhow!("{e}"))
}
