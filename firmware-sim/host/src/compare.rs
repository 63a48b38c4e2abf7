//! Host against firmware, record by record: the sequence number, the
//! timestamp, the reject count and the bits of every computed number must
//! agree. No tolerance: both run the same IEEE-754 `f32` operations, so a
//! single differing bit is a bug (a compiler flag, a fused multiply-add,
//! a target-dependent path).
//!
//! One exception, not a tolerance: any NaN equals any NaN. IEEE 754 leaves
//! the sign and payload of a NaN an operation creates to the hardware
//! (x86 SSE makes `0xFFC0_0000`, the Cortex-M4 `0x7FC0_0000`), so a
//! diverging look-ahead (e.g. a light model under a kite's tether force,
//! `--kite data/plate.omni`) is NaN on both sides with different bits.

use omniad_fw_pipeline::frame::NUMBER_NAMES;
use omniad_fw_pipeline::Telemetry;
use serde::Serialize;
use std::collections::BTreeMap;

/// Bitwise comparison of host and firmware telemetry.
#[derive(Debug, Default, Serialize)]
pub struct Agreement {
    /// Records compared (the shorter side's count).
    pub compared: usize,
    /// Records whose every number has identical bits.
    pub identical: usize,
    /// Largest absolute difference of any number (infinite when one side
    /// is NaN and the other not; JSON `null`).
    pub max_abs_diff: f64,
    /// Per-field count of differing records.
    pub differing_fields: BTreeMap<&'static str, usize>,
    /// Records with a NaN or infinite number (on the firmware's side): they
    /// agree, but the model diverged on them.
    pub non_finite_records: usize,
}

/// The same bits, or both NaN.
fn same(x: f32, y: f32) -> bool {
    x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan())
}

/// Compares record by record.
pub(crate) fn compare(host: &[Telemetry], fw: &[Telemetry]) -> Agreement {
    let mut a = Agreement {
        compared: host.len().min(fw.len()),
        ..Default::default()
    };
    for (h, f) in host.iter().zip(fw) {
        let (hn, fn_) = (h.numbers(), f.numbers());
        let mut identical = h.seq == f.seq && h.time_ms == f.time_ms && h.rejected == f.rejected;
        for ((&x, &y), name) in hn.iter().zip(fn_.iter()).zip(NUMBER_NAMES) {
            if !same(x, y) {
                identical = false;
                *a.differing_fields.entry(name).or_default() += 1;
                let d = (f64::from(x) - f64::from(y)).abs();
                a.max_abs_diff = a
                    .max_abs_diff
                    .max(if d.is_nan() { f64::INFINITY } else { d });
            }
        }
        if identical {
            a.identical += 1;
        }
        if fn_.iter().any(|y| !y.is_finite()) {
            a.non_finite_records += 1;
        }
    }
    a
}

/// The verdict: as many records on both sides (`host` and `fw` counts),
/// the same rejects by kind, and every compared record identical.
pub(crate) fn all_identical(a: &Agreement, host: usize, fw: usize, same_rejects: bool) -> bool {
    a.compared == host && a.compared == fw && a.identical == a.compared && same_rejects
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A plausible record.
    pub(crate) fn record(seq: u32) -> Telemetry {
        Telemetry {
            seq,
            time_ms: 100 * u64::from(seq),
            force: [1.0, -2.0, 300.5],
            torque: [0.25, 0.5, -0.75],
            tether_predicted: 3000.0,
            tether_residual: -12.5,
            eigenvalues: [-3.0, -1.0, 2.0],
            lookahead_attitude: [1.0, 0.0, 0.0, 0.0],
            lookahead_rates: [0.1, 0.2, 0.3],
            lookahead_airspeed: 21.0,
            rejected: 0,
            instructions: 0,
        }
    }

    #[test]
    fn identical_records_agree() {
        let host: Vec<_> = (0..5).map(record).collect();
        let a = compare(&host, &host.clone());
        assert_eq!((a.compared, a.identical), (5, 5));
        assert!(a.differing_fields.is_empty() && a.max_abs_diff == 0.0);
    }

    #[test]
    fn one_flipped_bit_is_a_difference() {
        let host: Vec<_> = (0..5).map(record).collect();
        let mut fw = host.clone();
        fw[3].torque[1] = f32::from_bits(fw[3].torque[1].to_bits() ^ 1);
        fw[4].time_ms += 1;
        let a = compare(&host, &fw);
        assert_eq!((a.compared, a.identical), (5, 3));
        assert_eq!(a.differing_fields.get("torque_y"), Some(&1));
        assert!(a.max_abs_diff > 0.0 && a.max_abs_diff < 1e-6);
    }

    #[test]
    fn nans_agree_whatever_their_bits_but_a_nan_against_a_number_does_not() {
        let host: Vec<_> = (0..3).map(record).collect();
        let mut fw = host.clone();
        let mut host = host;
        host[0].lookahead_rates[0] = f32::from_bits(0xFFC0_0000);
        fw[0].lookahead_rates[0] = f32::from_bits(0x7FC0_0000);
        fw[1].lookahead_airspeed = f32::NAN;
        let a = compare(&host, &fw);
        assert_eq!(a.identical, 2);
        assert_eq!(a.non_finite_records, 2);
        assert_eq!(a.differing_fields.get("look_airspeed"), Some(&1));
        assert_eq!(a.max_abs_diff, f64::INFINITY);
    }
}
