//! Fuzz target `kite_spec`: see `omniad_fuzz::kite_spec` (fuzz/src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| omniad_fuzz::kite_spec(data));
