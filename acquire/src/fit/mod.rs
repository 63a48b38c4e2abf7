//! Fitting (§6): the coefficient model from reconstructed frames.

pub mod coverage;
pub mod damping;
pub mod extensions;
pub mod lsq;
pub mod model;
pub mod paper;
pub mod residuals;
pub mod select;
