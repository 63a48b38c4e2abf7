//! The host's half of the comparison: the same wire bytes through the
//! same deframer and processor (`omniad-fw-pipeline`), compiled for the
//! host, and the core's own `Coefficients::wrench` on the same inputs.

use anyhow::{anyhow, Result};
use omniad_core::Coefficients;
use omniad_fw_pipeline::frame::RejectCounts;
use omniad_fw_pipeline::process::{air_inputs, AIR_DENSITY};
use omniad_fw_pipeline::{Deframer, Processor, SensorFrame, Telemetry};

/// What the host build made of the wire bytes.
pub(crate) struct HostRun {
    /// One record per accepted frame (`instructions` is 0).
    pub telemetry: Vec<Telemetry>,
    /// Rejected byte runs by kind.
    pub rejects: RejectCounts,
    /// The accepted frames.
    pub inputs: Vec<SensorFrame>,
}

/// Replays `wire` through the pipeline on the host.
pub(crate) fn run_host(model: &Coefficients<f32>, wire: &[u8]) -> Result<HostRun> {
    let processor = Processor::new(model).map_err(|e| anyhow!("mass properties: {e}"))?;
    let mut d = Deframer::new();
    let mut run = HostRun {
        telemetry: Vec::new(),
        rejects: RejectCounts::default(),
        inputs: Vec::new(),
    };
    for &b in wire {
        match d.push(b) {
            None => {}
            Some(Err(r)) => run.rejects.add(r),
            Some(Ok(f)) => {
                let seq = run.telemetry.len() as u32;
                let t = processor.process(seq, run.rejects.total(), &f);
                run.telemetry.push(t);
                run.inputs.push(f);
            }
        }
    }
    if let Some(r) = d.finish() {
        run.rejects.add(r);
    }
    Ok(run)
}

/// Records whose force and torque are bit-identical to the core's own
/// `f32` path (`Coefficients::wrench` with the model as given, which
/// the caller sets to the portable path) on the same inputs: the
/// firmware's pipeline adds nothing to the core's evaluation.
pub(crate) fn core_wrench_identical(
    model: &Coefficients<f32>,
    inputs: &[SensorFrame],
    firmware: &[Telemetry],
) -> usize {
    let bits = |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    inputs
        .iter()
        .zip(firmware)
        .filter(|(f, t)| {
            let (v, w) = air_inputs(f);
            let r = model.wrench(&v, &w, AIR_DENSITY);
            bits(r.force.as_slice(), &t.force) && bits(r.torque.as_slice(), &t.torque)
        })
        .count()
}
