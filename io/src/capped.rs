//! Reading an input no longer than its format allows.
//!
//! Why: `std::fs::read` trusts the file's length, and a character device
//! (`/dev/zero`, `/dev/urandom`) or a mistaken multi-gigabyte path would be
//! read whole before any header check. Every reader of a user file names
//! its format's maximum and gets a clear error past it.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// Reads `path` whole if it holds at most `max` bytes; more is an
/// `InvalidData` error that says the limit. Reads at most `max + 1` bytes.
pub fn read_capped(path: &Path, max: usize) -> io::Result<Vec<u8>> {
    let file = File::open(path)?;
    if file.metadata()?.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "is a folder, not a file",
        ));
    }
    let mut bytes = Vec::new();
    let limit = u64::try_from(max).unwrap_or(u64::MAX).saturating_add(1);
    file.take(limit).read_to_end(&mut bytes)?;
    if bytes.len() > max {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("longer than the format's maximum of {max} bytes"),
        ));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_file_up_to_the_cap() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("f");
        std::fs::write(&p, [7u8; 10]).unwrap();
        assert_eq!(read_capped(&p, 10).unwrap().len(), 10);
        let err = read_capped(&p, 9).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidData);
        assert!(err.to_string().contains("9 bytes"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_stops_at_the_cap() {
        let err = read_capped(Path::new("/dev/zero"), 1 << 16).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidData);
    }

    #[test]
    fn a_folder_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        assert!(read_capped(dir.path(), 10).is_err());
    }
}
