//! `omniad firmware replay LOG [--kite FILE.omni] [--json]` (issue 6).
//!
//! Parses the arguments, runs the replay (`omniad-fw-host`: build the
//! firmware, run it in QEMU on the flight log, replay the same bytes on the
//! host, compare bit for bit, measure the budgets) and prints its report.
//! A firmware error or any host/firmware disagreement is a failure exit.

use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use omniad_fw_host::{firmware_dir, replay, write_telemetry_csv, ReplayOptions, Report};
use std::path::PathBuf;
use std::time::Duration;

/// `omniad firmware ...`
#[derive(Subcommand, Debug)]
pub enum FirmwareCommand {
    /// Replay a flight log through the firmware in QEMU and compare with the host.
    Replay(ReplayArgs),
}

/// Arguments of `omniad firmware replay`.
#[derive(Args, Debug)]
pub struct ReplayArgs {
    /// Flight log: a Kitepower CSV (columns by name, see data/flight/), a
    /// synthetic CSV (time_s,qw,qx,qy,qz,p,q,r,airspeed,aoa_deg,tether_n,depower,steering)
    /// or a `.bin` file of raw bytes sent as is.
    pub log: PathBuf,
    /// Coefficient file to put in the firmware's flash (default: the one
    /// built in, a plate-like model of the Kitepower V3 kite).
    #[arg(long)]
    pub kite: Option<PathBuf>,
    /// Print a JSON report (budgets, agreement, counts).
    #[arg(long)]
    pub json: bool,
    /// Write the firmware's telemetry as CSV here (only if the replay
    /// succeeds).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Only the first N log rows.
    #[arg(long)]
    pub max_frames: Option<usize>,
    /// Insert N garbage byte runs (random bytes, oversize runs, bit flips)
    /// between frames; the firmware must count and skip them.
    #[arg(long, default_value_t = 0)]
    pub garbage: usize,
    /// Do not validate --kite on the host (to see the firmware reject it).
    #[arg(long)]
    pub unchecked_kite: bool,
    /// The firmware workspace (default: $OMNIAD_FIRMWARE_DIR, else
    /// firmware-sim/ of this source tree).
    #[arg(long)]
    pub firmware_dir: Option<PathBuf>,
    /// Do not run cargo; use the ELF files already built.
    #[arg(long)]
    pub no_build: bool,
    /// Seconds before QEMU is killed.
    #[arg(long, default_value_t = 300)]
    pub timeout: u64,
}

/// Runs `omniad firmware ...`.
pub fn run(cmd: &FirmwareCommand) -> Result<()> {
    match cmd {
        FirmwareCommand::Replay(a) => replay_cmd(a),
    }
}

fn replay_cmd(args: &ReplayArgs) -> Result<()> {
    if let Some(p) = &args.csv {
        let inputs: Vec<&std::path::Path> = std::iter::once(args.log.as_path())
            .chain(args.kite.as_deref())
            .collect();
        super::common::refuse_input(p, &inputs)?;
    }
    let out = replay(&ReplayOptions {
        log: args.log.clone(),
        kite: args.kite.clone(),
        max_frames: args.max_frames,
        garbage: args.garbage,
        check_kite: !args.unchecked_kite,
        firmware_dir: firmware_dir(args.firmware_dir.as_deref()),
        build: !args.no_build,
        timeout: Duration::from_secs(args.timeout),
    })?;
    let failure = out.failure();
    if let (None, Some(p)) = (&failure, &args.csv) {
        write_telemetry_csv(p, &out.telemetry)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&out.report)?);
    } else {
        print_text(&out.report);
    }
    match failure {
        Some(why) => bail!(why),
        None => Ok(()),
    }
}

fn print_text(r: &Report) {
    println!("firmware replay of {} (kite: {})", r.log, r.kite);
    let Some(m) = &r.measured else {
        return;
    };
    let (f, a, b) = (&m.frames, &m.agreement, &m.budgets);
    println!(
        "  frames: {} accepted, {} rejected (host: {} / {}), QEMU {:.2} s",
        f.accepted, f.rejected, f.host_accepted, f.host_rejected, r.firmware_seconds
    );
    println!(
        "  host/firmware: {} of {} records bit-identical; core wrench identical on {}",
        a.records.identical, a.records.compared, a.core_wrench_identical
    );
    if a.records.non_finite_records > 0 {
        println!(
            "  {} records have NaN or infinite outputs (the model diverges on this log)",
            a.records.non_finite_records
        );
    }
    println!(
        "  flash {} B (<= {}), RAM {} B = static {} + stack {} (<= {}; stack at boot {}, per frame {})",
        b.flash_bytes,
        b.limits.flash_bytes,
        b.ram_bytes,
        b.static_ram_bytes,
        b.stack_high_water_bytes,
        b.limits.ram_bytes,
        b.stack_high_water_boot_bytes,
        b.stack_high_water_frames_bytes
    );
    println!(
        "  instructions: force eval {:.0} (target {}), frame mean {:.0} / max {:.0} (limit {:.0})",
        b.force_eval_instructions,
        b.limits.force_eval_instructions,
        b.frame_instructions_mean,
        b.frame_instructions_max,
        b.limits.frame_instructions
    );
    println!("  panic symbols in the ELF: {:?}", m.panic_symbols);
}
