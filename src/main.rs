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
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Summary of a coefficient file (.omni).
    Info(cmd::info::InfoArgs),
    /// Evaluate coefficient functions C_F(E), C_T(E).
    #[command(subcommand)]
    Coeffs(cmd::coeffs::CoeffsCommand),
    /// Simulate one body falling through air (RK4).
    Simulate(cmd::simulate::SimulateArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Info(a) => cmd::info::run(a),
        Command::Coeffs(c) => cmd::coeffs::run(c),
        Command::Simulate(a) => cmd::simulate::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("omniad: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
