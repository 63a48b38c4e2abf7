//! Fuzz target `deframer`: see `omniad_fuzz::deframer` (fuzz/src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| omniad_fuzz::deframer(data));
