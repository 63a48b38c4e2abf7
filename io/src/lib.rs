//! File I/O shared by every crate that writes or reads user files.
//!
//! Two promises, one owner each:
//! - [`atomic`]: an output file is written to a temporary file in the same
//!   folder and renamed over the target only once it is complete, so a
//!   command that fails (full disk, bad input half-way, a signal) never
//!   damages what the user had.
//! - [`capped`]: an input is read up to a limit its format announces, so
//!   `/dev/zero` or a huge file is an error, not gigabytes of memory.
//! - [`text`]: CSV text as exports write it (byte-order mark, any line end).

pub mod atomic;
pub mod capped;
pub mod text;

pub use atomic::{refuse_input, write_atomic, write_files_atomic, write_with};
pub use capped::read_capped;
pub use text::{csv_lines, read_text};
