//! # omniad-kite: KiteShop (paper §7)
//!
//! * [`spec`]: the TOML kite file; [`geometry`], [`joints`], [`mass`]:
//!   rods, coverings, sockets, mass properties.
//! * [`library`]: primitive examples and their inverse-distance blending.
//! * [`assemble`]: a file turned into primitives for the core statics
//!   (`omniad_core::kite`).
//! * [`check`], [`trimming`]: the static report and trim search.
//! * [`wind`], [`flight`]: gusty wind and the tethered flight simulation
//!   ([`flight::Flight`] steps it; `kite fly` and the TUI both run it).
//! * [`export`]: OpenSCAD sockets, cut list, SVG three-view drawing;
//!   [`sockets`]: socket dimensions, cut-length insets, clashing bores.
//! * [`optimise`]: the trim search for the largest stability margin
//!   (`kite optimise`), keeping the frame in one piece ([`connect`]).
//! * [`launch`]: flights start at the equilibrium the kite settles to.

// `!(x > 0.0)` deliberately rejects NaN as well as non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod assemble;
mod attachment;
pub mod check;
pub mod connect;
mod design_params;
pub mod equilibrium;
mod equivalent;
pub mod export;
pub mod flight;
mod flight_step;
pub mod generate;
pub mod geometry;
pub mod gusts;
pub mod joints;
pub mod launch;
pub mod library;
pub mod limit_cycle;
pub mod linearise;
pub mod mass;
pub mod modes;
mod multi_start;
mod objective;
pub mod optimise;
pub mod rod_end;
mod search_moves;
mod settle;
pub mod sockets;
pub mod spec;
mod spectral;
pub mod strong_gust;
mod tether;
mod toml_writer;
pub mod trial_flights;
pub mod trimming;
mod union_check;
pub mod verdict;
pub mod wind;

pub use assemble::Design;
pub use library::Library;
pub use spec::KiteSpec;
