//! # omniad-core
//!
//! The OmniAD model of Martin, Umetani & Bickel (SIGGRAPH 2015) for embedded
//! and host use: `#![no_std]`, no allocator, no panics.
//!
//! * [`sh`]: real orthonormal spherical harmonics `Y_lm` (eqs. 7-8).
//! * [`lanes`]: eqs. (7)-(8) evaluated with SH orders in SIMD lanes, and the
//!   coefficient layout that goes with it.
//! * [`basis`]: the vector basis `E1, E2, E3` of §4.2.
//! * [`coefficients`]: the coefficient model (alpha, beta, D, provenance, extensions).
//! * [`aero`]: aerodynamic force and torque, eqs. (5)-(6).
//! * [`rigid_body`], [`integrate`]: eqs. (1)-(2) and a pure fixed-step RK4 step.
//! * [`spin_coupling`]: a model extension, the force bilinear in Ω and V
//!   (Magnus, added-mass coupling).
//! * [`gravity_coupling`]: a model extension, the force linear in gravity
//!   seen from the body (buoyancy, added mass).
//! * [`file`]: the `*.omni` coefficient file format.
//! * [`projection`]: eqs. (11), (13), a direction function onto
//!   coefficients, by [`quadrature`] on the sphere.
//! * [`reference`]: independent reference models (the quasi-steady panel
//!   model) that example coefficients are projected from, and the paper's
//!   comparison models (Fig. 12).
//! * [`model`]: the model selector (vacuum, comparison models, OmniAD).
//!
//! Every quantity is SI (m, kg, s, rad) unless a doc comment says otherwise.
#![no_std]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::unimplemented,
    clippy::todo,
    clippy::unreachable
)]
// `!(x > 0)` is deliberate throughout: it is true for NaN, which must be
// rejected along with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(feature = "std")]
extern crate std;

pub mod aero;
pub mod basis;
pub mod batch;
pub mod coefficients;
pub mod crc32;
pub mod effect;
pub mod error;
pub mod extension;
pub mod file;
pub mod gravity_coupling;
pub mod integrate;
pub mod kite;
pub mod lanes;
pub mod math;
pub mod metadata;
pub mod model;
mod payload;
pub mod projection;
pub mod quadrature;
pub mod reference;
pub mod rigid_body;
pub mod sh;
pub mod spin_coupling;
pub mod wrench;

pub use aero::Wrench;
pub use coefficients::{Coefficients, ModelError};
pub use lanes::LaneScalar;
pub use math::Real;
pub use rigid_body::{Environment, RigidBody, State};
