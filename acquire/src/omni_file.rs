//! Reading and writing a coefficient file (`.omni`,
//! [`omniad_core::file`]): the one place that puts a model on disk or
//! takes one from it, for the commands (`fit -o`, `residual --coeffs`,
//! ...), `synth`'s `truth/model.omni` and `residual`'s reading of it.

use crate::error::{Error, Result};
use omniad_core::{file, Coefficients};
use std::path::Path;

/// Encodes `model` and writes it to `path` atomically (a temporary file
/// renamed into place: an existing file is replaced only by a complete
/// new one). The encoded bytes are read back first ([`read`]'s checks),
/// so no command writes a file that no command can read. Errors name the
/// file.
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
    decode(bytes).map_err(|e| {
        Error::Data(format!(
            "{}: not written, no reader would take it: {e}",
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
    decode(&bytes).map_err(|e| Error::Data(format!("{}: {e}", path.display())))
}

/// The model `bytes` hold, checked as every reader checks it (the format's
/// own checks, then [`plausible`]); the error says what is wrong.
fn decode(bytes: &[u8]) -> std::result::Result<Coefficients<f64>, String> {
    let model = file::decode::<f64>(bytes).map_err(|e| e.to_string())?;
    plausible(&model)?;
    Ok(model)
}

/// The largest coefficient magnitude a file may hold. The format takes any
/// finite number, but a C_F, C_T or D coefficient of 1e100 is no air's
/// (the paper's are of order 1), and near `f64::MAX` the wrench of eqs.
/// (5-8) overflows: every command would print infinities and NaN.
pub const MAX_COEFFICIENT: f64 = 1e100;

/// An error naming the first coefficient (`alpha[i][k]`, `beta[i][k]` or
/// `D[r][c]`) whose magnitude exceeds [`MAX_COEFFICIENT`].
fn plausible(model: &Coefficients<f64>) -> std::result::Result<(), String> {
    let too_big = |v: f64| v.abs() > MAX_COEFFICIENT;
    let say = |what: String, v: f64| {
        format!("{what} = {v:e} is beyond any air's coefficient (the limit is {MAX_COEFFICIENT:e})")
    };
    for i in 0..3 {
        for k in 0..model.coeff_count() {
            if let Some(v) = model.alpha(i, k).filter(|v| too_big(*v)) {
                return Err(say(format!("alpha[{i}][{k}]"), v));
            }
        }
        for k in 0..model.torque_coeff_count() {
            if let Some(v) = model.beta(i, k).filter(|v| too_big(*v)) {
                return Err(say(format!("beta[{i}][{k}]"), v));
            }
        }
    }
    let d = model.damping();
    for (r, c) in (0..3).flat_map(|r| (0..3).map(move |c| (r, c))) {
        if too_big(d[(r, c)]) {
            return Err(say(format!("D[{r}][{c}]"), d[(r, c)]));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of finite but huge coefficients decodes, and would evaluate to
    /// infinities: the reader refuses it and names the coefficient, and the
    /// writer does not write one (the file there is kept).
    #[test]
    fn huge_coefficients_are_refused_by_name() {
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("big.omni");
        let mut model = Coefficients::<f64>::zeros(2, nalgebra::Vector3::z(), 0.5).expect("model");
        write(&path, &model).expect("write");
        assert!(read(&path).is_ok());
        let kept = std::fs::read(&path).expect("bytes");
        model.set_beta(1, 3, -1e300).expect("beta");
        let err = write(&path, &model).expect_err("not written").to_string();
        assert!(
            err.contains("beta[1][3]") && err.contains("big.omni"),
            "{err}"
        );
        assert_eq!(std::fs::read(&path).expect("bytes"), kept);
        // The same file made by another writer is refused when read.
        let mut buf = vec![0u8; file::MAX_FILE_SIZE];
        let n = file::encode(&model, &mut buf).expect("encode");
        std::fs::write(&path, buf.get(..n).expect("bytes")).expect("raw write");
        let err = read(&path).expect_err("huge").to_string();
        assert!(
            err.contains("beta[1][3]") && err.contains("big.omni"),
            "{err}"
        );
        model.set_beta(1, 3, 1e99).expect("beta");
        write(&path, &model).expect("write");
        assert!(
            read(&path).is_ok(),
            "a large but bounded coefficient is read"
        );
    }
}
