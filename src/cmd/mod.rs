//! Command implementations, one module per command family.

pub mod bench;
pub mod coeffs;
pub mod common;
pub mod firmware;
pub mod fit;
pub mod flight;
pub mod import;
pub mod info;
pub mod kite;
pub mod lab;
pub mod panel;
pub mod reconstruct;
pub mod report;
pub mod residual;
pub mod simulate;
pub mod synth;
pub mod tui;
