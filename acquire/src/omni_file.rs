//! Writing a coefficient file (`.omni`, [`omniad_core::file`]): the one
//! place that encodes a model and puts it on disk, for the commands
//! (`fit -o`, `residual -o`, ...) and for `synth`'s `truth/model.omni`.

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
