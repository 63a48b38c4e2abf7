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

use crate::fit::joint::{ridge_extra_columns, Joint};
use crate::fit::normals::solve;
use crate::fit::smoothing::regularise;
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
    ridge_extra_columns(&mut ata, 0..idx.len());
    let u = solve(&ata, &atb);
    let own = btb - 2.0 * u.dot(&atb) + u.dot(&(&ata * &u));
    (btb > 0.0).then(|| own.max(0.0) / btb)
}

/// The share of an effect's force that C_F cannot take over: the
/// weighted square of the force `A_new θ` (columns `new`, fitted values
/// `theta`) left after its best representation by the base unknowns (the
/// SH force coefficients alpha, with the base fit's smoothing) and the
/// columns `kept` of the effects chosen before it, over its own weighted
/// square, all takes: `1 - g' (A_kk + S)^-1 g / θ' A_nn θ` with `g = A_kn θ`.
///
/// Why: the held-out gain of an effect is bounded by this share, not by
/// its strength. A force the base model can represent (linear drag
/// `-k μ L V` at the speeds a direction is flown at is nearly
/// `½ ρ |V|² L² C_F(û)` times a constant, eq. 6) is absorbed by the base
/// fit's C_F, which is then off by as much, while its held-out residual,
/// the acceptance's "before", holds only the share outside C_F's span on
/// top of the reconstruction's own noise. A small share says the effect
/// is found by what it does to C_F rather than by the residual it
/// removes. `None` with a held model (`--coeffs`: nothing absorbs), no
/// columns, or a zero force.
pub(crate) fn beyond_cf(
    joint: &Joint,
    kept: &[usize],
    new: &[usize],
    theta: &[f64],
) -> Option<f64> {
    if joint.base == 0 || new.is_empty() || new.len() != theta.len() {
        return None;
    }
    let span: Vec<usize> = (0..joint.base)
        .chain(kept.iter().map(|c| joint.base + c))
        .collect();
    let own: Vec<usize> = new.iter().map(|c| joint.base + c).collect();
    let mut all = span.clone();
    all.extend(&own);
    let mut ata = DMatrix::zeros(all.len(), all.len());
    for n in &joint.takes {
        ata += n.ata.select_rows(&all).select_columns(&all);
    }
    let (ns, nn) = (span.len(), own.len());
    let mut a_ss = ata.view((0, 0), (ns, ns)).into_owned();
    regularise(&mut a_ss, 3, joint.degree, joint.smoothing);
    ridge_extra_columns(&mut a_ss, joint.base..ns);
    let theta = DVector::from_column_slice(theta);
    let g = ata.view((0, ns), (ns, nn)) * &theta;
    let energy = theta.dot(&(ata.view((ns, ns), (nn, nn)) * &theta));
    let absorbed = g.dot(&solve(&a_ss, &g));
    (energy > 0.0 && energy.is_finite()).then(|| ((energy - absorbed) / energy).clamp(0.0, 1.0))
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

    /// A column equal to the base's own rows (C_F can take all of it)
    /// has no share beyond C_F; a column unrelated to the base keeps
    /// nearly all of its force.
    #[test]
    fn a_force_the_base_can_represent_has_no_share_beyond_cf() {
        let mut j = joint();
        for f in &mut j.frames {
            let s = f.base[(0, 0)];
            let inside = Vector3::new(0.2, 0.1, -0.4) * s;
            let unrelated = Vector3::new(
                (0.91 * s * 37.0).sin(),
                (1.7 * s * 11.0).cos(),
                (0.3 * s * 53.0).sin(),
            );
            f.extra = DMatrix::from_fn(3, 2, |i, c| if c == 0 { inside[i] } else { unrelated[i] });
        }
        let j = Joint::new(j.frames, 0, j.smoothing);
        let inside = beyond_cf(&j, &[], &[0], &[3.0]).expect("share");
        assert!(inside < 1e-3, "a force C_F represents: {inside}");
        let outside = beyond_cf(&j, &[], &[1], &[3.0]).expect("share");
        assert!(outside > 0.5, "an unrelated force: {outside}");
        let both = beyond_cf(&j, &[1], &[0], &[1.0]).expect("share");
        assert!(both < 1e-3, "{both}");
        assert!(beyond_cf(&j, &[], &[], &[]).is_none());
        assert!(beyond_cf(&j, &[], &[0], &[0.0]).is_none());
    }
}
