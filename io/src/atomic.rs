//! Atomic replacement of an output file.
//!
//! Why a rename: on POSIX file systems `rename(2)` within one folder
//! replaces the target in one step, so a reader sees either the old file or
//! the complete new one. The temporary file lives in the target's folder
//! (a rename cannot cross file systems) and is removed when anything fails.
//!
//! What a rename must not replace ([`destination`]): a symbolic link is
//! followed (its target is written, created when missing, the link kept,
//! as `cp` does); a file that is not a regular one (a device, a FIFO) and
//! anything under `/dev` or `/proc` is written through, appended to, not
//! renamed over: renaming over `/dev/full` turned the device into a regular
//! file, and `-o /dev/stdout` must reach the pipe or the file the shell
//! redirected it to, as a shell's `>>` would. And a command's output must
//! never be one of its own inputs ([`refuse_input`]).

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
    let path = match destination(path)? {
        Destination::Through(p) => return write_through(&p, fill),
        Destination::Replace(p) => p,
    };
    let path = path.as_path();
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

/// Where an output named `path` is written.
#[derive(Debug, PartialEq, Eq)]
enum Destination {
    /// A regular file (or none yet): replaced by a rename.
    Replace(PathBuf),
    /// A device, a FIFO, or a process's file: written through.
    Through(PathBuf),
}

/// Most symbolic links followed from one output path (Linux's own limit).
const MAX_LINKS: usize = 40;

/// [`Destination`] of `path` (see the module comment): links followed one
/// by one, so a dangling link gives the file it names.
fn destination(path: &Path) -> io::Result<Destination> {
    if path.starts_with("/dev") || path.starts_with("/proc") {
        return Ok(Destination::Through(path.to_path_buf()));
    }
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if target.is_relative() => dir.join(target),
                    _ => target,
                };
                if p.starts_with("/dev") || p.starts_with("/proc") {
                    return Ok(Destination::Through(path.to_path_buf()));
                }
            }
            Ok(m) if !m.is_file() => return Ok(Destination::Through(p)),
            _ => return Ok(Destination::Replace(p)),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("more than {MAX_LINKS} links to follow"),
    ))
}

/// Writes `fill` straight into an existing file that is not a regular one
/// (a device, a FIFO, a process's file), appending as a shell's `>>` does.
fn write_through<F>(path: &Path, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let file = OpenOptions::new().append(true).open(path)?;
    let mut w = BufWriter::new(file);
    fill(&mut w)?;
    w.flush()
}

/// An error when `output` is the same file as one of `inputs` (through any
/// path or link; files that do not exist yet are no input): a command that
/// wrote its result over what it read would destroy the user's data even
/// when it succeeds. The error names both.
pub fn refuse_input<P: AsRef<Path>>(output: &Path, inputs: &[P]) -> io::Result<()> {
    let Ok(out) = fs::canonicalize(output) else {
        return Ok(());
    };
    for input in inputs {
        if fs::canonicalize(input.as_ref()).is_ok_and(|i| i == out) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "{} is an input of this command ({}); choose another output",
                    output.display(),
                    input.as_ref().display()
                ),
            ));
        }
    }
    Ok(())
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
    fn a_link_is_followed_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("target.txt");
        let link = dir.path().join("link.txt");
        fs::write(&target, "old").unwrap();
        std::os::unix::fs::symlink(&target, &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            2,
            "no temporary left"
        );
    }

    #[test]
    fn a_dangling_link_creates_its_target_and_stays_a_link() {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir(dir.path().join("runs")).unwrap();
        let link = dir.path().join("latest.omni");
        std::os::unix::fs::symlink("runs/model.omni", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(
            fs::read_to_string(dir.path().join("runs/model.omni")).unwrap(),
            "new"
        );
    }

    #[test]
    fn a_link_loop_is_an_error_not_a_hang() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::os::unix::fs::symlink(&b, &a).unwrap();
        std::os::unix::fs::symlink(&a, &b).unwrap();
        let err = write_atomic(&a, b"x").unwrap_err();
        assert!(err.to_string().contains("links"), "{err}");
        assert!(fs::symlink_metadata(&a).unwrap().file_type().is_symlink());
    }

    /// The standard streams are process files: written through (to the
    /// pipe, or appended to the file the shell redirected them to), never
    /// resolved and renamed over.
    #[test]
    fn the_standard_streams_are_written_through() {
        for p in [
            "/dev/stdout",
            "/dev/stderr",
            "/dev/fd/1",
            "/proc/self/fd/1",
            "/dev/null",
        ] {
            assert_eq!(
                destination(Path::new(p)).unwrap(),
                Destination::Through(PathBuf::from(p)),
                "{p}"
            );
        }
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("out");
        std::os::unix::fs::symlink("/dev/stdout", &link).unwrap();
        assert_eq!(
            destination(&link).unwrap(),
            Destination::Through(link.clone())
        );
    }

    /// A FIFO (as a device would) gets the bytes written through and stays a
    /// FIFO; a rename would have put a regular file in its place.
    #[test]
    fn a_fifo_is_written_through_not_replaced() {
        use std::io::Read;
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("no mkfifo here: skipped");
            return;
        }
        // The reader reports through a channel, so a regression (the FIFO
        // renamed over, its reader left waiting) fails instead of hanging.
        let (tx, rx) = std::sync::mpsc::channel();
        {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                let mut s = String::new();
                let read = File::open(&fifo).and_then(|mut f| f.read_to_string(&mut s));
                let _ = tx.send(read.map(|_| s));
            });
        }
        write_atomic(&fifo, b"through the pipe").unwrap();
        assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo());
        let got = rx.recv_timeout(std::time::Duration::from_secs(10));
        assert_eq!(got.unwrap().unwrap(), "through the pipe");
    }

    #[test]
    fn an_input_is_refused_as_output_through_any_path() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        fs::write(&input, "data").unwrap();
        let link = dir.path().join("alias.csv");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        let dotted = dir.path().join(".").join("in.csv");
        for out in [&input, &link, &dotted] {
            let err = refuse_input(out, &[&input]).unwrap_err();
            assert!(err.to_string().contains("in.csv"), "{err}");
        }
        refuse_input(&dir.path().join("out.csv"), &[&input]).unwrap();
        fs::write(dir.path().join("other.csv"), "x").unwrap();
        refuse_input(&dir.path().join("other.csv"), &[&input]).unwrap();
    }

    #[test]
    fn a_bare_file_name_writes_in_the_current_folder() {
        // create_temporary must place the temporary beside a relative name.
        let (tmp, _f) = create_temporary(Path::new("relative-name.txt")).unwrap();
        assert_eq!(tmp.parent(), Some(Path::new(".")));
        fs::remove_file(tmp).unwrap();
    }
}
