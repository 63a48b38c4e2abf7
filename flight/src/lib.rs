//! OmniAD on measured kite flight telemetry (`omniad flight fit`): the
//! closed loop of fit, held-out residual, named effect, refit, on real data
//! nobody here made (Kitepower V3, 8 October 2019, CC-BY 4.0).
//!
//! Stages, one module each: [`log`] (the CSV as it is) -> [`sample`] (force
//! balance and air velocity, in [`frames`], with [`kite`] properties) ->
//! [`terms`] (the base OmniAD model and the candidate effects as regressor
//! columns) -> [`fit`] (per-cycle normal equations, leave-one-cycle-out)
//! -> [`select`] (greedy forward selection on the training cycles) ->
//! [`report`] (held-out numbers on the test cycles, plots, the model file).

pub mod fit;
pub mod frames;
pub mod kite;
pub mod log;
pub mod plots;
pub mod report;
pub mod sample;
pub mod select;
pub mod terms;

pub use report::{run, FlightFitConfig, Report};
