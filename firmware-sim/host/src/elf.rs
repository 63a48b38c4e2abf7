//! What the harness reads from the firmware's 32-bit little-endian ELF:
//! the sizes of its load segments (flash and static RAM budgets), where
//! its sections are (the `.kite` region patched for `--kite`) and its
//! symbol names (the panic-machinery check).

use anyhow::{anyhow, bail, Result};

/// First address of RAM on the mps2-an386 board (see `fw/memory.x`):
/// segments loaded below it live in flash.
const RAM_START: u32 = 0x2000_0000;
/// `PT_LOAD`.
const LOAD: u32 = 1;
/// `SHT_SYMTAB`.
const SYMTAB: u32 = 2;
/// Bytes of one `Elf32_Sym`.
const SYM_SIZE: usize = 16;

/// A section's place in the file.
#[derive(Debug)]
pub(crate) struct Section {
    name: String,
    offset: usize,
    size: usize,
}

/// A `PT_LOAD` program header: where the loader copies it from and to.
#[derive(Debug)]
struct Load {
    /// Physical (load) address.
    paddr: u32,
    /// Virtual (run) address.
    vaddr: u32,
    /// Bytes in the file.
    filesz: u32,
    /// Bytes in memory (`.bss` included).
    memsz: u32,
}

/// Sections, load segments and symbol names of one ELF.
#[derive(Debug, Default)]
pub(crate) struct Elf {
    sections: Vec<Section>,
    loads: Vec<Load>,
    symbols: Vec<String>,
}

pub(crate) fn rd16(b: &[u8], at: usize) -> Result<u16> {
    match b.get(at..at.saturating_add(2)) {
        Some(&[x, y]) => Ok(u16::from_le_bytes([x, y])),
        _ => Err(anyhow!("ELF truncated")),
    }
}

pub(crate) fn rd32(b: &[u8], at: usize) -> Result<u32> {
    match b.get(at..at.saturating_add(4)) {
        Some(&[x, y, z, w]) => Ok(u32::from_le_bytes([x, y, z, w])),
        _ => Err(anyhow!("ELF truncated")),
    }
}

/// The NUL-terminated string at `at` (empty past the end).
fn cstr(b: &[u8], at: usize) -> String {
    let s = b.get(at..).unwrap_or(&[]);
    let end = s.iter().position(|&c| c == 0).unwrap_or(s.len());
    String::from_utf8_lossy(s.get(..end).unwrap_or(&[])).into_owned()
}

impl Elf {
    /// Parses sections, load segments and symbols.
    pub(crate) fn parse(b: &[u8]) -> Result<Self> {
        if b.get(..4) != Some(b"\x7fELF") || b.get(4) != Some(&1) || b.get(5) != Some(&1) {
            bail!("not a 32-bit little-endian ELF");
        }
        let mut elf = Elf {
            loads: loads(b)?,
            ..Elf::default()
        };
        let (shoff, shentsize) = (rd32(b, 32)? as usize, rd16(b, 46)? as usize);
        let (shnum, shstrndx) = (rd16(b, 48)? as usize, rd16(b, 50)? as usize);
        let sh = |i: usize, field: usize| rd32(b, shoff + i * shentsize + field);
        let names_off = sh(shstrndx, 16)? as usize;
        // (kind, offset, size, link) of every section, for the symbol tables.
        let mut raw = Vec::new();
        for i in 0..shnum {
            let name = cstr(b, names_off + sh(i, 0)? as usize);
            let (offset, size) = (sh(i, 16)? as usize, sh(i, 20)? as usize);
            raw.push((sh(i, 4)?, offset, size, sh(i, 24)? as usize));
            elf.sections.push(Section { name, offset, size });
        }
        for &(kind, off, size, link) in &raw {
            if kind != SYMTAB {
                continue;
            }
            let str_off = raw.get(link).map_or(0, |s| s.1);
            for e in (off..off + size).step_by(SYM_SIZE) {
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
    pub(crate) fn flash_bytes(&self) -> u64 {
        let flash = self.loads.iter().filter(|l| l.paddr < RAM_START);
        flash.map(|l| u64::from(l.filesz)).sum()
    }

    /// Static RAM: memory size of segments running from RAM (`.data`,
    /// `.bss`, `.uninit`).
    pub(crate) fn static_ram_bytes(&self) -> u64 {
        let ram = self.loads.iter().filter(|l| l.vaddr >= RAM_START);
        ram.map(|l| u64::from(l.memsz)).sum()
    }

    /// A section by name: (file offset, size).
    pub(crate) fn section(&self, name: &str) -> Option<(usize, usize)> {
        let s = self.sections.iter().find(|s| s.name == name)?;
        Some((s.offset, s.size))
    }

    /// Symbols that belong to Rust's panic machinery (expected: none, the
    /// release firmware cannot link a reachable panic).
    pub(crate) fn panic_symbols(&self) -> Vec<String> {
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

/// The `PT_LOAD` program headers.
fn loads(b: &[u8]) -> Result<Vec<Load>> {
    let phoff = rd32(b, 28)? as usize;
    let (phentsize, phnum) = (rd16(b, 42)? as usize, rd16(b, 44)? as usize);
    let mut loads = Vec::new();
    for i in 0..phnum {
        let p = phoff + i * phentsize;
        if rd32(b, p)? == LOAD {
            loads.push(Load {
                vaddr: rd32(b, p + 8)?,
                paddr: rd32(b, p + 12)?,
                filesz: rd32(b, p + 16)?,
                memsz: rd32(b, p + 20)?,
            });
        }
    }
    Ok(loads)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_what_is_not_a_32_bit_le_elf() {
        assert!(Elf::parse(b"").is_err());
        assert!(Elf::parse(b"\x7fELF\x02\x01").is_err());
        // A valid ident with nothing after it: truncated, not a panic.
        let err = Elf::parse(b"\x7fELF\x01\x01\x01\0").unwrap_err();
        assert!(err.to_string().contains("truncated"), "{err}");
    }

    #[test]
    fn readers_stop_at_the_end() {
        assert_eq!(rd32(&[1, 0, 0, 0], 0).unwrap(), 1);
        assert!(rd32(&[1, 0, 0], 0).is_err());
        assert!(rd16(&[1], usize::MAX).is_err());
        assert_eq!(cstr(b"ab\0cd", 0), "ab");
        assert_eq!(cstr(b"ab", 7), "");
    }
}
