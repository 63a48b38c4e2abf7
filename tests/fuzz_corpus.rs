//! The fuzz targets' bodies (fuzz/src/lib.rs) on stable, over each
//! target's seed corpus (fuzz/corpus/<target>/) and deterministic
//! mutations of it: every truncation and every byte set to 0x00, 0xff and
//! a flipped bit. libFuzzer explores further (`scripts/fuzz.sh`); this
//! keeps the bodies compiling and the seeds passing in CI.

#[path = "../fuzz/src/lib.rs"]
mod bodies;

use std::path::Path;

/// The seeds of `target`: every file of fuzz/corpus/<target>/.
fn seeds(target: &str) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let mut out: Vec<Vec<u8>> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| std::fs::read(e.expect("entry").path()).expect("read seed"))
        .collect();
    out.sort();
    assert!(!out.is_empty(), "{} holds seeds", dir.display());
    out
}

/// Runs `body` on every seed of `target` and its mutations; `stride`
/// thins the per-byte mutations of long seeds.
fn survive(target: &str, stride: usize, body: fn(&[u8])) {
    for seed in seeds(target) {
        body(&seed);
        for n in (0..seed.len()).step_by(stride) {
            body(&seed[..n]);
            let mut m = seed.clone();
            for value in [0x00, 0xff, seed[n] ^ 0x10] {
                m[n] = value;
                body(&m);
            }
        }
    }
}

#[test]
fn coefficient_decoder_survives_its_corpus() {
    survive("coefficients", 1, bodies::coefficients);
}

#[test]
fn track_readers_survive_their_corpus() {
    survive("tracks", 1, bodies::tracks);
    // The stray row of issue 18 is refused, not allocated.
    bodies::tracks(b"frame,marker,u,v\n0,m0,1,2\n4294967295,m0,100,100\n");
}

#[test]
fn kite_reader_survives_its_corpus() {
    survive("kite_spec", 3, bodies::kite_spec);
}

#[test]
fn deframer_survives_its_corpus() {
    survive("deframer", 1, bodies::deframer);
}
