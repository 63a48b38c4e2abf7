//! Reference models: independent physical models of the air forces on
//! simple shapes. [`panel`] makes example coefficients by projection
//! ([`crate::projection`]) and generates synthetic recordings; the
//! comparison models of the paper's Fig. 12 ([`kirchhoff`],
//! [`drag_traction`], [`simplified`]) are built from a [`shape::Shape`]
//! and move bodies directly ([`crate::rigid_body::Forces`]). None is the
//! OmniAD model and none is fitted to data.

pub mod drag_traction;
pub mod ellipsoid;
pub mod kirchhoff;
pub mod panel;
pub mod shape;
pub mod simplified;
pub mod taira;
