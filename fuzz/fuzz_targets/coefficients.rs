//! Fuzz target `coefficients`: see `omniad_fuzz::coefficients` (fuzz/src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| omniad_fuzz::coefficients(data));
