//! OmniAD terminal UI (issue 5): coefficient spheres, kite design with
//! live equilibrium and stability, a live simulation of many falling
//! bodies, and telemetry replay. ratatui + crossterm.
//!
//! Structure: [`app::App`] holds all state and reacts to [`event::Event`]s
//! (pure, tested without a terminal); `&App` is a ratatui `Widget`
//! ([`ui`]) that draws the tab bar, the current view and the status line;
//! [`term`] owns the terminal and the event loop.

pub mod app;
pub mod event;
pub mod frames;
pub mod help;
pub mod kite;
pub mod models;
pub mod sim;
pub mod sphere;
pub mod telemetry;
pub mod term;
pub mod theme;
pub mod ui;

pub use app::App;

/// How to start the TUI.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// `.omni` files: the first is shown, the others compared against it.
    pub files: Vec<String>,
    /// Capture the mouse (drag rotates the sphere).
    pub mouse: bool,
    /// Telemetry CSV to replay (a Kitepower-style log or the firmware
    /// simulator's `--csv` output) instead of the bundled log.
    pub telemetry: Option<String>,
    /// Kite file the kite view opens (if it exists; else the bundled box
    /// kite) and saves to (default `kite.toml`); a file that does not
    /// load is shown as the error and never saved over.
    pub kite: Option<String>,
    /// `--bench-frames N`: time N frames of the simulation view headless
    /// ([`frames`]) and print JSON instead of opening the terminal.
    pub bench: Option<frames::FrameBench>,
}

/// Usage text of the `omniad-tui` binary.
pub const USAGE: &str =
    "usage: omniad-tui [--no-mouse] [--kite FILE.toml] [--telemetry LOG.csv] [FILE.omni [COMPARE.omni ...]]\n       omniad-tui --bench-frames N [--bodies B] [--size WxH]";

/// Parses `omniad-tui` arguments.
pub fn parse_args(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        mouse: true,
        ..Options::default()
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--no-mouse" => o.mouse = false,
            "--kite" => o.kite = Some(it.next().ok_or("--kite needs a file")?.clone()),
            "--telemetry" => {
                o.telemetry = Some(it.next().ok_or("--telemetry needs a file")?.clone())
            }
            "--bench-frames" => bench(&mut o).frames = number(it.next(), a)?,
            "--bodies" => bench(&mut o).bodies = number(it.next(), a)?,
            "--size" => bench(&mut o).size = size(it.next())?,
            "-h" | "--help" => return Err(USAGE.into()),
            s if s.starts_with('-') => return Err(format!("unknown option {s}\n{USAGE}")),
            s => o.files.push(s.to_string()),
        }
    }
    Ok(o)
}

/// The frame measurement's settings, started from the defaults.
fn bench(o: &mut Options) -> &mut frames::FrameBench {
    o.bench.get_or_insert_with(frames::FrameBench::default)
}

/// The number after `flag`.
fn number(value: Option<&String>, flag: &str) -> Result<usize, String> {
    value
        .and_then(|v| v.parse().ok())
        .ok_or(format!("{flag} needs a whole number\n{USAGE}"))
}

/// `WxH` in cells.
fn size(value: Option<&String>) -> Result<(u16, u16), String> {
    value
        .and_then(|v| v.split_once('x'))
        .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
        .ok_or(format!("--size needs WxH, e.g. 160x48\n{USAGE}"))
}

/// Loads the models and runs the TUI until the user quits.
pub fn run(options: &Options) -> Result<(), String> {
    if let Some(bench) = options.bench {
        println!("{}", frames::measure(bench)?.json());
        return Ok(());
    }
    let models = options
        .files
        .iter()
        .map(|f| models::load(f))
        .collect::<Result<Vec<_>, _>>()?;
    let mut app = App::new(models, theme::Theme::from_env());
    app.kite = kite::files::kite_view(options.kite.as_deref());
    if let Some(path) = &options.telemetry {
        app.telemetry = telemetry::TelemetryView::load(path)?;
    }
    term::run(app, options.mouse).map_err(|e| format!("terminal: {e}"))
}

/// [`parse_args`] then [`run`].
pub fn run_with_args(args: &[String]) -> Result<(), String> {
    run(&parse_args(args)?)
}
