//! One event type for the run loop: terminal input from a reader thread,
//! and ticks (produced by the loop's receive timeout while animating).

use ratatui::crossterm::event::{self as ct, KeyEvent, KeyEventKind, MouseEvent};
use std::sync::mpsc::{Receiver, Sender};
use std::thread;

/// Everything the app reacts to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// A key press.
    Key(KeyEvent),
    /// A mouse event.
    Mouse(MouseEvent),
    /// The terminal was resized to (columns, rows).
    Resize(u16, u16),
    /// Time to advance an animation.
    Tick,
}

/// Starts the input thread; events arrive on the returned channel. The
/// thread blocks in `crossterm::event::read`, so nothing spins when idle.
pub fn spawn_input() -> Receiver<Event> {
    let (tx, rx) = std::sync::mpsc::channel();
    thread::Builder::new()
        .name("omniad-tui-input".into())
        .spawn(move || input_loop(&tx))
        .ok();
    rx
}

fn input_loop(tx: &Sender<Event>) {
    while let Ok(ev) = ct::read() {
        let out = match ev {
            ct::Event::Key(k) if k.kind != KeyEventKind::Release => Event::Key(k),
            ct::Event::Mouse(m) => Event::Mouse(m),
            ct::Event::Resize(w, h) => Event::Resize(w, h),
            _ => continue,
        };
        if tx.send(out).is_err() {
            break;
        }
    }
}
