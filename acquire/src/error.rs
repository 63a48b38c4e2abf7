//! Errors of the acquisition pipeline. Every input error names the file and,
//! where there is one, the line (1-based) or the field.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in a file an input error is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// The whole file.
    File,
    /// A 1-based line, optionally with the column name.
    Line(usize, Option<String>),
    /// A (dotted) field of a TOML document, e.g. `camera.fx`.
    Field(String),
}

/// An acquisition error.
#[derive(Debug)]
pub enum Error {
    /// A file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file's content is not as the recording format says.
    Format {
        /// The file.
        path: PathBuf,
        /// Where in it.
        location: Location,
        /// What is wrong.
        message: String,
    },
    /// The data cannot support the requested computation.
    Data(String),
}

impl Error {
    /// A format error at a line (1-based) of `path`, optionally naming a column.
    pub fn at_line(
        path: &Path,
        line: usize,
        column: Option<&str>,
        message: impl Into<String>,
    ) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            location: Location::Line(line, column.map(str::to_owned)),
            message: message.into(),
        }
    }

    /// A format error at a TOML field of `path`.
    pub fn at_field(path: &Path, field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            location: Location::Field(field.into()),
            message: message.into(),
        }
    }

    /// A format error about the whole of `path`.
    pub fn in_file(path: &Path, message: impl Into<String>) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            location: Location::File,
            message: message.into(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Format {
                path,
                location,
                message,
            } => {
                write!(f, "{}", path.display())?;
                match location {
                    Location::File => {}
                    Location::Line(line, None) => write!(f, ":{line}")?,
                    Location::Line(line, Some(col)) => write!(f, ":{line}: column `{col}`")?,
                    Location::Field(field) => write!(f, ": field `{field}`")?,
                }
                write!(f, ": {message}")
            }
            Self::Data(message) => write!(f, "{message}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Result with [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
