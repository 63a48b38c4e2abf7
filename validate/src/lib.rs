//! # omniad-validate
//!
//! Validation a scientist can check, in the manner of the OmniAD paper's
//! §8: a model's lift and drag section against measured flat-plate curves
//! ([`section`], Fig. 13), the same release under the comparison models
//! ([`release`], Fig. 12), fits at several SH degrees N on held-out takes
//! ([`resolution`], Fig. 8), and the one-command report of all that
//! applies to a recording set ([`report`], `omniad report`), with the
//! fit's C_F and C_T errors on a synthetic set ([`accuracy`]).
//!
//! Its own crate because it consumes everything — the acquisition
//! pipeline (fits), the core's models and `omniad-plot` — and nothing
//! consumes it but the CLI: inside `omniad-acquire` it would make the
//! acquisition depend on plotting.

pub mod accuracy;
pub mod release;
pub mod report;
pub mod resolution;
pub mod section;
