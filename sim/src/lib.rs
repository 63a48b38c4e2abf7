//! # omniad-sim
//!
//! Many independent rigid bodies under one coefficient set (paper Fig. 14:
//! falling plates), stepped with the core's batched RK4
//! ([`omniad_core::batch`], eight bodies per lane group) on all cores.
//!
//! * [`bodies`]: [`Bodies`], the states in lane groups, owned buffers (no
//!   allocation in a step), results independent of the thread count.

pub mod bodies;

pub use bodies::Bodies;
