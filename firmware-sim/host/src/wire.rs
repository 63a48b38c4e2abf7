//! Sensor frames on the wire, as the firmware reads them from
//! `frames.bin`, optionally with corrupted runs between frames so that a
//! replay exercises the deframer's reject counting.

use anyhow::{anyhow, Result};
use omniad_fw_pipeline::frame::{self, MAX_FRAME};
use omniad_fw_pipeline::SensorFrame;

/// xorshift64: deterministic garbage, the same on every run.
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
pub(crate) fn wire_bytes(frames: &[SensorFrame], garbage: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let every = frames
        .len()
        .checked_div(garbage)
        .map_or(usize::MAX, |n| n.max(1));
    let mut injected = 0;
    let mut buf = [0u8; 2 * MAX_FRAME];
    for (i, f) in frames.iter().enumerate() {
        let n = frame::encode_frame(f, &mut buf).ok_or_else(|| anyhow!("frame does not encode"))?;
        let encoded = buf.get(..n).unwrap_or(&[]);
        if injected < garbage && i % every == every / 2 {
            garbage_run(injected, encoded, &mut rng, &mut out);
            injected += 1;
        }
        out.extend_from_slice(encoded);
    }
    Ok(out)
}

/// The `k`-th corrupted run, placed before the frame `encoded`.
fn garbage_run(k: usize, encoded: &[u8], rng: &mut Rng, out: &mut Vec<u8>) {
    match k % 4 {
        0 => {
            let len = 1 + (rng.next() % 40) as usize;
            out.extend((0..len).map(|_| (rng.next() % 255) as u8 + 1));
            out.push(0);
        }
        1 => {
            out.extend(std::iter::repeat_n(0x55u8, MAX_FRAME + 10));
            out.push(0);
        }
        2 => {
            let mut bad = encoded.to_vec();
            let at = (rng.next() as usize) % (encoded.len().max(2) - 1);
            let bit = 1u8 << (rng.next() % 8);
            if let Some(b) = bad.get_mut(at) {
                *b ^= bit;
                if *b == 0 {
                    *b = 0xA5;
                }
            }
            out.extend_from_slice(&bad);
        }
        _ => {
            out.extend_from_slice(encoded.get(..encoded.len() / 2).unwrap_or(&[]));
            out.push(0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use omniad_fw_pipeline::frame::RejectCounts;
    use omniad_fw_pipeline::Deframer;

    fn frame(i: u64) -> SensorFrame {
        SensorFrame {
            time_ms: i * 100,
            attitude: [1.0, 0.0, 0.0, 0.0],
            rates: [0.1, 0.0, 0.0],
            airspeed: 20.0,
            angle_of_attack: 0.1,
            tether_force: 3000.0,
            depower: 0.2,
            steering: 0.0,
        }
    }

    #[test]
    fn every_frame_survives_and_every_garbage_run_is_rejected() {
        let frames: Vec<_> = (0..40).map(frame).collect();
        let wire = wire_bytes(&frames, 8).unwrap();
        let (mut d, mut rejects, mut ok) = (Deframer::new(), RejectCounts::default(), 0);
        for &b in &wire {
            match d.push(b) {
                Some(Ok(_)) => ok += 1,
                Some(Err(r)) => rejects.add(r),
                None => {}
            }
        }
        assert_eq!(ok, 40);
        assert!(rejects.total() >= 8, "{:?}", rejects.0);
        assert_eq!(wire_bytes(&frames, 8).unwrap(), wire, "deterministic");
    }
}
