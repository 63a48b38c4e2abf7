//! Headless measurement of the simulation view's frame rate (issue 19):
//! the run loop's own work for each animated frame ([`crate::term`]:
//! `App::handle(Tick)`, which steps the bodies by the batch RK4 on all
//! cores, then `Terminal::draw` of the whole app) for N frames, drawn into
//! ratatui's `TestBackend` instead of a terminal. What it leaves out is the
//! terminal's own cost of showing the changed cells (the bytes crossterm
//! writes and the emulator paints), which depends on the emulator.
//!
//! `omniad-tui --bench-frames N [--bodies B] [--size WxH]` prints it as
//! JSON; `omniad bench --json` reports it as `tui`.

use crate::app::{App, ViewId};
use crate::event::Event;
use ratatui::backend::TestBackend;
use ratatui::Terminal;
use std::time::Instant;

/// What to measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameBench {
    /// Falling bodies.
    pub bodies: usize,
    /// Frames timed (after one untimed warm-up frame).
    pub frames: usize,
    /// Terminal size, cells.
    pub size: (u16, u16),
}

impl Default for FrameBench {
    /// 12,800 bodies (what the view's `+` key reaches from its default
    /// 400) for 60 frames in a 160 x 48 terminal.
    fn default() -> Self {
        Self {
            bodies: 12_800,
            frames: 60,
            size: (160, 48),
        }
    }
}

/// Timing of [`FrameBench`], milliseconds per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTiming {
    /// What was measured.
    pub bench: FrameBench,
    /// Physics (the tick), mean.
    pub physics_ms: f64,
    /// Rendering and diffing the frame, mean.
    pub draw_ms: f64,
    /// The whole frame, mean.
    pub frame_ms: f64,
    /// The slowest frame.
    pub worst_frame_ms: f64,
    /// Simulated time at the end, s (the frames did step the bodies).
    pub simulated_s: f64,
}

impl FrameTiming {
    /// Frames per second at the mean frame time (unthrottled: the TUI
    /// itself ticks at most 30 times a second).
    pub fn fps(&self) -> f64 {
        1e3 / self.frame_ms
    }

    /// As a JSON object (no serde in this crate).
    pub fn json(&self) -> String {
        format!(
            "{{\"bodies\": {}, \"frames\": {}, \"width\": {}, \"height\": {}, \"physics_ms\": {:.3}, \"draw_ms\": {:.3}, \"frame_ms\": {:.3}, \"worst_frame_ms\": {:.3}, \"fps\": {:.1}}}",
            self.bench.bodies,
            self.bench.frames,
            self.bench.size.0,
            self.bench.size.1,
            self.physics_ms,
            self.draw_ms,
            self.frame_ms,
            self.worst_frame_ms,
            self.fps()
        )
    }
}

/// Runs the simulation view of [`App::demo`] (the built-in plate) with
/// `bench.bodies` bodies for `bench.frames` frames as the run loop does.
pub fn measure(bench: FrameBench) -> Result<FrameTiming, String> {
    let mut app = App::demo();
    app.view = ViewId::Sim;
    app.sim.world.resize(bench.bodies);
    app.sim.running = true;
    let (w, h) = bench.size;
    let mut term = Terminal::new(TestBackend::new(w, h)).map_err(|e| e.to_string())?;
    let mut frame = |app: &mut App| -> Result<(f64, f64), String> {
        let t0 = Instant::now();
        app.handle(&Event::Tick);
        let t1 = Instant::now();
        term.draw(|f| f.render_widget(&*app, f.area()))
            .map_err(|e| e.to_string())?;
        Ok((
            (t1 - t0).as_secs_f64() * 1e3,
            t1.elapsed().as_secs_f64() * 1e3,
        ))
    };
    frame(&mut app)?;
    let (mut physics, mut draw, mut worst) = (0.0, 0.0, 0.0f64);
    for _ in 0..bench.frames {
        let (p, d) = frame(&mut app)?;
        physics += p;
        draw += d;
        worst = worst.max(p + d);
    }
    let n = bench.frames.max(1) as f64;
    Ok(FrameTiming {
        bench,
        physics_ms: physics / n,
        draw_ms: draw / n,
        frame_ms: (physics + draw) / n,
        worst_frame_ms: worst,
        simulated_s: app.sim.world.time,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The measurement runs the real frame: the bodies move and the view
    /// is drawn (no time is asserted).
    #[test]
    fn frames_step_the_bodies_and_draw_the_view() {
        let bench = FrameBench {
            bodies: 64,
            frames: 3,
            size: (80, 24),
        };
        let t = measure(bench).unwrap();
        assert_eq!(t.bench, bench);
        assert!(t.physics_ms > 0.0 && t.draw_ms > 0.0);
        assert!(t.frame_ms >= t.physics_ms && t.worst_frame_ms >= t.frame_ms * 0.999);
        assert!(t.json().contains("\"bodies\": 64"));
        // The warm-up frame and the timed ones each advanced the bodies.
        let per_frame = crate::sim::world::STEPS_PER_FRAME as f64 * crate::sim::world::DT;
        assert!(
            (t.simulated_s - 4.0 * per_frame).abs() < 1e-9,
            "{}",
            t.simulated_s
        );
    }
}
