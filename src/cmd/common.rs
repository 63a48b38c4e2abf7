//! Helpers shared by commands: reading coefficient files with errors that
//! name the file.

use anyhow::{Context, Result};
use omniad_core::{file, Coefficients};
use std::path::Path;

/// Reads and decodes a `.omni` file in f64, naming the file in any error.
pub fn read_coefficients(path: &Path) -> Result<Coefficients<f64>> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    file::decode::<f64>(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// Encodes and writes a `.omni` file.
pub fn write_coefficients(path: &Path, model: &Coefficients<f64>) -> Result<()> {
    let mut buf = vec![0u8; file::MAX_FILE_SIZE];
    let n = file::encode(model, &mut buf)
        .map_err(|e| anyhow::anyhow!("encoding {}: {e}", path.display()))?;
    let bytes = buf
        .get(..n)
        .context("encoder reported more bytes than its buffer")?;
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}
