//! Terminal set-up and the run loop: raw mode and the alternate screen,
//! restored on exit, on Ctrl-C (a key in raw mode), on panic and on the
//! signals that end a process from outside (TERM, INT, HUP, QUIT).

use crate::app::App;
use crate::event::{spawn_input, Event};
use ratatui::crossterm::event::{DisableMouseCapture, EnableMouseCapture};
use ratatui::crossterm::execute;
use ratatui::crossterm::terminal::{self, EnterAlternateScreen, LeaveAlternateScreen};
use ratatui::prelude::CrosstermBackend;
use ratatui::Terminal;
use std::io::{self, Stdout};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Frame interval while animating (30 frames per second).
pub const FRAME: Duration = Duration::from_millis(33);

type Term = Terminal<CrosstermBackend<Stdout>>;

/// Puts the terminal back: raw mode off, main screen, mouse off, cursor
/// shown. Safe to call more than once.
pub fn restore() {
    let _ = terminal::disable_raw_mode();
    let _ = execute!(
        io::stdout(),
        DisableMouseCapture,
        LeaveAlternateScreen,
        ratatui::crossterm::cursor::Show
    );
}

fn install_panic_hook() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        restore();
        previous(info);
    }));
}

fn setup(mouse: bool) -> io::Result<Term> {
    terminal::enable_raw_mode()?;
    let mut out = io::stdout();
    execute!(out, EnterAlternateScreen)?;
    if mouse {
        execute!(out, EnableMouseCapture)?;
    }
    Terminal::new(CrosstermBackend::new(out))
}

/// Restores the terminal and exits `128 + signal` (the shell's convention)
/// when TERM, INT, HUP or QUIT arrives. Why a thread: restoring writes to
/// the terminal, which a signal handler must not do; signal-hook's iterator
/// turns the signal into an ordinary wake-up of this thread.
fn install_signal_restore() -> io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGTERM, SIGINT, SIGHUP, SIGQUIT])?;
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            restore();
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// Runs `app` in the terminal until the user quits.
pub fn run(mut app: App, mouse: bool) -> io::Result<()> {
    install_panic_hook();
    install_signal_restore()?;
    let result = setup(mouse).and_then(|mut t| event_loop(&mut t, &mut app));
    restore();
    result
}

/// Waits for the next event: blocks when idle, ticks at [`FRAME`] while
/// the app animates. `None` when the input thread is gone.
fn next_event(rx: &Receiver<Event>, animating: bool, last_tick: &mut Instant) -> Option<Event> {
    if !animating {
        return rx.recv().ok();
    }
    let wait = FRAME.saturating_sub(last_tick.elapsed());
    match rx.recv_timeout(wait) {
        Ok(e) => Some(e),
        Err(RecvTimeoutError::Timeout) => {
            *last_tick = Instant::now();
            Some(Event::Tick)
        }
        Err(RecvTimeoutError::Disconnected) => None,
    }
}

fn event_loop(term: &mut Term, app: &mut App) -> io::Result<()> {
    let rx = spawn_input();
    let (mut dirty, mut last_tick, mut last_draw) = (true, Instant::now(), Instant::now());
    loop {
        if dirty {
            let t0 = Instant::now();
            term.draw(|f| f.render_widget(&*app, f.area()))?;
            app.stats.draw_ms = t0.elapsed().as_secs_f64() * 1e3;
            let dt = last_draw.elapsed().as_secs_f64();
            if app.animating() && dt > 0.0 {
                let fps = 1.0 / dt;
                app.stats.fps = if app.stats.fps > 0.0 {
                    0.9 * app.stats.fps + 0.1 * fps
                } else {
                    fps
                };
            }
            last_draw = Instant::now();
            dirty = false;
        }
        if app.quit {
            return Ok(());
        }
        // For the end-to-end test of the panic hook only.
        if std::env::var_os("OMNIAD_TUI_TEST_PANIC").is_some() {
            panic!("OMNIAD_TUI_TEST_PANIC is set: testing that the terminal is restored");
        }
        let Some(ev) = next_event(&rx, app.animating(), &mut last_tick) else {
            return Ok(());
        };
        dirty |= app.handle(&ev);
        // Coalesce queued input (key repeat over a slow link): one redraw.
        while let Ok(ev) = rx.try_recv() {
            dirty |= app.handle(&ev);
        }
    }
}
