//! The model extensions this build evaluates (spin coupling, gravity
//! coupling): their forces, where they enter the dynamics, and their
//! storage in `.omni` files.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

#[path = "golden/model.rs"]
mod model;

use nalgebra::Vector3;
use nalgebra::{Matrix3, UnitQuaternion};
use omniad_core::coefficients::{extension_kind, Extension};
use omniad_core::file::{decode, encode, FileError, MAX_FILE_SIZE};
use omniad_core::gravity_coupling::GravityCoupling;
use omniad_core::rigid_body::{AirForces, Forces};
use omniad_core::spin_coupling::SpinCoupling;
use omniad_core::{Coefficients, ModelError};
use omniad_core::{Environment, State};

fn encoded(m: &Coefficients<f64>) -> Vec<u8> {
    let mut buf = vec![0u8; MAX_FILE_SIZE];
    let n = encode(m, &mut buf).unwrap();
    buf.truncate(n);
    buf
}

fn sample_tensor() -> SpinCoupling<f64> {
    SpinCoupling {
        k: std::array::from_fn(|i| {
            std::array::from_fn(|jk| 0.01 * (i as f64 + 1.0) - 0.003 * jk as f64)
        }),
    }
}

#[test]
fn magnus_tensor_is_half_rho_l_cubed_omega_cross_v() {
    let (v, w) = (Vector3::new(3.0, -1.0, 0.5), Vector3::new(0.2, 7.0, -4.0));
    let f = SpinCoupling::magnus(0.3).force(&v, &w, 1.2, 0.8);
    let expected = w.cross(&v) * (0.5 * 1.2 * 0.8f64.powi(3) * 0.3);
    assert!(
        (f - expected).norm() < 1e-12 * expected.norm(),
        "{f} vs {expected}"
    );
}

#[test]
fn force_is_bilinear_in_omega_and_v() {
    let s = sample_tensor();
    let (v, w) = (Vector3::new(1.0, 2.0, -3.0), Vector3::new(-0.5, 0.25, 2.0));
    let f = s.force(&v, &w, 1.2, 0.5);
    assert!((s.force(&(v * 2.0), &w, 1.2, 0.5) - f * 2.0).norm() < 1e-12);
    assert!((s.force(&v, &(w * -3.0), 1.2, 0.5) + f * 3.0).norm() < 1e-12);
    assert_eq!(s.force(&v, &Vector3::zeros(), 1.2, 0.5), Vector3::zeros());
}

#[test]
fn wrench_adds_the_coupling_force_and_nothing_else() {
    let plain = model::golden_model();
    let mut coupled = plain.clone();
    coupled.set_spin_coupling(Some(sample_tensor())).unwrap();
    let (v, w) = (Vector3::new(2.0, -1.0, 4.0), Vector3::new(3.0, 0.5, -1.0));
    let a = plain.wrench(&v, &w, 1.2);
    let b = coupled.wrench(&v, &w, 1.2);
    let k = coupled.spin_coupling().unwrap();
    let extra = k.force(&v, &w, 1.2, coupled.reference_length());
    assert!(extra.norm() > 1e-3);
    assert!((b.force - a.force - extra).norm() < 1e-12);
    assert_eq!(a.torque, b.torque);
    // Removing it restores the plain model exactly.
    coupled.set_spin_coupling(None).unwrap();
    assert_eq!(coupled.wrench(&v, &w, 1.2), a);
}

#[test]
fn coupling_survives_the_file_and_the_cast_to_f32() {
    let mut m = model::golden_model();
    m.set_spin_coupling(Some(sample_tensor())).unwrap();
    let back: Coefficients<f64> = decode(&encoded(&m)).unwrap();
    assert_eq!(back, m);
    let k = back.spin_coupling().unwrap();
    for (a, b) in k.k.iter().flatten().zip(sample_tensor().k.iter().flatten()) {
        // Stored as f32.
        assert!((a - b).abs() <= 1e-7 * b.abs().max(1e-3));
    }
    let single: Coefficients<f32> = decode(&encoded(&m)).unwrap();
    let (v, w) = (
        Vector3::new(2.0f32, -1.0, 4.0),
        Vector3::new(3.0f32, 0.5, -1.0),
    );
    let f32_force = single.spin_coupling().unwrap().force(&v, &w, 1.2, 1.0);
    let f64_force = k.force(&v.cast(), &w.cast(), 1.2, 1.0);
    assert!((f32_force.cast::<f64>() - f64_force).norm() < 1e-5 * f64_force.norm());
}

#[test]
fn malformed_or_duplicate_couplings_are_errors_and_unknown_versions_are_kept() {
    let mut m = model::golden_model();
    let mut short = sample_tensor().to_extension().unwrap();
    short.data.truncate(100);
    assert_eq!(
        m.add_extension(short.clone()),
        Err(ModelError::OutOfRange("spin_coupling payload"))
    );
    let mut nan = sample_tensor().to_extension().unwrap();
    nan.data[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        m.add_extension(nan),
        Err(ModelError::NonFinite("spin_coupling"))
    );
    m.set_spin_coupling(Some(sample_tensor())).unwrap();
    assert_eq!(
        m.add_extension(sample_tensor().to_extension().unwrap()),
        Err(ModelError::DuplicateExtension(
            extension_kind::SPIN_COUPLING
        ))
    );
    // A later payload version is kept, written back, and not evaluated.
    let mut plain = model::golden_model();
    let future = Extension {
        version: 2,
        ..short
    };
    plain.add_extension(future.clone()).unwrap();
    assert!(plain.spin_coupling().is_none());
    let back: Coefficients<f64> = decode(&encoded(&plain)).unwrap();
    assert!(back.extensions().contains(&future));
    assert!(back.spin_coupling().is_none());
}

#[test]
fn a_file_with_a_malformed_coupling_is_rejected_naming_it() {
    // Write a valid file with an unknown-version payload of the wrong
    // size, then patch its version byte to 1 and fix the CRC.
    let mut m = model::golden_model();
    let mut ext = sample_tensor().to_extension().unwrap();
    ext.data.truncate(100);
    ext.version = 9;
    m.add_extension(ext).unwrap();
    let mut bytes = encoded(&m);
    // The extension header (kind u16 varint 3, version 9, length 100) is
    // the only place the byte sequence [3, 9, 100] occurs.
    let at = bytes
        .windows(3)
        .rposition(|w| w == [3, 9, 100])
        .expect("extension header");
    bytes[at + 1] = 1;
    let body = bytes.len() - 4;
    let crc = omniad_core::crc32::crc32(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    let err = decode::<f64>(&bytes).unwrap_err();
    assert_eq!(
        err,
        FileError::from(ModelError::OutOfRange("spin_coupling payload"))
    );
}

#[test]
fn buoyancy_is_minus_rho_volume_gravity() {
    let g_body = Vector3::new(1.0, -2.0, -9.5);
    let b = GravityCoupling::buoyancy(2.0e-3, 0.6);
    let f = b.force(&g_body, 1.2, 0.6);
    let expected = -g_body * (1.2 * 2.0e-3);
    assert!((f - expected).norm() < 1e-12, "{f} vs {expected}");
}

#[test]
fn air_forces_add_the_gravity_coupling_at_the_body_attitude() {
    let mut m = model::golden_model();
    let g = GravityCoupling {
        g: Matrix3::new(0.01, 0.002, 0.0, -0.003, 0.02, 0.001, 0.0, 0.004, -0.03),
    };
    m.set_gravity_coupling(Some(g)).unwrap();
    let environment = Environment {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        air_density: 1.2,
        wind: Vector3::zeros(),
    };
    let state = State {
        position: Vector3::zeros(),
        orientation: UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1),
        velocity: Vector3::new(1.0, 2.0, -3.0),
        angular_velocity: Vector3::new(0.5, 0.0, -1.0),
    };
    let w = AirForces {
        model: &m,
        environment,
    }
    .wrench(0.0, &state);
    let v_body = state.orientation.inverse_transform_vector(&state.velocity);
    let plain = m.wrench(&v_body, &state.angular_velocity, 1.2);
    let g_body = state
        .orientation
        .inverse_transform_vector(&environment.gravity);
    // The model holds G rounded to f32 (the payload).
    let extra = m
        .gravity_coupling()
        .unwrap()
        .force(&g_body, 1.2, m.reference_length());
    assert!(extra.norm() > 1e-3);
    let scale = 1.0 + plain.force.norm();
    assert!(
        (w.force - plain.force - extra).norm() < 1e-12 * scale,
        "{} vs {}",
        w.force - plain.force,
        extra
    );
    assert_eq!(w.torque, plain.torque);
}

#[test]
fn both_couplings_survive_the_file_and_malformed_gravity_payloads_are_errors() {
    let mut m = model::golden_model();
    m.set_spin_coupling(Some(sample_tensor())).unwrap();
    let g = GravityCoupling::buoyancy(1.0e-3, m.reference_length());
    m.set_gravity_coupling(Some(g)).unwrap();
    let back: Coefficients<f64> = decode(&encoded(&m)).unwrap();
    assert_eq!(back, m);
    let stored = back.gravity_coupling().unwrap();
    assert!((stored.g - g.g).abs().max() <= 1e-7 * g.g.abs().max());
    let mut short = g.to_extension().unwrap();
    short.data.truncate(32);
    let mut plain = model::golden_model();
    assert_eq!(
        plain.add_extension(short),
        Err(ModelError::OutOfRange("gravity_coupling payload"))
    );
    assert_eq!(
        m.add_extension(g.to_extension().unwrap()),
        Err(ModelError::DuplicateExtension(
            extension_kind::GRAVITY_COUPLING
        ))
    );
    m.set_gravity_coupling(None).unwrap();
    assert!(m.gravity_coupling().is_none());
    assert!(m.spin_coupling().is_some());
}
