//! Board support for the omniad firmware on QEMU's mps2-an386
//! (Cortex-M4F): semihosting I/O and exit codes, SysTick instruction
//! counting, stack painting, the embedded coefficient file, and the
//! link-time no-panic guarantee.
#![no_std]

pub mod semihosting;

use omniad_core::file::{HEADER_LEN, MAX_FILE_SIZE};

/// Bytes reserved in flash for the coefficient file.
pub const KITE_CAPACITY: usize = MAX_FILE_SIZE;

const fn pad(src: &[u8]) -> [u8; KITE_CAPACITY] {
    let mut out = [0xFFu8; KITE_CAPACITY];
    let mut i = 0;
    while i < src.len() && i < KITE_CAPACITY {
        out[i] = src[i];
        i += 1;
    }
    out
}

/// The coefficient file, in its own flash section `.kite` (the host
/// harness may overwrite it in the ELF; unused bytes are 0xFF).
#[link_section = ".kite"]
#[used]
#[no_mangle]
pub static OMNIAD_KITE: [u8; KITE_CAPACITY] =
    pad(include_bytes!(concat!(env!("OUT_DIR"), "/kite.omni")));

/// The coefficient file's bytes: the length comes from its header (the
/// whole region when the header is unreadable, so that decoding reports
/// the error). Read through an opaque pointer so that the compiler cannot
/// fold the decoding of the build-time contents.
pub fn kite_file() -> &'static [u8] {
    let region: &'static [u8; KITE_CAPACITY] = core::hint::black_box(&OMNIAD_KITE);
    let region: &'static [u8] = region;
    let len = match region.get(10..HEADER_LEN) {
        Some(&[a, b, c, d]) => u32::from_le_bytes([a, b, c, d]) as usize,
        _ => return region,
    };
    let total = len.saturating_add(HEADER_LEN + 4);
    region.get(..total).unwrap_or(region)
}

/// SysTick as a free-running 24-bit down-counter on the processor clock.
/// Under `qemu -icount shift=0` every instruction advances virtual time by
/// 1 ns; the mps2 SysTick runs at 25 MHz, so one tick is 40 instructions
/// (measured at boot by [`calibrate`], not assumed).
pub mod systick {
    const CSR: *mut u32 = 0xE000_E010 as *mut u32;
    const RVR: *mut u32 = 0xE000_E014 as *mut u32;
    const CVR: *mut u32 = 0xE000_E018 as *mut u32;
    /// Counter mask.
    pub const MASK: u32 = 0x00FF_FFFF;

    /// Starts the counter (no interrupt).
    pub fn start() {
        // SAFETY: architectural SysTick registers, single-threaded.
        unsafe {
            RVR.write_volatile(MASK);
            CVR.write_volatile(0);
            CSR.write_volatile(0b101);
        }
    }
    /// Current value (counts down).
    #[inline(always)]
    pub fn now() -> u32 {
        // SAFETY: as above.
        unsafe { CVR.read_volatile() }
    }
    /// Ticks from `start` to `end` (at most 2^24 - 1).
    #[inline(always)]
    pub fn elapsed(start: u32, end: u32) -> u32 {
        start.wrapping_sub(end) & MASK
    }
}

/// Instructions per SysTick tick, x1000, measured with a loop of known
/// length (2 instructions per iteration).
pub fn calibrate() -> u32 {
    const ITER: u32 = 200_000;
    let t0 = systick::now();
    // SAFETY: a register-only countdown loop.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, {n}, #1",
            "bne 2b",
            n = inout(reg) ITER => _,
            options(nomem, nostack),
        );
    }
    let ticks = systick::elapsed(t0, systick::now()).max(1);
    ((2 * ITER as u64 * 1000) / ticks as u64) as u32
}

/// Converts ticks to instructions with a calibration from [`calibrate`].
pub fn instructions(ticks: u32, insns_per_tick_milli: u32) -> u32 {
    ((ticks as u64 * insns_per_tick_milli as u64 + 500) / 1000).min(u32::MAX as u64) as u32
}

/// Stack painting: fill the free stack with a pattern at boot, find the
/// deepest overwritten word at the end.
pub mod stack {
    const PATTERN: u32 = 0xC0FF_EE11;
    extern "C" {
        static mut __sheap: u32;
        static _stack_start: u32;
    }

    fn bottom() -> usize {
        // SAFETY: linker symbols; only their addresses are used.
        core::ptr::addr_of!(__sheap) as usize
    }
    fn top() -> usize {
        // SAFETY: as above.
        core::ptr::addr_of!(_stack_start) as usize
    }

    /// Bytes between the end of static RAM and the top of the stack.
    pub fn capacity() -> u32 {
        (top() - bottom()) as u32
    }

    /// Paints from the end of static RAM up to 64 bytes below the current
    /// stack pointer. Call first thing in `main`.
    #[inline(never)]
    pub fn paint() {
        let sp: usize;
        // SAFETY: reads SP.
        unsafe { core::arch::asm!("mov {}, sp", out(reg) sp, options(nomem, nostack)) };
        let mut p = (bottom() + 3) & !3;
        let end = sp.saturating_sub(64);
        while p < end {
            // SAFETY: [bottom, sp-64) is unused RAM below the live stack.
            unsafe { (p as *mut u32).write_volatile(PATTERN) };
            p += 4;
        }
    }

    /// Deepest stack use so far, bytes.
    pub fn high_water() -> u32 {
        let mut p = (bottom() + 3) & !3;
        let top = top();
        while p < top {
            // SAFETY: reading RAM inside the stack region.
            if unsafe { (p as *const u32).read_volatile() } != PATTERN {
                break;
            }
            p += 4;
        }
        (top - p) as u32
    }
}

/// No reachable panic: in a release build the panic handler calls a
/// function that does not exist, so any panic path that survives
/// optimisation fails the link ("undefined symbol
/// omniad_firmware_reachable_panic"). Debug builds halt with code 101.
#[cfg(not(debug_assertions))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    extern "C" {
        fn omniad_firmware_reachable_panic() -> !;
    }
    // SAFETY: never linked; reaching this is a link error by design.
    unsafe { omniad_firmware_reachable_panic() }
}

#[cfg(debug_assertions)]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    semihosting::exit(omniad_fw_pipeline::ExitCode::DebugPanic.status())
}

/// Writes `value` in decimal to the console.
pub fn print_u64(value: u64) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    let mut v = value;
    loop {
        i -= 1;
        if let Some(b) = buf.get_mut(i) {
            *b = b'0' + (v % 10) as u8;
        }
        v /= 10;
        if v == 0 || i == 0 {
            break;
        }
    }
    semihosting::console(buf.get(i..).unwrap_or(&[]));
}

/// Prints `key=value\n`.
pub fn print_kv(key: &str, value: u64) {
    semihosting::console(key.as_bytes());
    semihosting::console(b"=");
    print_u64(value);
    semihosting::console(b"\n");
}
