//! Reconstruction (§5): the filter state, the process and measurement
//! models, the iterated EKF and RTS smoother (with mirror handling), the
//! process noise and its schedule, a whole set's reconstruction, and the
//! air wrench of every frame by eqs. (9)-(10).

pub mod filter;
pub mod first;
pub mod forces;
pub(crate) mod measurement;
pub(crate) mod misfit;
pub mod noise;
pub(crate) mod process;
pub mod run;
pub mod schedule;
pub(crate) mod state;
