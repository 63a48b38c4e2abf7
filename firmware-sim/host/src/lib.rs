//! # omniad-fw-host
//!
//! The host side of the firmware simulator (issue 6): everything
//! `omniad firmware replay` and the end-to-end tests need to run the
//! Cortex-M4F firmware in QEMU and hold it to the host build of the same
//! code, bit for bit.
//!
//! * `build`: building the firmware workspace for its target.
//! * `elf`: sizes (flash, static RAM), sections and symbols of the ELF;
//!   the panic-symbol check.
//! * `flash`: the coefficient file in the ELF's `.kite` section, read
//!   and patched (`--kite`).
//! * `log`: flight-log CSV -> sensor frames, errors naming file, line and
//!   column.
//! * `wire`: frames on the wire, with injected garbage.
//! * `qemu`: running the replay and bench firmware.
//! * `host_replay`: the same bytes through the same pipeline on the host.
//! * `compare`: host against firmware, record by record.
//! * [`report`]: the typed report (`--json` serializes it).
//! * `replay`: one replay, end to end.
//! * `telemetry_csv`: `--csv`, written atomically.

mod build;
mod compare;
mod elf;
mod flash;
mod host_replay;
mod log;
mod qemu;
mod replay;
pub mod report;
mod telemetry_csv;
mod wire;

pub use build::{build_firmware, firmware_dir};
pub use compare::Agreement;
pub use replay::{replay, Replay, ReplayOptions};
pub use report::Report;
pub use telemetry_csv::write_telemetry_csv;
