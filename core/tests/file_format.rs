//! Coefficient file format: round trip, golden decode, corruption.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

#[path = "golden/model.rs"]
mod model;

use nalgebra::{Matrix3, Vector3};
use omniad_core::file::{decode, encode, FileError, MAX_FILE_SIZE};
use omniad_core::{Coefficients, ModelError};
use proptest::prelude::*;

const GOLDEN_V1: &[u8] = include_bytes!("golden/v1.omni");
/// Version 1 with a torque of its own degree (N = 4, N_T = 6).
const GOLDEN_TORQUE6: &[u8] = include_bytes!("golden/v1-torque6.omni");
const GOLDENS: [&[u8]; 2] = [GOLDEN_V1, GOLDEN_TORQUE6];

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
    assert_eq!(m.torque_degree(), 12);
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
fn an_old_file_has_the_torque_at_the_force_degree() {
    let old: Coefficients<f64> = decode(GOLDEN_V1).unwrap();
    assert_eq!((old.degree(), old.torque_degree()), (4, 4));
    assert_eq!(old.torque_coeff_count(), old.coeff_count());
}

#[test]
fn golden_torque_degree_decodes_to_the_generator_model_and_reencodes_identically() {
    let m = model::golden_torque_model();
    let decoded: Coefficients<f64> = decode(GOLDEN_TORQUE6).unwrap();
    assert_eq!((decoded.degree(), decoded.torque_degree()), (4, 6));
    assert_eq!(decoded, m);
    assert_eq!(encoded(&decoded), GOLDEN_TORQUE6);
    // The coefficients above the force's degree are the torque's alone.
    assert_eq!(decoded.beta(2, 48), m.beta(2, 48));
    assert!(decoded.beta(2, 48).unwrap() != 0.0);
    assert_eq!(decoded.alpha(0, 25), None);
    let f32_model: Coefficients<f32> = decode(GOLDEN_TORQUE6).unwrap();
    assert_eq!(
        f32_model.beta(1, 40).unwrap(),
        m.beta(1, 40).unwrap() as f32
    );
}

#[test]
fn round_trip_with_a_torque_degree_of_its_own_is_exact() {
    for (n, nt) in [(8u8, 10u8), (10, 8), (0, 12), (12, 0), (3, 3)] {
        let mut m = model::golden_model().with_degrees(n, nt).unwrap();
        for k in 0..m.torque_coeff_count() {
            m.set_beta(0, k, k as f64 * 0.01 - 0.3).unwrap();
        }
        for k in 0..m.coeff_count() {
            m.set_alpha(2, k, 0.5 - k as f64 * 0.02).unwrap();
        }
        let back: Coefficients<f64> = decode(&encoded(&m)).unwrap();
        assert_eq!(back, m, "N = {n}, N_T = {nt}");
    }
}

/// The payload of `golden` and the offset of its first beta count.
fn first_beta_count(golden: &[u8], alpha_count: usize) -> (Vec<u8>, usize) {
    let payload = golden[14..golden.len() - 4].to_vec();
    let name_len = payload[0] as usize;
    // name, degree, pole, L; then three alpha sets of a 1-byte count
    // (< 128) and f64s.
    let at = 1 + name_len + 1 + 24 + 8 + 3 * (1 + 8 * alpha_count);
    (payload, at)
}

#[test]
fn beta_counts_that_are_no_degree_or_differ_are_rejected() {
    let (payload, at) = first_beta_count(GOLDEN_TORQUE6, 25);
    assert_eq!(payload[at], 49);
    // The second beta set's count differs from the first's.
    let mut p = payload.clone();
    p[at + 1 + 8 * 49] = 36;
    assert_eq!(
        decode::<f64>(&reframe(&p)),
        Err(FileError::BadCount("beta"))
    );
    // A first count that is no (N_T+1)² (48), or beyond the largest (196).
    for bad in [48u8, 0] {
        let mut p = payload.clone();
        p[at] = bad;
        assert_eq!(
            decode::<f64>(&reframe(&p)),
            Err(FileError::BadCount("beta")),
            "count {bad}"
        );
    }
    // An alpha count off the force's degree.
    let mut p = payload;
    p[at - 8 * 25 - 1] = 36;
    assert_eq!(
        decode::<f64>(&reframe(&p)),
        Err(FileError::BadCount("alpha"))
    );
}

#[test]
fn every_truncation_is_an_error() {
    for golden in GOLDENS {
        for len in 0..golden.len() {
            assert!(
                decode::<f64>(&golden[..len]).is_err(),
                "prefix of {len} bytes decoded"
            );
        }
    }
}

#[test]
fn every_single_byte_corruption_is_an_error() {
    for golden in GOLDENS {
        let mut bytes = golden.to_vec();
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
    fn arbitrary_corruptions_of_golden_never_decode(which in 0usize..2, edits in proptest::collection::vec((0usize..4096, 1u8..=255), 1..6)) {
        let golden = GOLDENS[which];
        let mut bytes = golden.to_vec();
        for (i, x) in edits {
            let i = i % bytes.len();
            bytes[i] ^= x;
        }
        // Several edits can in principle cancel out; only then may it decode.
        if bytes != golden {
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
