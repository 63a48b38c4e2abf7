//! OmniAD acquisition (paper §5-6): recording sets -> coefficient files.
//!
//! The paper's stages, each depending only on those before it:
//! [`input`] (recording sets, camera, tracks, importers, state CSVs) ->
//! [`reconstruct`] (§5: iterated EKF + RTS smoother, process noise, eqs.
//! 9-10) -> [`fit`] (§6: per-take normal equations, leave-one-take-out
//! selection, the least-squares and the paper's fits) -> [`pipeline`]
//! (the iterative refinement and its provenance). [`synth`] generates
//! recording sets from a known model and compares with the truth; [`lab`]
//! holds the research measurements behind BENCHMARKS.md (`omniad lab`).

pub mod error;
pub mod fit;
pub mod input;
pub mod lab;
pub mod omni_file;
pub(crate) mod parallel;
pub mod pipeline;
pub mod reconstruct;
pub mod residual;
pub(crate) mod rng;
pub mod synth;

pub use error::{Error, Result};
