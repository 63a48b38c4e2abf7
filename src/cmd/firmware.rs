//! `omniad firmware replay LOG [--kite FILE.omni] [--json]` (issue 6).
//!
//! Builds the firmware in `firmware-sim/` if needed, boots it in QEMU
//! (`mps2-an386`, Cortex-M4F, `-icount shift=0`), feeds it the flight log
//! as framed sensor frames through semihosting, collects its telemetry,
//! replays the same bytes through the host build of the same code
//! (`omniad-fw-pipeline` + `omniad-core`, `f32`) and compares every output
//! bit for bit. Also measures the budgets: flash and RAM from the ELF,
//! stack high-water mark (painting), instructions per frame and per force
//! evaluation, and checks the ELF for panic symbols.

use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Subcommand};
use omniad_core::file::{self, FileError, HEADER_LEN};
use omniad_core::Coefficients;
use omniad_fw_pipeline::frame::{
    self, decode_block, Output, RejectCounts, Summary, Telemetry, NUMBER_NAMES,
};
use omniad_fw_pipeline::process::air_inputs;
use omniad_fw_pipeline::{Deframer, Processor, SensorFrame};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Budgets of issue 6.
pub mod budget {
    /// Flash, bytes.
    pub const FLASH: u64 = 128 * 1024;
    /// RAM including the stack, bytes.
    pub const RAM: u64 = 32 * 1024;
    /// Force + torque evaluation at N = 8, instructions.
    pub const FORCE_EVAL: f64 = 2_500.0;
    /// One telemetry frame: 100 Hz on a 168 MHz M4F with 5x headroom,
    /// instructions (taking one instruction per cycle).
    pub const FRAME: f64 = 168e6 / 100.0 / 5.0;
}

/// QEMU command line (the `-cpu cortex-m4` matters: the default CPU hangs
/// on hard-float code).
pub const QEMU: &str = "qemu-system-arm";
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
    /// Write the firmware's telemetry as CSV here.
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
    /// The firmware workspace (default: firmware-sim/ of this source tree).
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
        FirmwareCommand::Replay(a) => replay(a),
    }
}

fn firmware_dir(args: &ReplayArgs) -> PathBuf {
    args.firmware_dir
        .clone()
        .or_else(|| std::env::var_os("OMNIAD_FIRMWARE_DIR").map(PathBuf::from))
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("firmware-sim"))
}

/// Builds the firmware (release) with its own target directory.
pub fn build_firmware(dir: &Path) -> Result<()> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(dir)
        .args(["build", "--release", "--bins", "--target-dir"])
        .arg(dir.join("target"))
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_BUILD_TARGET")
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_RUSTFLAGS")
        .output()
        .context("cannot run cargo to build the firmware")?;
    if !out.status.success() {
        bail!(
            "firmware build failed in {}:\n{}",
            dir.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(())
}

fn elf_path(dir: &Path, bin: &str) -> PathBuf {
    dir.join("target/thumbv7em-none-eabihf/release").join(bin)
}

// ---------------------------------------------------------------- ELF32

/// What the harness needs from a 32-bit little-endian ELF.
#[derive(Debug, Default)]
pub struct Elf {
    /// `(name, file offset, size, address, flags, type)` per section.
    pub sections: Vec<(String, usize, usize, u32, u32, u32)>,
    /// `(paddr, vaddr, filesz, memsz)` per PT_LOAD segment.
    pub loads: Vec<(u32, u32, u32, u32)>,
    /// Symbol names.
    pub symbols: Vec<String>,
}

fn rd16(b: &[u8], at: usize) -> Result<u16> {
    let s = b.get(at..at + 2).ok_or_else(|| anyhow!("ELF truncated"))?;
    Ok(u16::from_le_bytes([s[0], s[1]]))
}
fn rd32(b: &[u8], at: usize) -> Result<u32> {
    let s = b.get(at..at + 4).ok_or_else(|| anyhow!("ELF truncated"))?;
    Ok(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}
fn cstr(b: &[u8], at: usize) -> String {
    let s = b.get(at..).unwrap_or(&[]);
    let end = s.iter().position(|&c| c == 0).unwrap_or(s.len());
    String::from_utf8_lossy(&s[..end]).into_owned()
}

impl Elf {
    /// Parses sections, load segments and symbols.
    pub fn parse(b: &[u8]) -> Result<Self> {
        if b.get(..4) != Some(b"\x7fELF") || b.get(4) != Some(&1) || b.get(5) != Some(&1) {
            bail!("not a 32-bit little-endian ELF");
        }
        let (phoff, shoff) = (rd32(b, 28)? as usize, rd32(b, 32)? as usize);
        let (phentsize, phnum) = (rd16(b, 42)? as usize, rd16(b, 44)? as usize);
        let (shentsize, shnum, shstrndx) = (
            rd16(b, 46)? as usize,
            rd16(b, 48)? as usize,
            rd16(b, 50)? as usize,
        );
        let mut elf = Elf::default();
        for i in 0..phnum {
            let p = phoff + i * phentsize;
            if rd32(b, p)? == 1 {
                elf.loads.push((
                    rd32(b, p + 12)?,
                    rd32(b, p + 8)?,
                    rd32(b, p + 16)?,
                    rd32(b, p + 20)?,
                ));
            }
        }
        let sh = |i: usize, field: usize| rd32(b, shoff + i * shentsize + field);
        let names_off = sh(shstrndx, 16)? as usize;
        let mut raw = Vec::new();
        for i in 0..shnum {
            let name = cstr(b, names_off + sh(i, 0)? as usize);
            let (kind, flags, addr) = (sh(i, 4)?, sh(i, 8)?, sh(i, 12)?);
            let (off, size, link) = (
                sh(i, 16)? as usize,
                sh(i, 20)? as usize,
                sh(i, 24)? as usize,
            );
            raw.push((kind, off, size, link));
            elf.sections.push((name, off, size, addr, flags, kind));
        }
        for &(kind, off, size, link) in &raw {
            if kind != 2 {
                continue; // SHT_SYMTAB
            }
            let str_off = raw.get(link).map(|s| s.1).unwrap_or(0);
            for e in (off..off + size).step_by(16) {
                let name = cstr(b, str_off + rd32(b, e)? as usize);
                if !name.is_empty() {
                    elf.symbols.push(name);
                }
            }
        }
        Ok(elf)
    }

    /// Flash used: file bytes of loadable segments placed below RAM
    /// (code, read-only data, the coefficient region, `.data`'s image).
    pub fn flash_bytes(&self) -> u64 {
        self.loads
            .iter()
            .filter(|l| l.0 < 0x2000_0000)
            .map(|l| l.2 as u64)
            .sum()
    }
    /// Static RAM: memory size of segments running from RAM (`.data`,
    /// `.bss`, `.uninit`).
    pub fn static_ram_bytes(&self) -> u64 {
        self.loads
            .iter()
            .filter(|l| l.1 >= 0x2000_0000)
            .map(|l| l.3 as u64)
            .sum()
    }
    /// A section by name: (file offset, size).
    pub fn section(&self, name: &str) -> Option<(usize, usize)> {
        self.sections
            .iter()
            .find(|s| s.0 == name)
            .map(|s| (s.1, s.2))
    }
    /// Symbols that belong to Rust's panic machinery.
    pub fn panic_symbols(&self) -> Vec<String> {
        const NEEDLES: [&str; 5] = [
            "panicking",
            "panic_bounds_check",
            "panic_fmt",
            "rust_begin_unwind",
            "reachable_panic",
        ];
        let mut v: Vec<String> = self
            .symbols
            .iter()
            .filter(|s| NEEDLES.iter().any(|n| s.contains(n)))
            .cloned()
            .collect();
        v.sort();
        v.dedup();
        v
    }
}

/// The coefficient file embedded in an ELF's `.kite` section.
pub fn embedded_kite(elf_bytes: &[u8], elf: &Elf) -> Result<Vec<u8>> {
    let (off, size) = elf
        .section(".kite")
        .ok_or_else(|| anyhow!("no .kite section in the firmware"))?;
    let region = elf_bytes
        .get(off..off + size)
        .ok_or_else(|| anyhow!(".kite outside the ELF"))?;
    let len = rd32(region, 10).unwrap_or(0) as usize + HEADER_LEN + 4;
    Ok(region.get(..len.min(size)).unwrap_or(region).to_vec())
}

/// A copy of the ELF with `kite` in its `.kite` section (padded with 0xFF).
pub fn patch_kite(elf_bytes: &[u8], elf: &Elf, kite: &[u8]) -> Result<Vec<u8>> {
    let (off, size) = elf
        .section(".kite")
        .ok_or_else(|| anyhow!("no .kite section in the firmware"))?;
    if kite.len() > size {
        bail!(
            "coefficient file is {} bytes, the firmware reserves {size}",
            kite.len()
        );
    }
    let mut out = elf_bytes.to_vec();
    let region = out
        .get_mut(off..off + size)
        .ok_or_else(|| anyhow!(".kite outside the ELF"))?;
    region.fill(0xFF);
    region[..kite.len()].copy_from_slice(kite);
    Ok(out)
}

// ---------------------------------------------------------------- logs

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Unit quaternion `[w, x, y, z]` of the 3-2-1 (yaw, pitch, roll) Euler
/// sequence from NED to FRD: body-to-world rotation.
pub fn quaternion_from_euler(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (sr, cr) = (roll * 0.5).sin_cos();
    let (sp, cp) = (pitch * 0.5).sin_cos();
    let (sy, cy) = (yaw * 0.5).sin_cos();
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

fn parse_num(s: &str) -> f64 {
    s.trim().parse::<f64>().unwrap_or(f64::NAN)
}

/// Reads a flight log into sensor frames (NaN where a value is missing:
/// the firmware rejects such frames).
pub fn read_log(path: &Path, max: Option<usize>) -> Result<Vec<SensorFrame>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::trim)
        .collect();
    let col = |name: &str| header.iter().position(|h| *h == name);
    let kitepower = col("airspeed_apparent_windspeed").is_some();
    let names: [&str; 13] = if kitepower {
        [
            "time",
            "kite_1_roll",
            "kite_1_pitch",
            "kite_1_yaw",
            "kite_1_roll_rate",
            "kite_1_pitch_rate",
            "kite_1_yaw_rate",
            "airspeed_apparent_windspeed",
            "airspeed_angle_of_attack",
            "ground_tether_force",
            "kite_actual_depower",
            "kite_actual_steering",
            "time",
        ]
    } else {
        [
            "time_s", "qw", "qx", "qy", "qz", "p", "q", "r", "airspeed", "aoa_deg", "tether_n",
            "depower", "steering",
        ]
    };
    let idx: Vec<usize> = names
        .iter()
        .map(|n| col(n).ok_or_else(|| anyhow!("{}: no column `{n}`", path.display())))
        .collect::<Result<_>>()?;
    let mut frames = Vec::new();
    for line in lines {
        if line.trim().is_empty() {
            continue;
        }
        if max.is_some_and(|m| frames.len() >= m) {
            break;
        }
        let cells: Vec<&str> = line.split(',').collect();
        let v: Vec<f64> = idx
            .iter()
            .map(|&i| cells.get(i).map_or(f64::NAN, |c| parse_num(c)))
            .collect();
        let f = if kitepower {
            let q = quaternion_from_euler(deg(v[1]), deg(v[2]), deg(v[3]));
            SensorFrame {
                time_ms: (v[0] * 1000.0).round().max(0.0) as u64,
                attitude: q.map(|x| x as f32),
                rates: [v[4] as f32, v[5] as f32, v[6] as f32],
                airspeed: v[7] as f32,
                angle_of_attack: deg(v[8]) as f32,
                tether_force: (v[9] * 9.806_65) as f32, // kg -> N
                depower: (v[10] / 100.0) as f32,
                steering: (v[11] / 100.0) as f32,
            }
        } else {
            SensorFrame {
                time_ms: (v[0] * 1000.0).round().max(0.0) as u64,
                attitude: [v[1] as f32, v[2] as f32, v[3] as f32, v[4] as f32],
                rates: [v[5] as f32, v[6] as f32, v[7] as f32],
                airspeed: v[8] as f32,
                angle_of_attack: deg(v[9]) as f32,
                tether_force: v[10] as f32,
                depower: v[11] as f32,
                steering: v[12] as f32,
            }
        };
        frames.push(f);
    }
    Ok(frames)
}

/// xorshift64, deterministic garbage.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// Encodes frames on the wire, with `garbage` corrupted runs spread
/// between them (cycling: random bytes, an oversize run, a frame with one
/// flipped bit, a truncated frame).
pub fn wire_bytes(frames: &[SensorFrame], garbage: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let every = frames
        .len()
        .checked_div(garbage)
        .map_or(usize::MAX, |n| n.max(1));
    let mut injected = 0;
    let mut buf = [0u8; 2 * frame::MAX_FRAME];
    for (i, f) in frames.iter().enumerate() {
        let n = frame::encode_frame(f, &mut buf).ok_or_else(|| anyhow!("frame does not encode"))?;
        if injected < garbage && i % every == every / 2 {
            match injected % 4 {
                0 => {
                    let len = 1 + (rng.next() % 40) as usize;
                    out.extend((0..len).map(|_| (rng.next() % 255) as u8 + 1));
                    out.push(0);
                }
                1 => {
                    out.extend(std::iter::repeat_n(0x55u8, frame::MAX_FRAME + 10));
                    out.push(0);
                }
                2 => {
                    let mut bad = buf[..n].to_vec();
                    let at = (rng.next() as usize) % (n - 1);
                    let bit = 1u8 << (rng.next() % 8);
                    bad[at] ^= bit;
                    if bad[at] == 0 {
                        bad[at] = 0xA5;
                    }
                    out.extend_from_slice(&bad);
                }
                _ => {
                    out.extend_from_slice(&buf[..n / 2]);
                    out.push(0);
                }
            }
            injected += 1;
        }
        out.extend_from_slice(&buf[..n]);
    }
    Ok(out)
}

// ---------------------------------------------------------------- runs

/// What one firmware run produced.
#[derive(Debug, Default)]
pub struct FirmwareRun {
    /// QEMU's exit status.
    pub exit_code: i32,
    /// Telemetry records.
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

fn temp_dir() -> Result<PathBuf> {
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("omniad-firmware-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    Ok(dir)
}

/// Runs one ELF in QEMU in `dir` (which holds frames.bin); returns the exit
/// code and the console output.
pub fn run_qemu(elf: &Path, dir: &Path, timeout: Duration) -> Result<(i32, String)> {
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
        use std::io::Read;
        let _ = o.read_to_string(&mut console);
    }
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut console);
    }
    Ok((status.code().unwrap_or(-1), console))
}

/// Runs the replay firmware on `wire` bytes.
pub fn run_firmware(elf: &[u8], wire: &[u8], timeout: Duration) -> Result<FirmwareRun> {
    let dir = temp_dir()?;
    let elf_path = dir.join("replay.elf");
    std::fs::write(&elf_path, elf)?;
    std::fs::write(dir.join("frames.bin"), wire)?;
    let start = Instant::now();
    let (exit_code, console) = run_qemu(&elf_path, &dir, timeout)?;
    let mut run = FirmwareRun {
        exit_code,
        console,
        seconds: start.elapsed().as_secs_f64(),
        ..Default::default()
    };
    let out = std::fs::read(dir.join("telemetry.bin")).unwrap_or_default();
    for block in out.split(|&b| b == 0) {
        if block.is_empty() {
            continue;
        }
        let mut owned = block.to_vec();
        match decode_block::<Output>(&mut owned) {
            Ok(Output::Telemetry(t)) => run.telemetry.push(t),
            Ok(Output::Summary(s)) => run.summary = Some(s),
            Err(_) => run.undecodable += 1,
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(run)
}

/// The host's replay of the same bytes: same deframer, same processor,
/// compiled for the host.
pub fn run_host(
    model: &Coefficients<f32>,
    wire: &[u8],
) -> Result<(Vec<Telemetry>, RejectCounts, Vec<SensorFrame>)> {
    let processor = Processor::new(model).map_err(|e| anyhow!("mass properties: {e}"))?;
    let mut d = Deframer::new();
    let mut rejects = RejectCounts::default();
    let (mut out, mut inputs) = (Vec::new(), Vec::new());
    for &b in wire {
        match d.push(b) {
            None => {}
            Some(Err(r)) => rejects.add(r),
            Some(Ok(f)) => {
                out.push(processor.process(out.len() as u32, rejects.total(), &f));
                inputs.push(f);
            }
        }
    }
    if let Some(r) = d.finish() {
        rejects.add(r);
    }
    Ok((out, rejects, inputs))
}

/// Runs the bench firmware; returns its `key=value` lines.
pub fn run_bench(elf: &[u8], timeout: Duration) -> Result<BTreeMap<String, f64>> {
    let dir = temp_dir()?;
    let path = dir.join("bench.elf");
    std::fs::write(&path, elf)?;
    let (code, console) = run_qemu(&path, &dir, timeout)?;
    let _ = std::fs::remove_dir_all(&dir);
    if code != 0 {
        bail!("bench firmware exited with {code}: {console}");
    }
    Ok(console
        .lines()
        .filter_map(|l| l.split_once('='))
        .filter_map(|(k, v)| Some((k.trim().to_string(), v.trim().parse::<f64>().ok()?)))
        .collect())
}

/// Bitwise comparison of host and firmware telemetry.
#[derive(Debug, Default)]
pub struct Agreement {
    /// Records compared.
    pub compared: usize,
    /// Records whose every number has identical bits.
    pub identical: usize,
    /// Largest absolute difference of any number.
    pub max_abs_diff: f64,
    /// Per-field count of differing records.
    pub differing_fields: BTreeMap<&'static str, usize>,
}

/// Compares record by record (sequence, timestamp, reject count and the
/// bits of every computed number).
pub fn compare(host: &[Telemetry], fw: &[Telemetry]) -> Agreement {
    let mut a = Agreement {
        compared: host.len().min(fw.len()),
        ..Default::default()
    };
    for (h, f) in host.iter().zip(fw) {
        let (hn, fn_) = (h.numbers(), f.numbers());
        let mut same = h.seq == f.seq && h.time_ms == f.time_ms && h.rejected == f.rejected;
        for (i, (x, y)) in hn
            .iter()
            .zip(fn_.iter())
            .enumerate()
            .take(NUMBER_NAMES.len())
        {
            if x.to_bits() != y.to_bits() {
                same = false;
                *a.differing_fields.entry(NUMBER_NAMES[i]).or_default() += 1;
                let d = (*x as f64 - *y as f64).abs();
                a.max_abs_diff = a
                    .max_abs_diff
                    .max(if d.is_nan() { f64::INFINITY } else { d });
            }
        }
        if same {
            a.identical += 1;
        }
    }
    a
}

fn file_error_name(code: i32) -> Option<&'static str> {
    Some(match code {
        10 => "bad magic",
        11 => "unknown version",
        12 => "truncated",
        13 => "CRC mismatch",
        14 => "trailing bytes",
        15 => "malformed payload",
        16 => "payload length",
        17 => "bad count",
        18 => "invalid model",
        19 => "buffer too small",
        20 => "invalid mass properties",
        2 => "cannot open frames.bin",
        3 => "cannot write telemetry.bin",
        _ => return None,
    })
}

fn write_csv(path: &Path, t: &[Telemetry]) -> Result<()> {
    let mut f = std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?,
    );
    write!(f, "seq,time_ms")?;
    for n in NUMBER_NAMES {
        write!(f, ",{n}")?;
    }
    writeln!(f, ",rejected,instructions")?;
    for r in t {
        write!(f, "{},{}", r.seq, r.time_ms)?;
        for x in r.numbers().iter().take(NUMBER_NAMES.len()) {
            write!(f, ",{x}")?;
        }
        writeln!(f, ",{},{}", r.rejected, r.instructions)?;
    }
    Ok(())
}

fn replay(args: &ReplayArgs) -> Result<()> {
    let dir = firmware_dir(args);
    if !args.no_build {
        build_firmware(&dir)?;
    }
    let replay_path = elf_path(&dir, "replay");
    let elf_bytes = std::fs::read(&replay_path).with_context(|| {
        format!(
            "cannot read {} (build the firmware first)",
            replay_path.display()
        )
    })?;
    let elf = Elf::parse(&elf_bytes)?;
    let kite = match &args.kite {
        Some(p) => std::fs::read(p).with_context(|| format!("cannot read {}", p.display()))?,
        None => embedded_kite(&elf_bytes, &elf)?,
    };
    let host_model: Result<Coefficients<f32>, FileError> = file::decode::<f32>(&kite);
    if !args.unchecked_kite {
        if let Err(e) = &host_model {
            bail!("coefficient file: {e}");
        }
    }
    let fw_elf = if args.kite.is_some() {
        patch_kite(&elf_bytes, &elf, &kite)?
    } else {
        elf_bytes.clone()
    };

    let frames = if args.log.extension().is_some_and(|e| e == "bin") {
        None
    } else {
        Some(read_log(&args.log, args.max_frames)?)
    };
    let wire = match &frames {
        Some(f) => wire_bytes(f, args.garbage)?,
        None => std::fs::read(&args.log)
            .with_context(|| format!("cannot read {}", args.log.display()))?,
    };
    let timeout = Duration::from_secs(args.timeout);
    let run = run_firmware(&fw_elf, &wire, timeout)?;

    let mut report = json!({
        "log": args.log.display().to_string(),
        "kite": args.kite.as_ref().map_or("(built in)".to_string(), |p| p.display().to_string()),
        "firmware_exit_code": run.exit_code,
        "firmware_seconds": run.seconds,
        "wire_bytes": wire.len(),
        "log_rows": frames.as_ref().map(Vec::len),
    });
    if run.exit_code != 0 {
        let why = file_error_name(run.exit_code).unwrap_or("unexpected exit");
        report["firmware_error"] = json!(why);
        if args.json {
            println!("{}", serde_json::to_string_pretty(&report)?);
        }
        bail!(
            "firmware exited with code {} ({why}); console: {}",
            run.exit_code,
            run.console.trim()
        );
    }
    let mut model = host_model.map_err(|e| anyhow!("coefficient file: {e}"))?;
    // The firmware runs the core's portable path; the host compares against
    // that same path (its SIMD path agrees only to rounding).
    model.set_portable(true);
    let summary = run
        .summary
        .ok_or_else(|| anyhow!("the firmware wrote no summary"))?;
    let (host, host_rejects, inputs) = run_host(&model, &wire)?;
    let agreement = compare(&host, &run.telemetry);

    // The core's own f32 path (Coefficients::wrench, portable) against the
    // firmware.
    let core_identical = inputs
        .iter()
        .zip(&run.telemetry)
        .filter(|(f, t)| {
            let (v, w) = air_inputs(f);
            let r = model.wrench(&v, &w, omniad_fw_pipeline::process::AIR_DENSITY);
            let bits =
                |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            bits(r.force.as_slice(), &t.force) && bits(r.torque.as_slice(), &t.torque)
        })
        .count();

    let bench_elf_path = elf_path(&dir, "bench");
    let bench_elf = std::fs::read(&bench_elf_path)
        .with_context(|| format!("cannot read {}", bench_elf_path.display()))?;
    let bench_elf = if args.kite.is_some() {
        patch_kite(&bench_elf, &Elf::parse(&bench_elf)?, &kite)?
    } else {
        bench_elf
    };
    let bench = run_bench(&bench_elf, timeout)?;
    let force_eval = bench
        .get("force_eval_insns_milli")
        .copied()
        .unwrap_or(f64::NAN)
        / 1000.0;
    let frame_bench = bench.get("frame_insns_milli").copied().unwrap_or(f64::NAN) / 1000.0;

    let flash = elf.flash_bytes();
    let static_ram = elf.static_ram_bytes();
    let ram = static_ram + summary.stack_high_water as u64;
    let frames_ok = summary.accepted.max(1) as f64;
    let frame_mean = summary.total_frame_instructions as f64 / frames_ok;
    let frame_max = summary.max_frame_instructions as f64;
    let panics = elf.panic_symbols();
    let within = json!({
        "flash": flash <= budget::FLASH,
        "ram": ram <= budget::RAM,
        "force_eval": force_eval <= budget::FORCE_EVAL,
        "frame": frame_max <= budget::FRAME,
    });
    let fw_rejects: u32 = summary.rejected.iter().sum();
    report["frames"] = json!({
        "accepted": summary.accepted,
        "rejected": fw_rejects,
        "rejected_by_kind": {
            "oversize": summary.rejected[0], "corrupt": summary.rejected[1],
            "non_finite": summary.rejected[2], "out_of_range": summary.rejected[3],
        },
        "host_accepted": host.len(),
        "host_rejected": host_rejects.total(),
        "telemetry_records": run.telemetry.len(),
        "undecodable_telemetry": run.undecodable,
    });
    report["agreement"] = json!({
        "compared": agreement.compared,
        "identical": agreement.identical,
        "all_identical": agreement.compared == host.len()
            && agreement.compared == run.telemetry.len()
            && agreement.identical == agreement.compared
            && host_rejects.0 == summary.rejected,
        "max_abs_diff": agreement.max_abs_diff,
        "differing_fields": agreement.differing_fields,
        "core_wrench_identical": core_identical,
        "tolerance": "none: identical bits required",
    });
    report["budgets"] = json!({
        "flash_bytes": flash,
        "static_ram_bytes": static_ram,
        "stack_high_water_bytes": summary.stack_high_water,
        "stack_high_water_boot_bytes": summary.stack_high_water_boot,
        "stack_high_water_frames_bytes": summary.stack_high_water_frames,
        "stack_capacity_bytes": summary.stack_capacity,
        "ram_bytes": ram,
        "ram_frames_bytes": static_ram + summary.stack_high_water_frames as u64,
        "ram_boot_bytes": static_ram + summary.stack_high_water_boot as u64,
        "force_eval_instructions": force_eval,
        "force_eval_no_damping_instructions": bench.get("force_eval_no_damping_insns_milli").map(|v| v / 1000.0),
        "frame_instructions_mean": frame_mean,
        "frame_instructions_max": frame_max,
        "frame_instructions_bench": frame_bench,
        "decode_instructions": bench.get("decode_insns"),
        "model_degree": model.degree(),
        "instructions_per_systick_tick": summary.insns_per_tick_milli as f64 / 1000.0,
        "limits": {
            "flash_bytes": budget::FLASH, "ram_bytes": budget::RAM,
            "force_eval_instructions": budget::FORCE_EVAL, "frame_instructions": budget::FRAME,
        },
        "within": within,
        "frame_rate_at_168mhz_hz": 168e6 / frame_max,
    });
    report["panic_symbols"] = json!(panics);

    if let Some(p) = &args.csv {
        write_csv(p, &run.telemetry)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_text(&report);
    }
    Ok(())
}

fn print_text(r: &Value) {
    let f = &r["frames"];
    let a = &r["agreement"];
    let b = &r["budgets"];
    println!(
        "firmware replay of {} (kite: {})",
        r["log"].as_str().unwrap_or(""),
        r["kite"].as_str().unwrap_or("")
    );
    println!(
        "  frames: {} accepted, {} rejected (host: {} / {}), QEMU {:.2} s",
        f["accepted"],
        f["rejected"],
        f["host_accepted"],
        f["host_rejected"],
        r["firmware_seconds"].as_f64().unwrap_or(0.0)
    );
    println!(
        "  host/firmware: {} of {} records bit-identical; core wrench identical on {}",
        a["identical"], a["compared"], a["core_wrench_identical"]
    );
    println!(
        "  flash {} B (<= {}), RAM {} B = static {} + stack {} (<= {}; stack at boot {}, per frame {})",
        b["flash_bytes"],
        budget::FLASH,
        b["ram_bytes"],
        b["static_ram_bytes"],
        b["stack_high_water_bytes"],
        budget::RAM,
        b["stack_high_water_boot_bytes"],
        b["stack_high_water_frames_bytes"]
    );
    println!(
        "  instructions: force eval {:.0} (target {}), frame mean {:.0} / max {:.0} (limit {:.0})",
        b["force_eval_instructions"].as_f64().unwrap_or(f64::NAN),
        budget::FORCE_EVAL,
        b["frame_instructions_mean"].as_f64().unwrap_or(f64::NAN),
        b["frame_instructions_max"].as_f64().unwrap_or(f64::NAN),
        budget::FRAME
    );
    println!("  panic symbols in the ELF: {}", r["panic_symbols"]);
}
