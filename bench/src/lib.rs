//! # omniad-bench
//!
//! The fixed suite of `omniad bench` (issue 19): each figure measured in
//! one run, so that ratios between them (batch / single, ours / MuJoCo)
//! are meaningful on a shared machine where absolute times are not.
//!
//! * [`physics`]: one evaluation, the batch per body, RK4 body-steps per
//!   second on one thread and on all cores;
//! * [`comparison`]: one RK4 step under each model of the core's model
//!   selector (vacuum, the paper's Fig. 12 comparison models, OmniAD);
//! * [`fit`]: `omniad fit` of a 13-take synthetic set generated at bench
//!   time (fixed seed) into a temporary folder;
//! * the TUI's simulation view, frame by frame, headless
//!   ([`omniad_tui::frames`]): physics and drawing of 12,800 bodies;
//! * [`peer`]: MuJoCo's ellipsoid fluid model on 1,000 plates, by
//!   `scripts/mujoco_peer.py`, when Python has `mujoco`.
//!
//! Nothing here asserts a time: the suite reports.

pub mod comparison;
pub mod fit;
pub mod model;
pub mod peer;
pub mod physics;
mod timer;

/// The paper's figures (§8): one evaluation in under 0.004 ms on a
/// 2.8 GHz i7; up to 1,000 bodies at about 30 fps including rendering;
/// about two minutes to estimate the parameters of one object.
pub mod paper {
    /// One force and torque evaluation, ns.
    pub const EVAL_NS: f64 = 4000.0;
    /// Bodies simulated at about 30 fps.
    pub const BODIES_REALTIME: f64 = 1000.0;
    /// Parameter estimation of one object, s.
    pub const FIT_SECONDS: f64 = 120.0;
}

/// Every figure of one run.
#[derive(Clone, Debug)]
pub struct Report {
    /// The physics figures.
    pub physics: physics::Figures,
    /// One RK4 step under each model of the core's selector.
    pub models: Vec<comparison::ModelStep>,
    /// `omniad fit` wall time, s (or why it was not measured).
    pub fit_seconds: Result<f64, String>,
    /// MuJoCo's figure measured in this run (or why not).
    pub peer: Result<peer::Peer, String>,
    /// The TUI's simulation view, per frame (or why not measured).
    pub tui: Result<omniad_tui::frames::FrameTiming, String>,
}

/// Runs the suite; `quick` shortens every measurement (and the fit to one
/// iteration is *not* done: the fit is always the 3-iteration one).
pub fn run(quick: bool) -> Report {
    let physics = physics::measure(quick);
    let models = comparison::measure(quick);
    let fit_seconds = fit::measure();
    let peer = peer::measure(quick);
    let mut frames = omniad_tui::frames::FrameBench::default();
    if quick {
        frames.frames = 15;
    }
    let tui = omniad_tui::frames::measure(frames);
    Report {
        physics,
        models,
        fit_seconds,
        peer,
        tui,
    }
}
