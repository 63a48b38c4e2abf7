//! The default model embedded in the firmware: a plate-like OmniAD model
//! of the Kitepower V3 leading-edge-inflatable kite (25 m², projected
//! 19.75 m²), projected onto spherical harmonics of degree [`DEGREE`].
//!
//! There is no measured OmniAD model of this kite; this one is built from
//! a textbook normal-force plate model so that the firmware computes with
//! realistic magnitudes, not as a validated kite model:
//!
//! `C_F(E) L² / S = -c_n (E·n + s0) n - c_d E` with `n` the canopy normal
//! (body +z, FRD), `c_n` = 4.0 (lift slope of an aspect-ratio 3.5 wing),
//! `s0` = 0.1 (camber: lift at zero angle of attack), `c_d` = 0.1;
//! `C_T = (r_cp / L) × C_F` with the centre of pressure `r_cp` 0.25 m aft
//! and 3 m above the centre of mass (which the control unit pulls below
//! the canopy); damping `D` = 0.005 I. The pole is `n`. The projection is
//! the core's (eqs. 11, 13, `omniad_core::projection`).

use crate::process::DEFAULT_BODY;
use nalgebra::{Matrix3, Vector3};
use omniad_core::coefficients::Provenance;
use omniad_core::projection::project;
use omniad_core::{Coefficients, ModelError};

/// SH degree of the default model (the budget is stated at N = 8).
pub const DEGREE: u8 = 8;
/// Reference length L, m: bounding-box diagonal of the 8.3 x 2.5 x 3 m canopy.
pub const REFERENCE_LENGTH: f64 = 9.2;
/// Projected area S, m².
pub const AREA: f64 = 19.75;

const C_N: f64 = 4.0;
const S0: f64 = 0.1;
const C_D: f64 = 0.1;
const R_CP: [f64; 3] = [-0.25, 0.0, -3.0];

fn coefficients_at(e: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let n = Vector3::z();
    let k = AREA / (REFERENCE_LENGTH * REFERENCE_LENGTH);
    let cf = (n * (C_N * (e.dot(&n) + S0)) + e * C_D) * -k;
    let p = Vector3::from(R_CP) / REFERENCE_LENGTH;
    (cf, p.cross(&cf))
}

/// Builds the default kite model (f64, ready to encode).
pub fn default_model() -> Result<Coefficients<f64>, ModelError> {
    let mut m = project(DEGREE, Vector3::z(), REFERENCE_LENGTH, coefficients_at)?;
    m.set_name("kitepower-v3-plate-like")?;
    m.set_damping(&(Matrix3::identity() * 0.005))?;
    m.body = Some(DEFAULT_BODY);
    let mut p = Provenance::default();
    let _ = p.method.push_str("projection");
    let _ = p
        .source
        .push_str("firmware-sim/pipeline/src/kite.rs: plate-like model of the Kitepower V3 kite");
    m.provenance = p;
    Ok(m)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn projection_reproduces_the_analytic_model() {
        let m = default_model().unwrap();
        // Away from the poles the degree-8 projection is close to the
        // analytic coefficients (the E2/E3 components have kinks at the
        // poles, so the error is largest there).
        for e in [
            Vector3::new(0.97f64, 0.0, 0.24),
            Vector3::new(0.6, 0.5, 0.62),
            Vector3::new(-0.3, 0.9, -0.3),
        ] {
            let e = e.normalize();
            let got = m.at_direction(&e).unwrap();
            let (cf, ct) = coefficients_at(&e);
            assert!(
                (got.force - cf).norm() < 0.05 * cf.norm().max(0.1),
                "{e:?}: {:?} vs {cf:?}",
                got.force
            );
            assert!(
                (got.torque - ct).norm() < 0.05 * cf.norm().max(0.1),
                "{e:?}"
            );
        }
    }
}
