//! The firmware: decode the coefficient file embedded in flash, then for
//! every sensor frame read from `frames.bin` (semihosting) compute the
//! model's wrench, tether-force residual, stability eigenvalues and RK4
//! look-ahead and write one telemetry frame to `telemetry.bin`; finish
//! with a summary frame (counts, stack high-water mark, instructions).
//!
//! Exit status: `omniad_fw_pipeline::ExitCode` (0 ok, 2 no input, 3 output
//! error, 10..19 coefficient file error (10 + kind), 20 bad mass properties).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use omniad_firmware::semihosting::{self, mode};
use omniad_firmware::{calibrate, instructions, kite_file, stack, systick};
use omniad_fw_pipeline::frame::{encode_frame, Output, RejectCounts, Summary, MAX_FRAME};
use omniad_fw_pipeline::{Deframer, ExitCode, Processor};

#[entry]
fn main() -> ! {
    stack::paint();
    systick::start();
    let calib = calibrate();
    let code = run(calib);
    semihosting::exit(code.status())
}

#[inline(never)]
fn run(calib: u32) -> ExitCode {
    // Decoded in place: exactly one copy of the model on the stack.
    let Ok(mut model) = omniad_core::Coefficients::<f32>::zeros(0, nalgebra::Vector3::z(), 1.0)
    else {
        return ExitCode::file_error(&omniad_core::file::FileError::BufferTooSmall);
    };
    if let Err(e) = omniad_core::file::decode_into(kite_file(), &mut model) {
        semihosting::console(b"omniad-firmware: invalid coefficient file in flash\n");
        return ExitCode::file_error(&e);
    }
    frames(&model, calib)
}

#[inline(never)]
fn frames(model: &omniad_core::Coefficients<f32>, calib: u32) -> ExitCode {
    let Ok(processor) = Processor::new(model) else {
        semihosting::console(b"omniad-firmware: invalid mass properties\n");
        return ExitCode::BadBody;
    };
    let Some(input) = semihosting::open(b"frames.bin\0", mode::READ_BINARY) else {
        semihosting::console(b"omniad-firmware: cannot open frames.bin\n");
        return ExitCode::NoInput;
    };
    let Some(output) = semihosting::open(b"telemetry.bin\0", mode::WRITE_BINARY) else {
        return ExitCode::Output;
    };

    // Boot's stack peak, then paint again to measure frame processing alone.
    let boot_peak = stack::high_water();
    stack::paint();

    let mut deframer = Deframer::new();
    let mut rejects = RejectCounts::default();
    let mut summary = Summary {
        insns_per_tick_milli: calib,
        ..Summary::default()
    };
    let mut chunk = [0u8; 256];
    let mut out = [0u8; 2 * MAX_FRAME];
    loop {
        let n = semihosting::read(input, &mut chunk);
        if n == 0 {
            break;
        }
        for &byte in chunk.get(..n).unwrap_or(&[]) {
            match deframer.push(byte) {
                None => {}
                Some(Err(reason)) => rejects.add(reason),
                Some(Ok(frame)) => {
                    let t0 = systick::now();
                    let mut telemetry =
                        processor.process(summary.accepted, rejects.total(), &frame);
                    let ticks = systick::elapsed(t0, systick::now());
                    telemetry.instructions = instructions(ticks, calib);
                    summary.max_frame_instructions =
                        summary.max_frame_instructions.max(telemetry.instructions);
                    summary.total_frame_instructions += telemetry.instructions as u64;
                    summary.accepted += 1;
                    let Some(len) = encode_frame(&Output::Telemetry(telemetry), &mut out) else {
                        return ExitCode::Output;
                    };
                    if !semihosting::write(output, out.get(..len).unwrap_or(&[])) {
                        return ExitCode::Output;
                    }
                }
            }
        }
    }
    if let Some(reason) = deframer.finish() {
        rejects.add(reason);
    }
    summary.rejected = rejects.0;
    summary.stack_high_water_frames = stack::high_water();
    summary.stack_high_water_boot = boot_peak;
    summary.stack_high_water = boot_peak.max(summary.stack_high_water_frames);
    summary.stack_capacity = stack::capacity();
    let Some(len) = encode_frame(&Output::Summary(summary), &mut out) else {
        return ExitCode::Output;
    };
    let ok = semihosting::write(output, out.get(..len).unwrap_or(&[]));
    semihosting::close(output);
    semihosting::close(input);
    if ok {
        ExitCode::Ok
    } else {
        ExitCode::Output
    }
}
