//! The coefficient file in the firmware's flash: the `.kite` section that
//! `fw/src/lib.rs` reserves (filled with 0xFF after the file), read to
//! find the built-in model and overwritten in a copy of the ELF for
//! `--kite`, so that one firmware build runs any model.

use crate::elf::{rd32, Elf};
use anyhow::{anyhow, bail, Result};
use omniad_core::file::HEADER_LEN;

/// Offset of the payload length in the coefficient file's header.
const LENGTH_AT: usize = 10;
/// Bytes of the CRC after the payload.
const CRC_LEN: usize = 4;

/// The `.kite` section's bytes in `elf_bytes`.
fn kite_region<'a>(elf_bytes: &'a [u8], elf: &Elf) -> Result<(usize, &'a [u8])> {
    let (off, size) = elf
        .section(".kite")
        .ok_or_else(|| anyhow!("no .kite section in the firmware"))?;
    let region = elf_bytes
        .get(off..off.saturating_add(size))
        .ok_or_else(|| anyhow!(".kite outside the ELF"))?;
    Ok((off, region))
}

/// The coefficient file embedded in an ELF's `.kite` section (its length
/// from its header; the whole region when the header is unreadable).
pub(crate) fn embedded_kite(elf_bytes: &[u8], elf: &Elf) -> Result<Vec<u8>> {
    let (_, region) = kite_region(elf_bytes, elf)?;
    let len = rd32(region, LENGTH_AT).unwrap_or(0) as usize + HEADER_LEN + CRC_LEN;
    Ok(region
        .get(..len.min(region.len()))
        .unwrap_or(region)
        .to_vec())
}

/// A copy of the ELF with `kite` in its `.kite` section (padded with 0xFF,
/// as the firmware's build pads it).
pub(crate) fn patch_kite(elf_bytes: &[u8], elf: &Elf, kite: &[u8]) -> Result<Vec<u8>> {
    let (off, region) = kite_region(elf_bytes, elf)?;
    let size = region.len();
    if kite.len() > size {
        bail!(
            "coefficient file is {} bytes, the firmware reserves {size}",
            kite.len()
        );
    }
    let mut out = elf_bytes.to_vec();
    if let Some(region) = out.get_mut(off..off + size) {
        region.fill(0xFF);
        if let Some(head) = region.get_mut(..kite.len()) {
            head.copy_from_slice(kite);
        }
    }
    Ok(out)
}
