//! Input: recording sets (`recording.toml`), the camera model, marker and
//! pose tracks, importers (DLTdv, DeepLabCut) and the state CSV.

pub mod camera;
pub mod import;
pub mod object;
pub mod recording;
pub mod state_csv;
pub mod tracks;
pub(crate) mod validate;
