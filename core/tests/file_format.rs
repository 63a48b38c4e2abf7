//! Coefficient file format: round trip, golden decode, corruption.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

#[path = "golden/model.rs"]
mod model;

use nalgebra::{Matrix3, Vector3};
use omniad_core::file::{decode, encode, FileError, MAX_FILE_SIZE};
use omniad_core::{Coefficients, ModelError};
use proptest::prelude::*;

const GOLDEN_V1: &[u8] = include_bytes!("golden/v1.omni");

fn encoded(m: &Coefficients<f64>) -> Vec<u8> {
    let mut buf = vec![0u8; MAX_FILE_SIZE];
    let n = encode(m, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

#[test]
fn round_trip_is_exact_in_f64() {
    let m = model::golden_model();
    let back: Coefficients<f64> = decode(&encoded(&m)).unwrap();
    assert_eq!(back, m);
}

#[test]
fn largest_model_fits_the_advertised_buffer() {
    let mut m = model::golden_model().with_degree(12).unwrap();
    m.set_name(&"n".repeat(64)).unwrap();
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            m.set_alpha(i, k, -1.234_567_890_123e-7).unwrap();
            m.set_beta(i, k, 9.876e5).unwrap();
        }
    }
    while m.extensions().len() < omniad_core::coefficients::MAX_EXTENSIONS {
        let mut e = m.extensions()[0].clone();
        while e.data.push(0xFF).is_ok() {}
        m.add_extension(e).unwrap();
    }
    let bytes = encoded(&m);
    assert!(bytes.len() <= MAX_FILE_SIZE);
    assert_eq!(decode::<f64>(&bytes).unwrap(), m);
}

#[test]
fn golden_v1_decodes_to_the_generator_model_and_reencodes_identically() {
    let m = model::golden_model();
    let decoded: Coefficients<f64> = decode(GOLDEN_V1).unwrap();
    assert_eq!(decoded, m);
    assert_eq!(encoded(&decoded), GOLDEN_V1);
    // f32 readers get the same model rounded.
    let f32_model: Coefficients<f32> = decode(GOLDEN_V1).unwrap();
    assert_eq!(
        f32_model.alpha(1, 7).unwrap(),
        m.alpha(1, 7).unwrap() as f32
    );
}

#[test]
fn every_truncation_is_an_error() {
    for len in 0..GOLDEN_V1.len() {
        assert!(
            decode::<f64>(&GOLDEN_V1[..len]).is_err(),
            "prefix of {len} bytes decoded"
        );
    }
}

#[test]
fn every_single_byte_corruption_is_an_error() {
    let mut bytes = GOLDEN_V1.to_vec();
    for i in 0..bytes.len() {
        let orig = bytes[i];
        for flip in [0x01u8, 0x80, 0xFF] {
            bytes[i] = orig ^ flip;
            assert!(
                decode::<f64>(&bytes).is_err(),
                "corrupting byte {i} with {flip:#x} decoded"
            );
        }
        bytes[i] = orig;
    }
}

#[test]
fn specific_errors_are_reported() {
    let mut bad_magic = GOLDEN_V1.to_vec();
    bad_magic[1] = b'X';
    assert_eq!(decode::<f64>(&bad_magic), Err(FileError::BadMagic));
    let mut trailing = GOLDEN_V1.to_vec();
    trailing.push(0);
    assert_eq!(decode::<f64>(&trailing), Err(FileError::TrailingBytes(1)));
    let mut version = GOLDEN_V1.to_vec();
    version[8] = 9;
    assert_eq!(decode::<f64>(&version), Err(FileError::UnknownVersion(9)));
    assert_eq!(decode::<f64>(&GOLDEN_V1[..20]), Err(FileError::Truncated));
    assert!(matches!(decode::<f64>(&[]), Err(FileError::Truncated)));
}

/// Builds a file with valid framing and CRC around an edited payload.
fn reframe(payload: &[u8]) -> Vec<u8> {
    let mut out = GOLDEN_V1[..10].to_vec();
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(payload);
    let crc = omniad_core::crc32::crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

#[test]
fn semantic_errors_survive_a_valid_crc() {
    let payload = &GOLDEN_V1[14..GOLDEN_V1.len() - 4];
    // Degree byte follows the name (1 length byte + 15 chars).
    let name_len = payload[0] as usize;
    let mut p = payload.to_vec();
    p[1 + name_len] = 13;
    assert_eq!(
        decode::<f64>(&reframe(&p)),
        Err(FileError::Model(ModelError::DegreeTooHigh(13)))
    );
    // A NaN in the pole (first f64 after the degree).
    let mut p = payload.to_vec();
    let at = 2 + name_len;
    p[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    assert_eq!(
        decode::<f64>(&reframe(&p)),
        Err(FileError::Model(ModelError::NonFinite("pole")))
    );
    // Extra payload bytes.
    let mut p = payload.to_vec();
    p.push(0);
    assert_eq!(decode::<f64>(&reframe(&p)), Err(FileError::PayloadLength));
}

#[test]
fn invalid_damping_is_rejected_at_construction() {
    let mut m = Coefficients::<f64>::zeros(2, Vector3::z(), 1.0).unwrap();
    let indefinite = Matrix3::new(1.0, 0.0, 0.0, 0.0, -0.1, 0.0, 0.0, 0.0, 1.0);
    assert_eq!(
        m.set_damping(&indefinite),
        Err(ModelError::DampingNotPositiveSemidefinite)
    );
    assert_eq!(m.set_alpha(0, 9, 1.0), Err(ModelError::OutOfRange("alpha")));
    assert_eq!(
        m.set_alpha(0, 0, f64::NAN),
        Err(ModelError::NonFinite("alpha"))
    );
    assert!(Coefficients::<f64>::zeros(13, Vector3::z(), 1.0).is_err());
    assert!(Coefficients::<f64>::zeros(2, Vector3::zeros(), 1.0).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let _ = decode::<f32>(&bytes);
        let _ = decode::<f64>(&bytes);
    }

    #[test]
    fn arbitrary_corruptions_of_golden_never_decode(edits in proptest::collection::vec((0usize..4096, 1u8..=255), 1..6)) {
        let mut bytes = GOLDEN_V1.to_vec();
        for (i, x) in edits {
            let i = i % bytes.len();
            bytes[i] ^= x;
        }
        // Several edits can in principle cancel out; only then may it decode.
        if bytes != GOLDEN_V1 {
            prop_assert!(decode::<f64>(&bytes).is_err());
        }
    }
}

#[test]
fn decode_into_reuses_storage_without_leftovers_and_resets_on_error() {
    let mut out = model::golden_model().with_degree(12).unwrap();
    out.provenance.coverage.clear();
    let small = {
        let mut m = Coefficients::<f64>::zeros(1, Vector3::x(), 2.0).unwrap();
        m.set_alpha(0, 3, 0.5).unwrap();
        m
    };
    omniad_core::file::decode_into(&encoded(&small), &mut out).unwrap();
    assert_eq!(out, small);
    let mut corrupt = GOLDEN_V1.to_vec();
    corrupt[100] ^= 1;
    assert!(omniad_core::file::decode_into(&corrupt, &mut out).is_err());
    assert_eq!(out, Coefficients::zeros(0, Vector3::z(), 1.0).unwrap());
}
