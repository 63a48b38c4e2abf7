//! OmniAD acquisition (paper §5-6): recording sets -> coefficient files.
//!
//! Pipeline: [`recording`] + [`tracks`] (input; [`import`] for DLTdv and
//! DeepLabCut) -> [`filter`] (iterated EKF + RTS smoother with
//! [`process`] and [`measurement`], §5) -> [`forces`] (eqs. 9-10, stability
//! enforcement) -> [`fit_lsq`] / [`fit_paper`] (§6) -> [`pipeline`]
//! (iterative refinement, provenance with [`coverage`]). [`synth`] generates
//! recording sets from a known model.

pub mod camera;
pub mod coverage;
pub mod damping;
pub mod error;
pub mod filter;
pub mod fit_cv;
pub mod fit_extensions;
pub mod fit_lsq;
pub mod fit_paper;
pub mod forces;
pub mod import;
pub mod measurement;
pub mod model;
pub mod parallel;
pub mod pipeline;
pub mod process;
pub mod recording;
pub mod residuals;
pub mod rng;
pub mod state;
pub mod synth;
pub mod synth_write;
pub mod tracks;
pub mod truth;

pub use error::{Error, Result};
