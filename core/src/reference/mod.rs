//! Reference models: independent physical models of the air forces on
//! simple shapes, used to make example coefficients by projection
//! ([`crate::projection`]) and to generate synthetic recordings. They are
//! not the OmniAD model and are not fitted to data; comparison models
//! (e.g. Kirchhoff added mass, drag and traction) belong beside them.

pub mod panel;
