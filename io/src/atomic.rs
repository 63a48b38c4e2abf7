//! Atomic replacement of an output file.
//!
//! Why a rename: on POSIX file systems `rename(2)` within one folder
//! replaces the target in one step, so a reader sees either the old file or
//! the complete new one. The temporary file lives in the target's folder
//! (a rename cannot cross file systems) and is removed when anything fails.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `bytes` to `path` atomically (see the module comment).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |w| w.write_all(bytes))
}

/// Writes `path` atomically through `fill`, which streams into a buffered
/// writer; nothing replaces `path` unless `fill` and the flush succeed.
pub fn write_with<F>(path: &Path, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    if path.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "is a folder, not a file",
        ));
    }
    let (tmp, file) = create_temporary(path)?;
    let result = (|| {
        let mut w = BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Writes each `(file name, bytes)` into the folder `dir` (created if
/// needed), each file atomically; an error names the path that failed.
pub fn write_files_atomic<N, B>(
    dir: &Path,
    files: impl IntoIterator<Item = (N, B)>,
) -> io::Result<()>
where
    N: AsRef<Path>,
    B: AsRef<[u8]>,
{
    let named = |p: &Path, e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", p.display()));
    fs::create_dir_all(dir).map_err(|e| named(dir, e))?;
    for (name, bytes) in files {
        let path = dir.join(name);
        write_atomic(&path, bytes.as_ref()).map_err(|e| named(&path, e))?;
    }
    Ok(())
}

/// A new, exclusive temporary file beside `path`: `.NAME.PID.N.tmp`.
fn create_temporary(path: &Path) -> io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "has no file name"))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(
            ".{}.{}.{n}.tmp",
            name.to_string_lossy(),
            std::process::id()
        ));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_target_when_complete() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        fs::write(&p, "old").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temporary left"
        );
    }

    #[test]
    fn a_failing_writer_leaves_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        fs::write(&p, "precious").unwrap();
        let err = write_with(&p, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("disk full"))
        })
        .unwrap_err();
        assert_eq!(err.to_string(), "disk full");
        assert_eq!(fs::read_to_string(&p).unwrap(), "precious");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temporary left"
        );
    }

    #[test]
    fn a_missing_folder_is_an_error_and_creates_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/out.txt");
        assert!(write_atomic(&p, b"x").is_err());
        assert!(!dir.path().join("no").exists());
    }

    #[test]
    fn files_into_a_new_folder() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("plots");
        write_files_atomic(&sub, [("a.svg", "<svg/>"), ("b.svg", "<svg></svg>")]).unwrap();
        assert_eq!(
            fs::read_to_string(sub.join("b.svg")).unwrap(),
            "<svg></svg>"
        );
        let err = write_files_atomic(&sub.join("a.svg"), [("c", "x")]).unwrap_err();
        assert!(err.to_string().contains("a.svg"), "{err}");
    }

    #[test]
    fn a_folder_is_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        assert!(write_atomic(dir.path(), b"x").is_err());
        assert!(dir.path().is_dir());
    }

    #[test]
    fn a_bare_file_name_writes_in_the_current_folder() {
        // create_temporary must place the temporary beside a relative name.
        let (tmp, _f) = create_temporary(Path::new("relative-name.txt")).unwrap();
        assert_eq!(tmp.parent(), Some(Path::new(".")));
        fs::remove_file(tmp).unwrap();
    }
}
