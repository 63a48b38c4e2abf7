//! Reading and writing a coefficient file (`.omni`,
//! [`omniad_core::file`]): the one place that puts a model on disk or
//! takes one from it, for the commands (`fit -o`, `residual --coeffs`,
//! ...), `synth`'s `truth/model.omni` and `residual`'s reading of it.

use crate::error::{Error, Result};
use omniad_core::{file, Coefficients};
use std::path::Path;

/// Encodes `model` and writes it to `path` atomically (a temporary file
/// renamed into place: an existing file is replaced only by a complete
/// new one). Errors name the file.
pub fn write(path: &Path, model: &Coefficients<f64>) -> Result<()> {
    let mut buf = vec![0u8; file::MAX_FILE_SIZE];
    let n = file::encode(model, &mut buf)
        .map_err(|e| Error::Data(format!("encoding {}: {e}", path.display())))?;
    let bytes = buf.get(..n).ok_or_else(|| {
        Error::Data(format!(
            "encoding {}: the encoder reported more bytes than its buffer",
            path.display()
        ))
    })?;
    omniad_io::write_atomic(path, bytes).map_err(|e| Error::io(path, e))
}

/// Reads and decodes a `.omni` file in f64. Reads at most the format's
/// maximum size, so a device or a huge file is an error at once, not
/// gigabytes read before the header check. Errors name the file
/// (`Error::Io` when it cannot be read, `Error::Data` when it does not
/// decode).
pub fn read(path: &Path) -> Result<Coefficients<f64>> {
    let bytes =
        omniad_io::read_capped(path, file::MAX_FILE_SIZE).map_err(|e| Error::io(path, e))?;
    file::decode::<f64>(&bytes).map_err(|e| Error::Data(format!("{}: {e}", path.display())))
}
