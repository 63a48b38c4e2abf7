//! One replay, end to end: read the log and put it on the wire, build the
//! firmware, put the coefficient file in its flash, run it in QEMU, replay
//! the same bytes on the host, compare, run the bench firmware, measure.

use crate::build::{build_firmware, elf_path};
use crate::compare::{all_identical, compare};
use crate::elf::Elf;
use crate::flash::{embedded_kite, patch_kite};
use crate::host_replay::{core_wrench_identical, run_host, HostRun};
use crate::log::read_log;
use crate::qemu::{run_bench, run_firmware, FirmwareRun};
use crate::report::{
    AgreementReport, Budgets, Frames, Limits, Measured, RejectedByKind, Report, Within,
};
use crate::wire::wire_bytes;
use anyhow::{anyhow, bail, Context, Result};
use omniad_core::file::{self, FileError, MAX_FILE_SIZE};
use omniad_core::Coefficients;
use omniad_fw_pipeline::{ExitCode, Summary, Telemetry};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Longest raw `.bin` log, bytes.
const MAX_WIRE_BYTES: usize = 256 << 20;

/// What to replay, and how.
#[derive(Debug, Clone)]
pub struct ReplayOptions {
    /// A Kitepower or synthetic CSV log, or a `.bin` file of raw bytes.
    pub log: PathBuf,
    /// A coefficient file for the firmware's flash (default: built in).
    pub kite: Option<PathBuf>,
    /// Only the first N log rows.
    pub max_frames: Option<usize>,
    /// Garbage byte runs to insert between frames.
    pub garbage: usize,
    /// Refuse a coefficient file the host cannot decode (before QEMU).
    pub check_kite: bool,
    /// The firmware workspace.
    pub firmware_dir: PathBuf,
    /// Run cargo on the firmware first.
    pub build: bool,
    /// Time before QEMU is killed.
    pub timeout: Duration,
}

/// A finished replay: the report, the firmware's telemetry and console.
#[derive(Debug)]
pub struct Replay {
    /// Everything measured.
    pub report: Report,
    /// The firmware's telemetry records.
    pub telemetry: Vec<Telemetry>,
    /// QEMU's console output.
    pub console: String,
}

impl Replay {
    /// Why the replay failed (firmware error or disagreement), if it did.
    pub fn failure(&self) -> Option<String> {
        self.report.failure(&self.console)
    }
}

/// Runs one replay. Errors are what stops it from running (bad log, bad
/// coefficient file, no QEMU); a firmware error or a disagreement is a
/// finished replay whose [`Replay::failure`] says so.
pub fn replay(o: &ReplayOptions) -> Result<Replay> {
    // The log first: a broken input fails before a long firmware build.
    let (log_rows, wire) = log_on_the_wire(o)?;
    if o.build {
        build_firmware(&o.firmware_dir)?;
    }
    let fw = Firmware::load(o)?;
    let run = run_firmware(&fw.image, &wire, o.timeout)?;
    let mut report = Report {
        log: o.log.display().to_string(),
        kite: o
            .kite
            .as_ref()
            .map_or("(built in)".into(), |p| p.display().to_string()),
        firmware_exit_code: run.exit_code,
        firmware_error: None,
        firmware_seconds: run.seconds,
        wire_bytes: wire.len(),
        log_rows,
        measured: None,
    };
    if run.exit_code != 0 {
        let code = ExitCode::from_status(run.exit_code);
        report.firmware_error = Some(code.map_or("unexpected exit", ExitCode::describe));
    } else {
        let mut model = fw.model.map_err(|e| anyhow!("coefficient file: {e}"))?;
        // The firmware runs the core's portable path; the host compares
        // against that same path (its SIMD path agrees only to rounding).
        model.set_portable(true);
        report.measured = Some(measure(o, &model, &fw.elf, &fw.kite, &wire, &run)?);
    }
    Ok(Replay {
        report,
        telemetry: run.telemetry,
        console: run.console,
    })
}

/// The log's rows (none for a `.bin` log) and the bytes sent to the
/// firmware.
fn log_on_the_wire(o: &ReplayOptions) -> Result<(Option<usize>, Vec<u8>)> {
    if o.log.extension().is_some_and(|e| e == "bin") {
        return Ok((None, read(&o.log, MAX_WIRE_BYTES)?));
    }
    let frames = read_log(&o.log, o.max_frames)?;
    Ok((Some(frames.len()), wire_bytes(&frames, o.garbage)?))
}

/// The replay firmware as it will run.
struct Firmware {
    /// The built ELF, parsed (sizes and symbols do not change by patching).
    elf: Elf,
    /// The ELF to run: the built one, with `--kite`'s file in flash.
    image: Vec<u8>,
    /// The coefficient file in its flash.
    kite: Vec<u8>,
    /// That file decoded on the host.
    model: Result<Coefficients<f32>, FileError>,
}

impl Firmware {
    /// Reads the built replay ELF and puts the coefficient file in it;
    /// refuses a file the host cannot decode unless told not to check.
    fn load(o: &ReplayOptions) -> Result<Self> {
        let path = elf_path(&o.firmware_dir, "replay");
        let built = std::fs::read(&path).with_context(|| {
            format!("cannot read {} (build the firmware first)", path.display())
        })?;
        let elf = Elf::parse(&built)?;
        let kite = match &o.kite {
            Some(p) => read(p, MAX_FILE_SIZE)?,
            None => embedded_kite(&built, &elf)?,
        };
        let model = file::decode::<f32>(&kite);
        if let (true, Err(e)) = (o.check_kite, &model) {
            bail!("coefficient file: {e}");
        }
        let image = with_kite(o, built, &kite)?;
        Ok(Self {
            elf,
            image,
            kite,
            model,
        })
    }
}

/// Reads a user's file, at most `max` bytes.
fn read(path: &Path, max: usize) -> Result<Vec<u8>> {
    omniad_io::read_capped(path, max).with_context(|| format!("cannot read {}", path.display()))
}

/// The ELF with `--kite`'s file in its flash (unchanged without one).
fn with_kite(o: &ReplayOptions, elf_bytes: Vec<u8>, kite: &[u8]) -> Result<Vec<u8>> {
    match o.kite {
        Some(_) => patch_kite(&elf_bytes, &Elf::parse(&elf_bytes)?, kite),
        None => Ok(elf_bytes),
    }
}

/// Host replay, comparison, bench and budgets of a firmware run that
/// exited 0.
fn measure(
    o: &ReplayOptions,
    model: &Coefficients<f32>,
    elf: &Elf,
    kite: &[u8],
    wire: &[u8],
    run: &FirmwareRun,
) -> Result<Measured> {
    let summary = run
        .summary
        .ok_or_else(|| anyhow!("the firmware wrote no summary"))?;
    let host = run_host(model, wire)?;
    let bench_path = elf_path(&o.firmware_dir, "bench");
    let bench_elf = std::fs::read(&bench_path)
        .with_context(|| format!("cannot read {}", bench_path.display()))?;
    let bench = run_bench(&with_kite(o, bench_elf, kite)?, o.timeout)?;
    Ok(Measured {
        frames: frames(&summary, &host, run),
        agreement: agreement(model, &summary, &host, run),
        budgets: budgets(model, elf, &summary, &bench),
        panic_symbols: elf.panic_symbols(),
    })
}

fn frames(summary: &Summary, host: &HostRun, run: &FirmwareRun) -> Frames {
    let [oversize, corrupt, non_finite, out_of_range] = summary.rejected;
    Frames {
        accepted: summary.accepted,
        rejected: summary.rejected.iter().sum(),
        rejected_by_kind: RejectedByKind {
            oversize,
            corrupt,
            non_finite,
            out_of_range,
        },
        host_accepted: host.telemetry.len(),
        host_rejected: host.rejects.total(),
        telemetry_records: run.telemetry.len(),
        undecodable_telemetry: run.undecodable,
    }
}

fn agreement(
    model: &Coefficients<f32>,
    summary: &Summary,
    host: &HostRun,
    run: &FirmwareRun,
) -> AgreementReport {
    let records = compare(&host.telemetry, &run.telemetry);
    let same_rejects = host.rejects.0 == summary.rejected;
    let all_identical = all_identical(
        &records,
        host.telemetry.len(),
        run.telemetry.len(),
        same_rejects,
    );
    AgreementReport {
        records,
        all_identical,
        core_wrench_identical: core_wrench_identical(model, &host.inputs, &run.telemetry),
        tolerance: "none: identical bits required (any NaN equals any NaN)",
    }
}

fn budgets(
    model: &Coefficients<f32>,
    elf: &Elf,
    s: &Summary,
    bench: &BTreeMap<String, f64>,
) -> Budgets {
    let per_rep = |key: &str| bench.get(key).map(|v| v / 1000.0);
    let force_eval = per_rep("force_eval_insns_milli").unwrap_or(f64::NAN);
    let (flash, static_ram) = (elf.flash_bytes(), elf.static_ram_bytes());
    let ram = static_ram + u64::from(s.stack_high_water);
    let frame_max = f64::from(s.max_frame_instructions);
    let limits = Limits::ISSUE_6;
    Budgets {
        flash_bytes: flash,
        static_ram_bytes: static_ram,
        stack_high_water_bytes: s.stack_high_water,
        stack_high_water_boot_bytes: s.stack_high_water_boot,
        stack_high_water_frames_bytes: s.stack_high_water_frames,
        stack_capacity_bytes: s.stack_capacity,
        ram_bytes: ram,
        ram_frames_bytes: static_ram + u64::from(s.stack_high_water_frames),
        ram_boot_bytes: static_ram + u64::from(s.stack_high_water_boot),
        force_eval_instructions: force_eval,
        force_eval_no_damping_instructions: per_rep("force_eval_no_damping_insns_milli"),
        frame_instructions_mean: s.total_frame_instructions as f64 / f64::from(s.accepted.max(1)),
        frame_instructions_max: frame_max,
        frame_instructions_bench: per_rep("frame_insns_milli").unwrap_or(f64::NAN),
        decode_instructions: bench.get("decode_insns").copied(),
        model_degree: model.degree(),
        model_torque_degree: model.torque_degree(),
        instructions_per_systick_tick: f64::from(s.insns_per_tick_milli) / 1000.0,
        within: Within {
            flash: flash <= limits.flash_bytes,
            ram: ram <= limits.ram_bytes,
            force_eval: force_eval <= limits.force_eval_instructions,
            frame: frame_max <= limits.frame_instructions,
        },
        limits,
        frame_rate_at_168mhz_hz: 168e6 / frame_max,
    }
}
