//! `omniad tui [FILE.omni ...]` (and `omniad` with no command): the
//! terminal UI of `omniad-tui`.

use anyhow::{anyhow, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `omniad tui`.
#[derive(Args, Debug, Default)]
pub struct TuiArgs {
    /// Coefficient files (.omni): the first is shown, the others can be
    /// compared with it (default: the bundled plate).
    pub files: Vec<PathBuf>,
    /// Kite file the kite view opens (if it exists; else the bundled box
    /// kite) and saves to; a file that does not load is shown as the
    /// error and never saved over.
    #[arg(long, default_value = "kite.toml")]
    pub kite: PathBuf,
    /// Telemetry CSV to replay in view 4 (a Kitepower-style log, or the
    /// output of `omniad firmware replay --csv`).
    #[arg(long)]
    pub telemetry: Option<PathBuf>,
    /// Do not capture the mouse (keeps the terminal's own selection).
    #[arg(long)]
    pub no_mouse: bool,
}

/// Opens the TUI on the bundled defaults (`omniad` with no command).
pub fn run_default() -> Result<()> {
    run(&TuiArgs {
        kite: "kite.toml".into(),
        ..TuiArgs::default()
    })
}

/// Opens the TUI.
pub fn run(args: &TuiArgs) -> Result<()> {
    let options = omniad_tui::Options {
        files: args
            .files
            .iter()
            .map(|f| f.to_string_lossy().into_owned())
            .collect(),
        mouse: !args.no_mouse,
        kite: Some(args.kite.to_string_lossy().into_owned()),
        telemetry: args
            .telemetry
            .as_ref()
            .map(|p| p.to_string_lossy().into_owned()),
        bench: None,
    };
    omniad_tui::run(&options).map_err(|e| anyhow!(e))
}
