//! Identifiability of a design against the force coefficients: can its
//! effects' columns, *without* any C_F, reproduce the measured force
//! itself?
//!
//! Why this is needed. Added mass's regressor is the measured body-frame
//! acceleration `dU/dt` (eq. 9's own velocity difference), so with a term
//! in gravity seen from the body the design holds the target: for an
//! isotropic `M_a = -k M I` and buoyancy `ρ V_b = k M`,
//! `-M_a dU/dt - Ω × (M_a U) - ρ V_b Rᵀg = k M (dU/dt + Ω × U - Rᵀg)
//! = k M Rᵀ(a - g) = k F*` (eq. 9, body frame, N). The joint fit can then
//! predict `(1 - k) C_F + k F*` for any k: on a held-out take that is a
//! blend of the model with the held-out measurement, whose error is
//! `(1 - k)` times the model's, so the held-out "gain" is no evidence, and
//! the base fit's smoothing (cheaper for a smaller alpha) drives k up
//! (plate `added_mass=0.3` seed 1: M_a ≈ -0.03 I kg, V_b 0.025 m³, C_F 63 %
//! off). Buoyancy and the generic gravity coupling both complete this
//! design once added mass is in it (and added mass completes it once they
//! are).
//!
//! The test fits the target with the design's extra columns alone on all
//! takes: a design whose columns leave at most [`COPY_FRACTION`] of the
//! measured force's weighted square unexplained, with no C_F, carries the
//! target in its columns and cannot be told from a rescaled C_F. What is
//! left in such a design is the identity's discretisation error (`dU/dt`
//! from the bodies' own rotations at `k ± 1`, eq. 9 from `R_k`), small;
//! a real effect leaves C_F's share unexplained. Measured (BENCHMARKS.md,
//! issue 15): added mass with buoyancy or gravity coupling 0.0002-0.0043
//! on plate and box sets and shared `plate-buoyancy`; every other design
//! 0.023 or more (the wind, the base model's own derivative, 0.04-0.12;
//! rotational lift on the `magnus=1.2` plate, 15 weights, 0.23).

use crate::fit::joint::Joint;
use crate::fit::normals::solve;
use nalgebra::{DMatrix, DVector};

/// A design whose extra columns alone leave at most this fraction of the
/// target's weighted square unexplained reproduces the target (1 %: the
/// columns explain 99 % of the measured force without any C_F).
pub const COPY_FRACTION: f64 = 0.01;

/// Weighted squared error of the target fitted by the extra columns
/// `cols` alone (all takes, no base unknown) over the target's weighted
/// square; `None` when there are no base unknowns (a held model,
/// `--coeffs`: C_F cannot move) or no columns.
pub(crate) fn unexplained_without_cf(joint: &Joint, cols: &[usize]) -> Option<f64> {
    if joint.base == 0 || cols.is_empty() {
        return None;
    }
    let idx: Vec<usize> = cols.iter().map(|c| joint.base + c).collect();
    let mut ata = DMatrix::zeros(idx.len(), idx.len());
    let mut atb = DVector::zeros(idx.len());
    let mut btb = 0.0;
    for n in &joint.takes {
        ata += n.ata.select_rows(&idx).select_columns(&idx);
        atb += n.atb.select_rows(&idx);
        btb += n.btb;
    }
    // The same relative ridge as the joint solve keeps the columns
    // regular.
    for i in 0..idx.len() {
        ata[(i, i)] *= 1.0 + 1e-6;
    }
    let u = solve(&ata, &atb);
    let own = btb - 2.0 * u.dot(&atb) + u.dot(&(&ata * &u));
    (btb > 0.0).then(|| own.max(0.0) / btb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::joint::JointFrame;
    use crate::fit::smoothing::Smoothing;
    use nalgebra::{Matrix3, Vector3};

    /// Degree-0 base (a constant force per axis times a per-frame scale)
    /// and two extra columns: `target - g` and `g`, whose sum is the
    /// target itself (as added mass and buoyancy are together), and `g`
    /// alone is an unrelated term.
    fn joint() -> Joint {
        let alpha = Vector3::new(0.3, -0.2, 0.5);
        let frames = (0..120)
            .map(|k| {
                let x = k as f64;
                let s = 1.0 + 0.5 * (0.37 * x).sin();
                let noise = 0.01 * Vector3::new((1.3 * x).sin(), (2.1 * x).cos(), (0.7 * x).sin());
                let target = alpha * s + noise;
                let g = Vector3::new((0.11 * x).cos(), (0.23 * x).sin(), 1.0);
                let mut extra = DMatrix::zeros(3, 2);
                extra.set_column(0, &(target - g));
                extra.set_column(1, &g);
                JointFrame {
                    take: k / 20,
                    base: DMatrix::from_diagonal_element(3, 3, s),
                    extra,
                    weight: Matrix3::identity(),
                    target,
                }
            })
            .collect();
        let smoothing = Smoothing {
            weight: 1e-3,
            order: 2,
        };
        Joint::new(frames, 0, smoothing)
    }

    #[test]
    fn a_design_holding_the_target_is_caught_and_an_unrelated_one_is_not() {
        let j = joint();
        let both = unexplained_without_cf(&j, &[0, 1]).expect("fraction");
        assert!(both < 1e-4, "columns summing to the target: {both}");
        let unrelated = unexplained_without_cf(&j, &[1]).expect("fraction");
        assert!(unrelated > 0.5, "an unrelated column: {unrelated}");
        assert!(unexplained_without_cf(&j, &[]).is_none());
    }
}
