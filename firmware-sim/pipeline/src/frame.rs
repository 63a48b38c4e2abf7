//! Wire format: sensor frames in, telemetry out.
//!
//! Every frame on the wire is `COBS(postcard(payload) ++ crc32_le(postcard(payload))) 0x00`.
//! The CRC (IEEE, the one of the `.omni` format) makes a corrupted frame
//! detectable even when its bytes would still decode; COBS makes the
//! stream self-synchronising: after garbage the next `0x00` starts afresh.

use crate::cobs;
use omniad_core::crc32::crc32;
use serde::{Deserialize, Serialize};

/// Largest encoded frame (COBS block, without the zero), bytes.
pub const MAX_FRAME: usize = 160;

/// One sample of the kite's sensors.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq, Default)]
pub struct SensorFrame {
    /// Timestamp, ms (Unix time in the Kitepower logs).
    pub time_ms: u64,
    /// Attitude: unit quaternion `[w, x, y, z]`, body (FRD) to world (NED).
    pub attitude: [f32; 4],
    /// Body rates p, q, r (FRD), rad/s.
    pub rates: [f32; 3],
    /// Pitot airspeed, m/s.
    pub airspeed: f32,
    /// Angle of attack from the flow vane, rad (sideslip is not measured).
    pub angle_of_attack: f32,
    /// Measured tether force, N.
    pub tether_force: f32,
    /// Depower, fraction 0..1.
    pub depower: f32,
    /// Steering, fraction -1..1.
    pub steering: f32,
}

/// Why a frame was skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reject {
    /// Longer than [`MAX_FRAME`] before its terminating zero.
    Oversize = 0,
    /// COBS, CRC or postcard decoding failed.
    Corrupt = 1,
    /// A NaN or infinite number.
    NonFinite = 2,
    /// A finite number outside its physical range.
    OutOfRange = 3,
}

/// Number of [`Reject`] kinds.
pub const REJECT_KINDS: usize = 4;

/// Limits a sensor frame must respect (inclusive).
pub mod limits {
    /// |quaternion|² must lie in this band (then it is renormalised).
    pub const QUAT_NORM_SQ: (f32, f32) = (0.98, 1.02);
    /// Each body rate, rad/s.
    pub const RATE: f32 = 10.0;
    /// Airspeed, m/s.
    pub const AIRSPEED: (f32, f32) = (0.0, 60.0);
    /// Angle of attack, rad (±90°).
    pub const AOA: f32 = 1.570_796_4;
    /// Tether force, N (the ground load cell reads slightly negative when slack).
    pub const TETHER: (f32, f32) = (-1_000.0, 50_000.0);
    /// Depower fraction.
    pub const DEPOWER: (f32, f32) = (-0.05, 1.05);
    /// Steering fraction.
    pub const STEERING: f32 = 1.05;
}

impl SensorFrame {
    /// Checks finiteness and ranges.
    pub fn validate(&self) -> Result<(), Reject> {
        let numbers = self.attitude.into_iter().chain(self.rates).chain([
            self.airspeed,
            self.angle_of_attack,
            self.tether_force,
            self.depower,
            self.steering,
        ]);
        for x in numbers {
            if !x.is_finite() {
                return Err(Reject::NonFinite);
            }
        }
        let [w, x, y, z] = self.attitude;
        let n2 = w * w + x * x + y * y + z * z;
        let within = |v: f32, (lo, hi): (f32, f32)| v >= lo && v <= hi;
        let ok = within(n2, limits::QUAT_NORM_SQ)
            && self.rates.iter().all(|r| r.abs() <= limits::RATE)
            && within(self.airspeed, limits::AIRSPEED)
            && self.angle_of_attack.abs() <= limits::AOA
            && within(self.tether_force, limits::TETHER)
            && within(self.depower, limits::DEPOWER)
            && self.steering.abs() <= limits::STEERING;
        if ok {
            Ok(())
        } else {
            Err(Reject::OutOfRange)
        }
    }
}

/// One telemetry record: everything the firmware computed for one frame.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq, Default)]
pub struct Telemetry {
    /// Index of this accepted frame (0, 1, ...).
    pub seq: u32,
    /// Input timestamp, ms.
    pub time_ms: u64,
    /// Aerodynamic force, body frame (FRD), N (eq. 5).
    pub force: [f32; 3],
    /// Aerodynamic torque about the centre of mass, body frame, N m (eq. 6).
    pub torque: [f32; 3],
    /// Quasi-steady tether force predicted by the model, N.
    pub tether_predicted: f32,
    /// Predicted minus measured tether force, N.
    pub tether_residual: f32,
    /// Eigenvalues (ascending) of the symmetric part of the aerodynamic
    /// torque Jacobian w.r.t. small body rotations, N m/rad (negative:
    /// restoring).
    pub eigenvalues: [f32; 3],
    /// Look-ahead attitude `[w, x, y, z]` after [`crate::process::LOOKAHEAD_STEPS`] RK4 steps.
    pub lookahead_attitude: [f32; 4],
    /// Look-ahead body rates, rad/s.
    pub lookahead_rates: [f32; 3],
    /// Look-ahead airspeed, m/s.
    pub lookahead_airspeed: f32,
    /// Frames rejected so far.
    pub rejected: u32,
    /// Instructions spent computing this record (firmware: SysTick under
    /// `-icount shift=0`, resolution one SysTick tick; host: 0). Not part
    /// of the host/firmware comparison.
    pub instructions: u32,
}

impl Telemetry {
    /// The computed numbers (everything but `instructions`), for bitwise
    /// comparison; names in [`NUMBER_NAMES`].
    pub fn numbers(&self) -> [f32; 19] {
        let [f0, f1, f2] = self.force;
        let [t0, t1, t2] = self.torque;
        let [e0, e1, e2] = self.eigenvalues;
        let [q0, q1, q2, q3] = self.lookahead_attitude;
        let [r0, r1, r2] = self.lookahead_rates;
        [
            f0,
            f1,
            f2,
            t0,
            t1,
            t2,
            self.tether_predicted,
            self.tether_residual,
            e0,
            e1,
            e2,
            q0,
            q1,
            q2,
            q3,
            r0,
            r1,
            r2,
            self.lookahead_airspeed,
        ]
    }
}

/// Names of [`Telemetry::numbers`].
pub const NUMBER_NAMES: [&str; 19] = [
    "force_x",
    "force_y",
    "force_z",
    "torque_x",
    "torque_y",
    "torque_z",
    "tether_predicted",
    "tether_residual",
    "eig_0",
    "eig_1",
    "eig_2",
    "look_qw",
    "look_qx",
    "look_qy",
    "look_qz",
    "look_p",
    "look_q",
    "look_r",
    "look_airspeed",
];

/// End-of-run record.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq, Default)]
pub struct Summary {
    /// Frames accepted and processed.
    pub accepted: u32,
    /// Frames rejected, by [`Reject`] kind.
    pub rejected: [u32; REJECT_KINDS],
    /// Stack high-water mark over the whole run, bytes (stack painting).
    pub stack_high_water: u32,
    /// Stack high-water mark of boot alone (decoding the coefficient file
    /// and setting up), bytes.
    pub stack_high_water_boot: u32,
    /// Stack high-water mark of frame processing alone (the stack is
    /// painted again after boot), bytes.
    pub stack_high_water_frames: u32,
    /// Stack space available, bytes.
    pub stack_capacity: u32,
    /// Largest per-frame instruction count.
    pub max_frame_instructions: u32,
    /// Sum of per-frame instruction counts.
    pub total_frame_instructions: u64,
    /// Instructions per SysTick tick found by the boot calibration, x1000.
    pub insns_per_tick_milli: u32,
}

/// What the firmware writes.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum Output {
    /// One processed frame.
    Telemetry(Telemetry),
    /// The end of the run.
    Summary(Summary),
}

/// Encodes `value` as one wire frame (including the terminating zero) into
/// `out`; returns the length.
pub fn encode_frame<T: Serialize>(value: &T, out: &mut [u8]) -> Option<usize> {
    let mut raw = [0u8; MAX_FRAME];
    let n = postcard::to_slice(value, &mut raw).ok()?.len();
    let crc = crc32(raw.get(..n)?).to_le_bytes();
    raw.get_mut(n..n + 4)?.copy_from_slice(&crc);
    let m = cobs::encode(raw.get(..n + 4)?, out)?;
    *out.get_mut(m)? = 0;
    Some(m + 1)
}

/// Decodes one COBS block (without its zero) in place.
pub fn decode_block<'a, T: Deserialize<'a>>(block: &'a mut [u8]) -> Result<T, Reject> {
    let n = cobs::decode_in_place(block).ok_or(Reject::Corrupt)?;
    let data: &'a [u8] = block.get(..n).ok_or(Reject::Corrupt)?;
    let body_len = n.checked_sub(4).ok_or(Reject::Corrupt)?;
    let (body, crc) = data.split_at(body_len);
    let mut stored = [0u8; 4];
    stored.copy_from_slice(crc.get(..4).ok_or(Reject::Corrupt)?);
    if crc32(body) != u32::from_le_bytes(stored) {
        return Err(Reject::Corrupt);
    }
    match postcard::take_from_bytes::<T>(body) {
        Ok((v, [])) => Ok(v),
        _ => Err(Reject::Corrupt),
    }
}

/// Splits a byte stream into frames and decodes them.
pub struct Deframer {
    buf: [u8; MAX_FRAME],
    len: usize,
    overflow: bool,
}

impl Default for Deframer {
    fn default() -> Self {
        Self::new()
    }
}

impl Deframer {
    /// An empty deframer.
    pub const fn new() -> Self {
        Self {
            buf: [0; MAX_FRAME],
            len: 0,
            overflow: false,
        }
    }

    /// Feeds one byte; at the end of a frame returns the decoded,
    /// validated sensor frame or why it was rejected. Empty frames (two
    /// zeros in a row) are ignored.
    pub fn push(&mut self, byte: u8) -> Option<Result<SensorFrame, Reject>> {
        if byte != 0 {
            match self.buf.get_mut(self.len) {
                Some(slot) => {
                    *slot = byte;
                    self.len += 1;
                }
                None => self.overflow = true,
            }
            return None;
        }
        let len = core::mem::replace(&mut self.len, 0);
        if core::mem::replace(&mut self.overflow, false) {
            return Some(Err(Reject::Oversize));
        }
        if len == 0 {
            return None;
        }
        let block = self.buf.get_mut(..len)?;
        Some(decode_block::<SensorFrame>(block).and_then(|f| f.validate().map(|()| f)))
    }

    /// At the end of the stream: a partial frame left over counts as corrupt.
    pub fn finish(&mut self) -> Option<Reject> {
        let pending = self.len > 0 || self.overflow;
        self.len = 0;
        self.overflow = false;
        pending.then_some(Reject::Corrupt)
    }
}

/// Counts of rejected frames by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RejectCounts(pub [u32; REJECT_KINDS]);

impl RejectCounts {
    /// Counts one.
    pub fn add(&mut self, r: Reject) {
        if let Some(c) = self.0.get_mut(r as usize) {
            *c = c.saturating_add(1);
        }
    }
    /// All kinds together.
    pub fn total(&self) -> u32 {
        self.0.iter().fold(0u32, |a, &b| a.saturating_add(b))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::indexing_slicing, clippy::unwrap_used)]
    use super::*;

    fn frame() -> SensorFrame {
        SensorFrame {
            time_ms: 1_570_531_585_300,
            attitude: [1.0, 0.0, 0.0, 0.0],
            rates: [0.1, 0.2, -0.3],
            airspeed: 20.0,
            angle_of_attack: 0.15,
            tether_force: 3000.0,
            depower: 0.2,
            steering: -0.3,
        }
    }

    #[test]
    fn frames_round_trip_and_garbage_is_rejected() {
        let mut wire = [0u8; 2 * MAX_FRAME];
        let n = encode_frame(&frame(), &mut wire).unwrap();
        let mut d = Deframer::new();
        let mut got = None;
        for &b in &wire[..n] {
            if let Some(r) = d.push(b) {
                got = Some(r);
            }
        }
        assert_eq!(got, Some(Ok(frame())));
        // Flip each bit of the body: never accepted.
        for i in 0..n - 1 {
            for bit in 0..8 {
                let mut w = wire;
                w[i] ^= 1 << bit;
                let mut d = Deframer::new();
                for &b in &w[..n] {
                    if let Some(Ok(f)) = d.push(b) {
                        assert_ne!(
                            f,
                            frame(),
                            "corruption at byte {i} bit {bit} went unnoticed"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn nan_and_range() {
        let mut f = frame();
        f.airspeed = f32::NAN;
        assert_eq!(f.validate(), Err(Reject::NonFinite));
        let mut f = frame();
        f.airspeed = 100.0;
        assert_eq!(f.validate(), Err(Reject::OutOfRange));
    }
}
