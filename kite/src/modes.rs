//! A diagnostic beyond the paper, used to explain where the static verdict
//! and the flight simulation disagree: the linearised *rotational*
//! dynamics about the static balance, `I Θ̈ = J Θ + C Θ̇`, with `J` the
//! stability Jacobian (string tension from linear equilibrium, as in §7)
//! and `C = ∂T_air/∂Ω` at `Ω = 0` (the rate damping that comes from each
//! primitive moving through the air at `Ω × Y_p`; OmniAD's own D term is
//! quadratic in Ω and so has no linear part). The largest real part of the
//! eigenvalues of `[[0, 1], [I⁻¹J, I⁻¹C]]` is the growth rate (1/s) of the
//! fastest rotational mode: positive means the attitude oscillation grows
//! (flutter from the non-symmetric part of `J`, which the symmetric-part
//! test of §7 ignores). Translation along the line is still ignored.

use crate::assemble::Design;
use anyhow::{anyhow, Result};
use nalgebra::{Matrix3, SMatrix, UnitQuaternion, Vector3};
use omniad_core::kite::{stability, statics};

/// `C = ∂T_air/∂Ω` at Ω = 0, body frame, N m s/rad (central differences).
pub fn rate_damping(design: &Design, wind: Option<f64>, r: &UnitQuaternion<f64>) -> Matrix3<f64> {
    let prims = design.primitives();
    let cond = design.conditions(wind);
    let v = r.inverse_transform_vector(&(-cond.wind));
    let h = 1e-4;
    let mut c = Matrix3::zeros();
    for (j, e) in [Vector3::x(), Vector3::y(), Vector3::z()]
        .iter()
        .enumerate()
    {
        let t = |s: f64| statics::air_wrench(&prims, &v, &(e * s), cond.air_density).torque;
        c.set_column(j, &((t(h) - t(-h)) / (2.0 * h)));
    }
    c
}

/// The largest real part of the rotational modes, 1/s.
pub fn max_growth_rate(
    design: &Design,
    wind: Option<f64>,
    r: &UnitQuaternion<f64>,
    p: &Vector3<f64>,
) -> Result<f64> {
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let cond = design.conditions(wind);
    let j = stability::jacobian(&kite, &cond, r, p).map_err(|e| anyhow!("{e}"))?;
    let c = rate_damping(design, wind, r);
    let inv = design.body()?.inverse_inertia;
    let mut a = SMatrix::<f64, 6, 6>::zeros();
    a.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&Matrix3::identity());
    a.fixed_view_mut::<3, 3>(3, 0).copy_from(&(inv * j));
    a.fixed_view_mut::<3, 3>(3, 3).copy_from(&(inv * c));
    let eig = a.complex_eigenvalues();
    Ok(eig.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max))
}
