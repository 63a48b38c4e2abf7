//! Minimal ARM semihosting (QEMU `-semihosting-config enable=on,target=native`).

const SYS_OPEN: usize = 0x01;
const SYS_CLOSE: usize = 0x02;
const SYS_WRITE: usize = 0x05;
const SYS_READ: usize = 0x06;
const SYS_EXIT_EXTENDED: usize = 0x20;
const ADP_STOPPED_APPLICATION_EXIT: usize = 0x20026;

/// Open modes (ISO C fopen modes as numbered by the semihosting spec).
pub mod mode {
    /// "rb"
    pub const READ_BINARY: usize = 1;
    /// "w"
    pub const WRITE_TEXT: usize = 4;
    /// "wb"
    pub const WRITE_BINARY: usize = 5;
}

#[inline(always)]
fn call(op: usize, arg: usize) -> isize {
    let r: isize;
    // SAFETY: `bkpt 0xab` is the semihosting trap; r1 points to a
    // parameter block that lives for the call.
    unsafe {
        core::arch::asm!("bkpt #0xab", inout("r0") op => r, in("r1") arg, options(nostack));
    }
    r
}

/// Opens a host file; `name` must end with a NUL byte.
pub fn open(name: &[u8], mode: usize) -> Option<usize> {
    if name.last() != Some(&0) {
        return None;
    }
    let block = [name.as_ptr() as usize, mode, name.len() - 1];
    let h = call(SYS_OPEN, block.as_ptr() as usize);
    (h >= 0).then_some(h as usize)
}

/// Closes a handle.
pub fn close(handle: usize) {
    let block = [handle];
    call(SYS_CLOSE, block.as_ptr() as usize);
}

/// Reads up to `buf.len()` bytes; returns how many were read (0 at the end).
pub fn read(handle: usize, buf: &mut [u8]) -> usize {
    let block = [handle, buf.as_mut_ptr() as usize, buf.len()];
    let not_read = call(SYS_READ, block.as_ptr() as usize);
    if not_read < 0 {
        return 0;
    }
    buf.len().saturating_sub(not_read as usize)
}

/// Writes all of `data`; false on failure.
pub fn write(handle: usize, data: &[u8]) -> bool {
    let block = [handle, data.as_ptr() as usize, data.len()];
    call(SYS_WRITE, block.as_ptr() as usize) == 0
}

static mut CONSOLE: usize = usize::MAX;

/// Writes to QEMU's stdout (`:tt`).
pub fn console(data: &[u8]) {
    // SAFETY: single-threaded firmware, no interrupts use CONSOLE.
    let h = unsafe { CONSOLE };
    let h = if h == usize::MAX {
        let Some(h) = open(b":tt\0", mode::WRITE_TEXT) else {
            return;
        };
        // SAFETY: as above.
        unsafe { CONSOLE = h };
        h
    } else {
        h
    };
    write(h, data);
}

/// Ends the QEMU process with `code` as its exit status.
pub fn exit(code: u32) -> ! {
    let block = [ADP_STOPPED_APPLICATION_EXIT, code as usize];
    loop {
        call(SYS_EXIT_EXTENDED, block.as_ptr() as usize);
    }
}
