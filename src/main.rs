//! `omniad`: the command-line front end. Thin: parses arguments and
//! dispatches to `omniad-core`, `omniad-acquire`, `omniad-tui`.
//!
//! One module per command family under `src/cmd/`.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Data-driven omni-directional aerodynamics for light rigid objects.
#[derive(Parser, Debug)]
#[command(name = "omniad", version, about, long_about = None)]
struct Cli {
    /// Without a command the terminal UI opens on the bundled defaults.
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Summary of a coefficient file (.omni).
    Info(cmd::info::InfoArgs),
    /// Evaluate coefficient functions C_F(E), C_T(E).
    #[command(subcommand)]
    Coeffs(cmd::coeffs::CoeffsCommand),
    /// Validation report of a recording set (the paper's Figs. 8, 12, 13).
    Report(cmd::report::ReportArgs),
    /// Simulate one body falling through air (RK4).
    Simulate(cmd::simulate::SimulateArgs),
    /// Firmware simulator: the core on a Cortex-M4F in QEMU, replaying flight logs.
    #[command(subcommand)]
    Firmware(cmd::firmware::FirmwareCommand),
    /// KiteShop (paper §7): check, trim, fly and export 3-D kites.
    #[command(subcommand)]
    Kite(cmd::kite::KiteCommand),
    /// Coefficients of a panel model (plate, open box) projected onto SH.
    Panel(cmd::panel::PanelArgs),
    /// Terminal UI: coefficient spheres, kite design, live simulation,
    /// telemetry (also what `omniad` with no command opens).
    Tui(cmd::tui::TuiArgs),
    /// Fit a coefficient file to a recording set (paper §5-6).
    Fit(cmd::fit::FitArgs),
    /// Find the residual on held-out takes, the effect it points to, and
    /// the error before and after adding it (issue 15).
    Residual(cmd::residual::ResidualArgs),
    /// Smoothed rigid-body states of every take of a recording set (§5).
    Reconstruct(cmd::reconstruct::ReconstructArgs),
    /// Generate a synthetic recording set (with truth/) from a known model.
    Synth(cmd::synth::SynthArgs),
    /// Convert DLTdv / DeepLabCut marker tracks to the recording format.
    ImportTracks(cmd::import::ImportArgs),
    /// Real kite flight telemetry: fit, held-out residual, effects.
    #[command(subcommand)]
    Flight(cmd::flight::FlightCommand),
    /// Speed suite: evaluation, batch, many-body RK4, fit, MuJoCo peer (BENCHMARKS.md).
    Bench(cmd::bench::BenchArgs),
    /// Research measurements behind BENCHMARKS.md (synthetic sets with truth/).
    #[command(subcommand)]
    Lab(cmd::lab::LabCommand),
}

/// Restores the default action of SIGPIPE, which Rust's runtime ignores:
/// `omniad ... | head` then ends quietly when `head` closes the pipe, as
/// every Unix filter does, instead of panicking on the failed write.
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: called first in main, before any thread exists; SIG_DFL is a
    // valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    quiet_on_closed_pipe();
    let cli = Cli::parse();
    let result = match &cli.command {
        None => cmd::tui::run_default(),
        Some(Command::Tui(a)) => cmd::tui::run(a),
        Some(Command::Info(a)) => cmd::info::run(a),
        Some(Command::Coeffs(c)) => cmd::coeffs::run(c),
        Some(Command::Report(a)) => cmd::report::run(a),
        Some(Command::Simulate(a)) => cmd::simulate::run(a),
        Some(Command::Firmware(c)) => cmd::firmware::run(c),
        Some(Command::Kite(c)) => cmd::kite::run(c),
        Some(Command::Panel(a)) => cmd::panel::run(a),
        Some(Command::Fit(a)) => cmd::fit::run(a),
        Some(Command::Reconstruct(a)) => cmd::reconstruct::run(a),
        Some(Command::Residual(a)) => cmd::residual::run(a),
        Some(Command::Synth(a)) => cmd::synth::run(a),
        Some(Command::ImportTracks(a)) => cmd::import::run(a),
        Some(Command::Flight(c)) => cmd::flight::run(c),
        Some(Command::Lab(c)) => cmd::lab::run(c),
        Some(Command::Bench(a)) => cmd::bench::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("omniad: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
