//! # omniad-fw-pipeline
//!
//! What the omniad firmware (issue 6) does with one sensor frame, as a
//! `no_std`, allocation-free library shared by the firmware (Cortex-M4F,
//! `thumbv7em-none-eabihf`) and the host replay (`omniad firmware replay`),
//! so that the host can compare every telemetry output with the firmware's
//! bit for bit.
//!
//! * [`frame`]: the wire format. Sensor frames in, telemetry frames out:
//!   `COBS(postcard(payload) ++ CRC-32 LE) 0x00`.
//! * [`process`]: the per-frame computation (aerodynamic wrench, predicted
//!   tether force and residual, stability eigenvalues, RK4 look-ahead).
//! * [`kite`]: the default kite model embedded in the firmware.
//! * [`exit`]: the firmware's exit codes, named once for the firmware and
//!   the host harness.
//! * [`eig`]: eigenvalues of a symmetric 3x3 matrix (cyclic Jacobi, sqrt
//!   only, no trigonometry).
//!
//! Everything here is deterministic IEEE-754 `f32` arithmetic with no
//! target-dependent code paths: `+ - * /` and correctly rounded square
//! roots only (no fused multiply-add, no libm transcendental on the frame
//! path), which is why the host and the firmware agree to the bit.
#![cfg_attr(not(test), no_std)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::unreachable
)]

pub mod cobs;
pub mod eig;
pub mod exit;
pub mod frame;
pub mod kite;
pub mod process;

pub use exit::ExitCode;
pub use frame::{Deframer, Output, Reject, SensorFrame, Summary, Telemetry};
pub use process::Processor;
