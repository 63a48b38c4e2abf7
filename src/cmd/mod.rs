//! Command implementations, one module per command family.

pub mod coeffs;
pub mod common;
pub mod info;
pub mod simulate;
