//! Instruction counts (run under `qemu -icount shift=0`): prints
//! `key=value` lines on the console. All counts are averages over many
//! repetitions with the loop overhead subtracted.
#![no_std]
#![no_main]

use core::hint::black_box;
use cortex_m_rt::entry;
use nalgebra::Vector3;
use omniad_firmware::{calibrate, kite_file, print_kv, semihosting, systick};
use omniad_fw_pipeline::{ExitCode, Processor, SensorFrame};

const REPS: u32 = 1000;

#[entry]
fn main() -> ! {
    systick::start();
    let calib = calibrate();
    print_kv("insns_per_tick_milli", calib as u64);

    // Any failure to load the model exits with 10 without naming the
    // error's kind: mapping the kind (`ExitCode::file_error`) moves the
    // measured loops below and changes their counts by ~0.1 %.
    let t0 = systick::now();
    let Ok(mut model) = omniad_core::Coefficients::<f32>::zeros(0, Vector3::z(), 1.0) else {
        semihosting::exit(ExitCode::BadMagic.status())
    };
    let decoded = omniad_core::file::decode_into(kite_file(), &mut model);
    let decode_ticks = systick::elapsed(t0, systick::now());
    if decoded.is_err() {
        semihosting::exit(ExitCode::BadMagic.status())
    }
    let Ok(p) = Processor::new(&model) else {
        semihosting::exit(ExitCode::BadBody.status())
    };
    print_kv("degree", model.degree() as u64);
    print_kv("decode_insns", milli(decode_ticks, calib, 1) / 1000);

    // Directions sweep a cone; rates non-zero so the damping term runs too.
    let dirs = [
        Vector3::new(24.0f32, 0.3, 3.1),
        Vector3::new(18.0, -4.0, 6.0),
        Vector3::new(-3.0, 20.0, 1.0),
        Vector3::new(10.0, 10.0, -10.0),
    ];
    let omega = Vector3::new(0.1f32, -0.2, 0.9);

    // Loop overhead: same loop, black_box only.
    let t0 = systick::now();
    for i in 0..REPS {
        let v = black_box(dirs.get((i & 3) as usize).copied().unwrap_or_default());
        black_box(v);
    }
    let overhead = systick::elapsed(t0, systick::now());

    let t0 = systick::now();
    for i in 0..REPS {
        let v = black_box(dirs.get((i & 3) as usize).copied().unwrap_or_default());
        black_box(p.wrench(&v, &black_box(omega)));
    }
    let ticks = systick::elapsed(t0, systick::now()).saturating_sub(overhead);
    print_kv("force_eval_insns_milli", milli(ticks, calib, REPS));

    let zero = Vector3::zeros();
    let t0 = systick::now();
    for i in 0..REPS {
        let v = black_box(dirs.get((i & 3) as usize).copied().unwrap_or_default());
        black_box(p.wrench(&v, &black_box(zero)));
    }
    let ticks = systick::elapsed(t0, systick::now()).saturating_sub(overhead);
    print_kv(
        "force_eval_no_damping_insns_milli",
        milli(ticks, calib, REPS),
    );

    let frame = SensorFrame {
        time_ms: 0,
        attitude: [0.9, 0.1, 0.3, -0.2],
        rates: [0.1, 0.2, 0.8],
        airspeed: 24.0,
        angle_of_attack: 0.14,
        tether_force: 3500.0,
        depower: 0.2,
        steering: 0.1,
    };
    const FRAMES: u32 = 100;
    let t0 = systick::now();
    for i in 0..FRAMES {
        black_box(p.process(i, 0, &black_box(frame)));
    }
    let ticks = systick::elapsed(t0, systick::now());
    print_kv("frame_insns_milli", milli(ticks, calib, FRAMES));
    semihosting::exit(ExitCode::Ok.status())
}

/// Average instructions per repetition, x1000.
fn milli(ticks: u32, calib_milli: u32, reps: u32) -> u64 {
    ticks as u64 * calib_milli as u64 / reps.max(1) as u64
}
