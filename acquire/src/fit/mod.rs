//! Fitting (§6): the coefficient model from reconstructed frames.
//!
//! Force, torque and every model extension supply rows to per-take normal
//! equations (`normals`); one leave-one-take-out engine (`select`)
//! chooses the smoothing ([`smoothing`]) and the extensions
//! ([`extensions`], whose terms are registered in [`effects`]); frames are
//! weighted in `weights`. `lsq` is the default fit, `paper` the
//! paper's method; [`model`] assembles the core coefficients.

pub mod config;
pub(crate) mod context;
pub(crate) mod coverage;
pub(crate) mod damping;
pub mod effects;
pub mod extensions;
pub(crate) mod force;
pub(crate) mod joint;
pub(crate) mod lsq;
pub mod model;
pub mod normals;
pub(crate) mod paper;
pub(crate) mod residuals;
pub mod select;
pub mod smoothing;
pub(crate) mod thrust;
pub(crate) mod torque;
pub(crate) mod torque_prior;
pub(crate) mod torque_rows;
pub(crate) mod torque_window;
pub(crate) mod weights;
