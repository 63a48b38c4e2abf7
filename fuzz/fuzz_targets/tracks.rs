//! Fuzz target `tracks`: see `omniad_fuzz::tracks` (fuzz/src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| omniad_fuzz::tracks(data));
