//! Running the firmware in QEMU: `mps2-an386` with `-cpu cortex-m4` (the
//! default CPU hangs on hard-float code) and `-icount shift=0`, so that
//! virtual time counts instructions and SysTick measures them. Each run
//! gets a fresh folder holding the ELF, `frames.bin` in and
//! `telemetry.bin` out (semihosting files are relative to QEMU's current
//! directory).

use anyhow::{anyhow, bail, Context, Result};
use omniad_fw_pipeline::frame::decode_block;
use omniad_fw_pipeline::{Output, Summary, Telemetry};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The emulator.
const QEMU: &str = "qemu-system-arm";
const QEMU_ARGS: [&str; 9] = [
    "-machine",
    "mps2-an386",
    "-cpu",
    "cortex-m4",
    "-nographic",
    "-semihosting-config",
    "enable=on,target=native",
    "-icount",
    "shift=0",
];

/// What one run of the replay firmware produced.
#[derive(Debug, Default)]
pub(crate) struct FirmwareRun {
    /// QEMU's exit status (the firmware's `ExitCode`, or -1 if killed).
    pub exit_code: i32,
    /// Telemetry records, in order.
    pub telemetry: Vec<Telemetry>,
    /// The summary record, if it came.
    pub summary: Option<Summary>,
    /// Frames in telemetry.bin that did not decode.
    pub undecodable: usize,
    /// QEMU's console output.
    pub console: String,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Runs one ELF in QEMU in `dir`; returns the exit code and the console
/// output (stdout, then stderr).
fn run_qemu(elf: &Path, dir: &Path, timeout: Duration) -> Result<(i32, String)> {
    let mut child = Command::new(QEMU)
        .args(QEMU_ARGS)
        .arg("-kernel")
        .arg(elf)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("cannot run {QEMU} (Debian: apt-get install qemu-system-arm)"))?;
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait()? {
            break s;
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            bail!("QEMU did not finish within {} s", timeout.as_secs());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut console = String::new();
    if let Some(mut o) = child.stdout.take() {
        let _ = o.read_to_string(&mut console);
    }
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut console);
    }
    Ok((status.code().unwrap_or(-1), console))
}

/// Runs the replay firmware `elf` on `wire` bytes and decodes its
/// telemetry.
pub(crate) fn run_firmware(elf: &[u8], wire: &[u8], timeout: Duration) -> Result<FirmwareRun> {
    let dir = tempfile::tempdir().context("cannot create a folder for QEMU")?;
    let elf_path = dir.path().join("replay.elf");
    std::fs::write(&elf_path, elf)?;
    std::fs::write(dir.path().join("frames.bin"), wire)?;
    let start = Instant::now();
    let (exit_code, console) = run_qemu(&elf_path, dir.path(), timeout)?;
    let mut run = FirmwareRun {
        exit_code,
        console,
        seconds: start.elapsed().as_secs_f64(),
        ..Default::default()
    };
    let out = std::fs::read(dir.path().join("telemetry.bin")).unwrap_or_default();
    for block in out.split(|&b| b == 0).filter(|b| !b.is_empty()) {
        let mut owned = block.to_vec();
        match decode_block::<Output>(&mut owned) {
            Ok(Output::Telemetry(t)) => run.telemetry.push(t),
            Ok(Output::Summary(s)) => run.summary = Some(s),
            Err(_) => run.undecodable += 1,
        }
    }
    Ok(run)
}

/// Runs the bench firmware; returns its `key=value` console lines.
pub(crate) fn run_bench(elf: &[u8], timeout: Duration) -> Result<BTreeMap<String, f64>> {
    let dir = tempfile::tempdir().context("cannot create a folder for QEMU")?;
    let path = dir.path().join("bench.elf");
    std::fs::write(&path, elf)?;
    let (code, console) = run_qemu(&path, dir.path(), timeout)?;
    if code != 0 {
        return Err(anyhow!("bench firmware exited with {code}: {console}"));
    }
    Ok(console
        .lines()
        .filter_map(|l| l.split_once('='))
        .filter_map(|(k, v)| Some((k.trim().to_string(), v.trim().parse::<f64>().ok()?)))
        .collect())
}
