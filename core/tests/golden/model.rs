//! The deterministic model stored in the golden files. Shared by the
//! generator (`examples/make_golden.rs`) and the golden tests.

use nalgebra::{Matrix3, Vector3};
use omniad_core::coefficients::{extension_kind, Extension, MassProperties, COVERAGE_CELLS};
use omniad_core::Coefficients;

/// A degree-4 model exercising every field of format version 1.
pub fn golden_model() -> Coefficients<f64> {
    let pole = Vector3::new(0.0, 0.6, 0.8);
    let mut m = Coefficients::zeros(4, pole, 0.5834).expect("valid");
    m.set_name("golden plate v1").expect("fits");
    for k in 0..m.coeff_count() {
        for i in 0..3 {
            let v = ((k * 31 + i * 17) % 23) as f64 / 23.0 - 0.5;
            m.set_alpha(i, k, v).expect("in range");
            m.set_beta(i, k, v * 0.125).expect("in range");
        }
    }
    let d = Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.01, 0.0005, 0.0, 0.0005, 0.005);
    m.set_damping(&d).expect("psd");
    m.body = Some(MassProperties {
        mass: 0.048,
        inertia: [1.0e-3, 3.6e-4, 1.36e-3, 0.0, 0.0, 0.0],
    });
    m.provenance.method = "fit-lsq".try_into().expect("fits");
    m.provenance.source = "golden generator, core/examples/make_golden.rs"
        .try_into()
        .expect("fits");
    m.provenance.frames_used = 1234;
    m.provenance.frames_dropped = 56;
    for r in [0.31, 0.12, 0.09] {
        m.provenance.force_residuals.push(r).expect("fits");
        m.provenance.torque_residuals.push(r / 10.0).expect("fits");
    }
    for c in 0..COVERAGE_CELLS {
        m.provenance.coverage.push((c % 37) as u16).expect("fits");
    }
    let mut ext = Extension {
        kind: extension_kind::ADDED_MASS,
        version: 1,
        data: heapless::Vec::new(),
    };
    for b in [1u8, 2, 3, 250] {
        ext.data.push(b).expect("fits");
    }
    m.add_extension(ext).expect("fits");
    m
}

/// [`golden_model`] with a torque of its own degree, 6 (the force keeps
/// 4): beta above degree 4 filled too.
#[allow(dead_code)] // not every includer uses it
pub fn golden_torque_model() -> Coefficients<f64> {
    let mut m = golden_model().with_torque_degree(6).expect("valid");
    m.set_name("golden N_T = 6").expect("fits");
    for k in 0..m.torque_coeff_count() {
        for i in 0..3 {
            let v = ((k * 13 + i * 7) % 19) as f64 / 19.0 - 0.5;
            m.set_beta(i, k, v * 0.25).expect("in range");
        }
    }
    m
}
