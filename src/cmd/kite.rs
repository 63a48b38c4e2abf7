//! `omniad kite ...`: KiteShop (paper §7) — static check, trim, tethered
//! flight, fabrication export. The work is in the `omniad-kite` crate.

use anyhow::Result;
use clap::{Args, Subcommand};
use omniad_kite::{Design, Library};
use std::path::{Path, PathBuf};

/// `omniad kite` subcommands.
#[derive(Subcommand, Debug)]
pub enum KiteCommand {
    /// Static equilibrium and stability (tension, unbalanced torque,
    /// attachment point, eigen-axes, verdict).
    Check(StaticArgs),
    /// Orientation at which the kite balances with the file's attachment
    /// point (zero unbalanced torque), and its stability there.
    Trim(StaticArgs),
    /// Tethered flight in gusty wind (RK4); outcome flies / crashes, with
    /// the reason (hit the ground, or unsettled: looping, rolling, low).
    Fly(FlyArgs),
    /// OpenSCAD sockets for every rod joint, a cut list, an SVG drawing.
    Export(ExportArgs),
    /// Searches pitch, string offset and each primitive's yaw, roll and
    /// place across the wind for the largest stability margin (gust
    /// margin, settling, damping), flies the best designs on its own
    /// seeds 101-103, writes the one that flies by the widest margin.
    Optimise(OptimiseArgs),
}

/// Options shared by every kite command.
#[derive(Args, Debug)]
pub struct Common {
    /// Kite file (TOML; see data/kites/README.md).
    pub file: PathBuf,
    /// Primitive library directory (default: $OMNIAD_PRIMITIVES or the
    /// repository's data/primitives).
    #[arg(long)]
    pub primitives: Option<PathBuf>,
}

/// `omniad kite check` and `omniad kite trim`: the same statics inputs.
#[derive(Args, Debug)]
pub struct StaticArgs {
    #[command(flatten)]
    pub common: Common,
    /// Wind speed, m/s, above 0 and at most 60 (default: the file's).
    #[arg(long)]
    pub wind: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `omniad kite fly`.
#[derive(Args, Debug)]
pub struct FlyArgs {
    #[command(flatten)]
    pub common: Common,
    /// Simulated time, s (at most 3600: bounded work).
    #[arg(long, default_value_t = 60.0)]
    pub seconds: f64,
    /// Gust strength G: standard deviation of the along-wind gust, m/s
    /// (0 to 30).
    #[arg(long, default_value_t = 1.0)]
    pub gust: f64,
    /// Turbulence seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Mean wind speed, m/s, above 0 and at most 60 (default: the file's).
    #[arg(long)]
    pub wind: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Write the trace (every 0.05 s) as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

/// `omniad kite export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    #[command(flatten)]
    pub common: Common,
    /// Output directory.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
}

/// `omniad kite optimise`.
#[derive(Args, Debug)]
pub struct OptimiseArgs {
    #[command(flatten)]
    pub common: Common,
    /// Output kite file (written atomically).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Largest number of designs checked, shared by the three searches.
    #[arg(long, default_value_t = omniad_kite::optimise::DEFAULT_EVALUATIONS)]
    pub evaluations: usize,
    /// Designs flown (three 60 s flights each, seeds 101-103) by the
    /// nonlinear check (default: the library's).
    #[arg(long)]
    pub flown: Option<usize>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

fn load(common: &Common) -> Result<Design> {
    let dir = common
        .primitives
        .clone()
        .unwrap_or_else(omniad_kite::library::default_dir);
    let library = Library::load(&dir)?;
    Design::load(Path::new(&common.file), &library)
}

/// Runs a kite subcommand.
pub fn run(command: &KiteCommand) -> Result<()> {
    match command {
        KiteCommand::Check(a) => {
            check_inputs(a.wind, None)?;
            let design = load(&a.common)?;
            let report = omniad_kite::check::check(&design, a.wind)?;
            if a.json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", omniad_kite::check::render(&report));
            }
            Ok(())
        }
        KiteCommand::Trim(a) => {
            check_inputs(a.wind, None)?;
            let design = load(&a.common)?;
            let report = omniad_kite::trimming::trim(&design, a.wind)?;
            if a.json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", omniad_kite::trimming::render(&report));
            }
            Ok(())
        }
        KiteCommand::Fly(a) => fly(a),
        KiteCommand::Optimise(a) => optimise(a),
        KiteCommand::Export(a) => {
            let design = load(&a.common)?;
            for path in omniad_kite::export::export(&design, &a.output)? {
                println!("wrote {}", path.display());
            }
            Ok(())
        }
    }
}

/// The strongest wind accepted, m/s (the kite file's own bound).
const MAX_WIND: f64 = omniad_kite::spec::MAX_WIND_SPEED;
/// The longest simulated flight, s: bounds `kite fly`'s work.
const MAX_SECONDS: f64 = 3600.0;
/// The strongest gust accepted (standard deviation), m/s.
const MAX_GUST: f64 = 30.0;

/// Checks the physical options before any work: `--wind` (when given),
/// and for `kite fly` `(--seconds, --gust)`; errors name the option.
fn check_inputs(wind: Option<f64>, flight: Option<(f64, f64)>) -> Result<()> {
    let mut checks = Vec::with_capacity(3);
    if let Some(w) = wind {
        checks.push((
            "--wind",
            w,
            w > 0.0 && w <= MAX_WIND,
            "above 0 and at most",
            MAX_WIND,
        ));
    }
    if let Some((s, g)) = flight {
        checks.push((
            "--seconds",
            s,
            s > 0.0 && s <= MAX_SECONDS,
            "above 0 and at most",
            MAX_SECONDS,
        ));
        checks.push((
            "--gust",
            g,
            (0.0..=MAX_GUST).contains(&g),
            "from 0 to",
            MAX_GUST,
        ));
    }
    for (name, v, ok, range, max) in checks {
        if !ok {
            anyhow::bail!("{name} must be {range} {max} (got {v})");
        }
    }
    Ok(())
}

fn fly(a: &FlyArgs) -> Result<()> {
    check_inputs(a.wind, Some((a.seconds, a.gust)))?;
    let design = load(&a.common)?;
    let opts = omniad_kite::flight::FlightOptions {
        seconds: a.seconds,
        gust: a.gust,
        seed: a.seed,
        wind: a.wind,
        ..Default::default()
    };
    if let Some(path) = &a.csv {
        super::common::refuse_input(path, &[&a.common.file])?;
    }
    let report = omniad_kite::flight::fly(&design, &opts)?;
    if let Some(path) = &a.csv {
        omniad_io::write_atomic(path, omniad_kite::flight::trace_csv(&report).as_bytes())
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!("{}", omniad_kite::flight::render(&report));
    }
    Ok(())
}

/// `kite optimise`: the search runs in the kite crate; each trial is
/// assembled with the file's library and directory (object files stay
/// relative to the input file).
fn optimise(a: &OptimiseArgs) -> Result<()> {
    let dir = a
        .common
        .primitives
        .clone()
        .unwrap_or_else(omniad_kite::library::default_dir);
    let library = Library::load(&dir)?;
    let design = Design::load(&a.common.file, &library)?;
    let base = a
        .common
        .file
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let assemble = |spec| Design::assemble(spec, &base, &library);
    let defaults = omniad_kite::optimise::OptimiseOptions::default();
    let opts = omniad_kite::optimise::OptimiseOptions {
        max_evaluations: a.evaluations,
        flown: a.flown.unwrap_or(defaults.flown),
    };
    let report = omniad_kite::optimise::optimise(&design, &assemble, &opts)?;
    report.spec.save(&a.output)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", omniad_kite::optimise::render(&report));
        println!("wrote {}", a.output.display());
    }
    Ok(())
}
