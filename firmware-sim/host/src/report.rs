//! The replay's report, typed: what `--json` prints (by serializing it)
//! and what the text output reads. Field names are the JSON's keys.

use crate::compare::Agreement;
use serde::Serialize;

/// Budgets of issue 6 (one instruction per cycle assumed).
mod budget {
    /// Flash, bytes.
    pub const FLASH: u64 = 128 * 1024;
    /// RAM including the stack, bytes.
    pub const RAM: u64 = 32 * 1024;
    /// Force + torque evaluation at N = 8, instructions (about 15 µs at
    /// 168 MHz).
    pub const FORCE_EVAL: f64 = 2_500.0;
    /// One telemetry frame: 100 Hz on a 168 MHz M4F with 5x headroom,
    /// instructions.
    pub const FRAME: f64 = 168e6 / 100.0 / 5.0;
}

/// One replay: inputs, the firmware's exit, and (when it exited 0) what
/// was measured.
#[derive(Debug, Default, Serialize)]
pub struct Report {
    /// The flight log.
    pub log: String,
    /// The coefficient file, or `(built in)`.
    pub kite: String,
    /// QEMU's exit status (see `omniad_fw_pipeline::ExitCode`).
    pub firmware_exit_code: i32,
    /// What a non-zero exit status means.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub firmware_error: Option<&'static str>,
    /// Wall-clock seconds in QEMU.
    pub firmware_seconds: f64,
    /// Bytes sent to the firmware.
    pub wire_bytes: usize,
    /// Rows read from a CSV log (none for a `.bin` log).
    pub log_rows: Option<usize>,
    /// Present when the firmware exited 0.
    #[serde(flatten)]
    pub measured: Option<Measured>,
}

/// What a complete replay measured.
#[derive(Debug, Default, Serialize)]
pub struct Measured {
    /// Frame counts on both sides.
    pub frames: Frames,
    /// Host against firmware.
    pub agreement: AgreementReport,
    /// Flash, RAM, stack and instruction counts against the budgets.
    pub budgets: Budgets,
    /// Panic-machinery symbols in the ELF (expected: none).
    pub panic_symbols: Vec<String>,
}

/// Frames accepted and rejected.
#[derive(Debug, Default, Serialize)]
pub struct Frames {
    /// Frames the firmware processed.
    pub accepted: u32,
    /// Byte runs the firmware rejected.
    pub rejected: u32,
    /// The firmware's rejects by kind.
    pub rejected_by_kind: RejectedByKind,
    /// Frames the host processed.
    pub host_accepted: usize,
    /// Byte runs the host rejected.
    pub host_rejected: u32,
    /// Telemetry records the firmware wrote.
    pub telemetry_records: usize,
    /// Blocks of telemetry.bin that did not decode.
    pub undecodable_telemetry: usize,
}

/// Rejects by kind (`omniad_fw_pipeline::Reject`).
#[derive(Debug, Default, Serialize)]
pub struct RejectedByKind {
    /// Longer than a frame can be.
    pub oversize: u32,
    /// Bad COBS, CRC or payload.
    pub corrupt: u32,
    /// A NaN or infinite value.
    pub non_finite: u32,
    /// A value outside its sensor's range.
    pub out_of_range: u32,
}

/// Host against firmware, with the verdict.
#[derive(Debug, Default, Serialize)]
pub struct AgreementReport {
    /// Record-by-record comparison.
    #[serde(flatten)]
    pub records: Agreement,
    /// Same record counts, same rejects by kind, every record identical.
    pub all_identical: bool,
    /// Records whose force and torque equal the core's own `f32` path.
    pub core_wrench_identical: usize,
    /// The comparison's tolerance (none).
    pub tolerance: &'static str,
}

/// Budget figures; instruction counts from SysTick under `-icount`.
#[derive(Debug, Default, Serialize)]
pub struct Budgets {
    pub flash_bytes: u64,
    pub static_ram_bytes: u64,
    /// Deepest stack use, boot or frames.
    pub stack_high_water_bytes: u32,
    pub stack_high_water_boot_bytes: u32,
    pub stack_high_water_frames_bytes: u32,
    pub stack_capacity_bytes: u32,
    /// Static RAM + deepest stack.
    pub ram_bytes: u64,
    pub ram_frames_bytes: u64,
    pub ram_boot_bytes: u64,
    /// One force + torque evaluation (bench firmware).
    pub force_eval_instructions: f64,
    pub force_eval_no_damping_instructions: Option<f64>,
    /// Per replayed frame.
    pub frame_instructions_mean: f64,
    pub frame_instructions_max: f64,
    /// Per frame in the bench firmware.
    pub frame_instructions_bench: f64,
    /// Decoding the coefficient file.
    pub decode_instructions: Option<f64>,
    pub model_degree: u8,
    /// The torque's own SH degree N_T.
    pub model_torque_degree: u8,
    pub instructions_per_systick_tick: f64,
    pub limits: Limits,
    pub within: Within,
    pub frame_rate_at_168mhz_hz: f64,
}

/// The budgets themselves ([`budget`]).
#[derive(Debug, Default, Serialize)]
pub struct Limits {
    pub flash_bytes: u64,
    pub ram_bytes: u64,
    pub force_eval_instructions: f64,
    pub frame_instructions: f64,
}

/// Which budgets hold.
#[derive(Debug, Default, Serialize)]
pub struct Within {
    pub flash: bool,
    pub ram: bool,
    pub force_eval: bool,
    pub frame: bool,
}

impl Limits {
    /// Issue 6's budgets.
    pub(crate) const ISSUE_6: Limits = Limits {
        flash_bytes: budget::FLASH,
        ram_bytes: budget::RAM,
        force_eval_instructions: budget::FORCE_EVAL,
        frame_instructions: budget::FRAME,
    };
}

impl Report {
    /// Why this replay is a failure, if it is: the firmware exited
    /// non-zero, or host and firmware disagree. `console` is QEMU's output.
    pub fn failure(&self, console: &str) -> Option<String> {
        if self.firmware_exit_code != 0 {
            let why = self.firmware_error.unwrap_or("unexpected exit");
            return Some(format!(
                "firmware exited with code {} ({why}); console: {}",
                self.firmware_exit_code,
                console.trim()
            ));
        }
        let m = self.measured.as_ref()?;
        let a = &m.agreement;
        if a.all_identical {
            return None;
        }
        let fields: Vec<String> = (a.records.differing_fields.iter())
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        Some(format!(
            "host and firmware disagree: {} of {} records bit-identical \
             (records: firmware {}, host {}; rejects: firmware {}, host {}; \
             differing fields: {}; largest difference {})",
            a.records.identical,
            a.records.compared,
            m.frames.telemetry_records,
            m.frames.host_accepted,
            m.frames.rejected,
            m.frames.host_rejected,
            if fields.is_empty() {
                "none".into()
            } else {
                fields.join(", ")
            },
            a.records.max_abs_diff,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare::tests::record;
    use crate::compare::{all_identical, compare};

    /// A report of a run that exited 0 with `host` and `fw` records.
    fn report(
        host: &[omniad_fw_pipeline::Telemetry],
        fw: &[omniad_fw_pipeline::Telemetry],
    ) -> Report {
        let records = compare(host, fw);
        let all = all_identical(&records, host.len(), fw.len(), true);
        let agreement = AgreementReport {
            records,
            all_identical: all,
            ..Default::default()
        };
        let frames = Frames {
            host_accepted: host.len(),
            telemetry_records: fw.len(),
            ..Default::default()
        };
        Report {
            measured: Some(Measured {
                agreement,
                frames,
                ..Default::default()
            }),
            ..Default::default()
        }
    }

    #[test]
    fn agreement_is_success() {
        let host: Vec<_> = (0..4).map(record).collect();
        assert_eq!(report(&host, &host).failure(""), None);
    }

    #[test]
    fn a_disagreement_is_a_failure_naming_the_fields() {
        let host: Vec<_> = (0..4).map(record).collect();
        let mut fw = host.clone();
        fw[2].eigenvalues[0] += 1.0;
        let why = report(&host, &fw).failure("").expect("a failure");
        assert!(why.contains("disagree") && why.contains("3 of 4"), "{why}");
        assert!(why.contains("differing fields: eig_0 1;"), "{why}");
        // A missing record is a disagreement even if the others agree.
        let why = report(&host, &host[..3]).failure("").expect("a failure");
        assert!(why.contains("firmware 3, host 4"), "{why}");
    }

    #[test]
    fn a_firmware_error_is_a_failure_naming_the_code() {
        let r = Report {
            firmware_exit_code: 13,
            firmware_error: Some("CRC mismatch"),
            ..Default::default()
        };
        let why = r.failure(" bad file\n").expect("a failure");
        assert!(
            why.contains("code 13 (CRC mismatch)") && why.ends_with("bad file"),
            "{why}"
        );
    }
}
