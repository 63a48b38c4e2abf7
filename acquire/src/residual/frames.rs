//! The per-frame held-out force residuals (issue 15 item 2): what the
//! report's profiles and figures are binned from, one row per frame, so
//! that a user can look at them with any tool (`omniad residual --plots
//! DIR` writes them as `residual-frames.csv`).
//!
//! Why body-frame vectors and not the fit's numbers: the joint problems
//! hold each frame's residual in its own tangent basis `B` (§4.2, eq. 7's
//! `BᵀF*`), which changes from frame to frame. `B` is orthonormal, so the
//! body-frame residual is `B r` with the same length.

use crate::reconstruct::forces::Sample;
use crate::residual::problems::Problems;
use nalgebra::Vector3;
use std::fmt::Write as _;

/// One frame's held-out residual under one model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameResidual {
    /// `base` (the base model on the frames `extended` is scored on: the
    /// report's `baseline`), `extended` (the last round's model with the
    /// selected effects) or `first_round` (the base model on the first
    /// round's states: the report's `first_round_baseline`); each take
    /// held out.
    pub model: &'static str,
    /// The frame: its take, time, body-frame V, Ω, dV/dt and measured
    /// force F* (eq. 9).
    pub sample: Sample,
    /// Measured minus held-out model force, body frame, N (for a model
    /// with added mass, `M` times the measured minus the predicted rate:
    /// `super::output_error`).
    pub residual: Vector3<f64>,
}

/// The rows of `residuals` (one per force frame of `p`, in the fit's
/// basis, as `select::Scored::residuals`) in the body frame, labelled
/// `model`.
pub(crate) fn rows(
    model: &'static str,
    p: &Problems,
    residuals: &[Vector3<f64>],
) -> Vec<FrameResidual> {
    p.force_samples
        .iter()
        .zip(&p.force_bases)
        .zip(residuals)
        .map(|((s, b), r)| FrameResidual {
            model,
            sample: *s,
            residual: b * r,
        })
        .collect()
}

/// The CSV text of `rows` (header first; takes by their names in `takes`).
pub fn csv(rows: &[FrameResidual], takes: &[String]) -> String {
    let mut out =
        String::from("model,take,t,vx,vy,vz,wx,wy,wz,dvx_dt,dvy_dt,dvz_dt,fx,fy,fz,rx,ry,rz\n");
    for r in rows {
        let s = &r.sample;
        let name = takes.get(s.take).map_or("?", String::as_str);
        let _ = write!(out, "{},{},{:.6}", r.model, name, s.t);
        for v in [
            &s.velocity,
            &s.angular_velocity,
            &s.velocity_rate,
            &s.force,
            &r.residual,
        ] {
            let _ = write!(out, ",{:.9e},{:.9e},{:.9e}", v.x, v.y, v.z);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::context::FitContext;
    use crate::fit::force::force_row;
    use crate::fit::joint::Joint;
    use crate::fit::smoothing::Smoothing;
    use nalgebra::Matrix3;

    /// A residual equal to the whole target (a model that predicts no
    /// force) is the measured force itself once turned into the body
    /// frame: the basis is the fit's own.
    #[test]
    fn a_residual_turns_back_into_the_body_frame() {
        let fit = FitContext {
            air_density: 1.2,
            reference_length: 0.5,
            pole: Vector3::z(),
        };
        let s = Sample {
            take: 0,
            index: 1,
            t: 0.05,
            kind: crate::input::recording::TakeKind::Drop,
            velocity: Vector3::new(0.3, -1.1, -2.4),
            angular_velocity: Vector3::new(1.0, -2.0, 0.5),
            velocity_rate: Vector3::zeros(),
            force: Vector3::new(0.05, 0.21, -0.33),
            torque: Vector3::zeros(),
            gravity_body: Vector3::new(0.0, 0.0, -9.81),
            force_cov: Matrix3::identity() * 1e-4,
            use_force: true,
            use_torque: true,
        };
        let row = force_row(&s, &Matrix3::identity(), &fit, 2);
        let none = Smoothing {
            weight: 0.0,
            order: 2,
        };
        let p = Problems {
            force: Joint::new(Vec::new(), 2, none),
            torque: Joint::new(Vec::new(), 2, none),
            offsets: crate::residual::problems::offsets(),
            force_samples: vec![s],
            force_bases: vec![row.basis],
            mass: 0.04,
            held_added_mass: Matrix3::zeros(),
        };
        let out = rows("base", &p, &[row.target]);
        let r = out.first().map(|f| f.residual).unwrap_or_default();
        assert!((r - s.force).norm() < 1e-12, "{r:?} vs {:?}", s.force);
        let text = csv(&out, &["drop-01".into()]);
        assert!(
            text.lines()
                .nth(1)
                .is_some_and(|l| l.starts_with("base,drop-01,")),
            "{text}"
        );
        assert_eq!(text.lines().count(), 2);
    }
}
