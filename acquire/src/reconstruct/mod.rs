//! Reconstruction (§5): the filter state, the process and measurement
//! models, the iterated EKF and RTS smoother (with mirror handling), and
//! the air wrench of every frame by eqs. (9)-(10).

pub mod filter;
pub mod forces;
pub mod measurement;
pub mod process;
pub mod state;
