//! `kite trim`: the orientation at which the kite balances (`T_kite = 0`)
//! with the string fixed at the file's attachment point, searched from the
//! file's orientation and a few rotated starts (core `kite::trim`), then
//! checked for stability there. Reports when no trim is found.

use crate::assemble::Design;
use crate::check::{self, CheckReport};
use anyhow::{anyhow, Result};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::kite::trim::{trim as solve, TrimOptions};
use serde::Serialize;

/// Start offsets from the file's orientation, (x, y, z) rotation vectors in degrees.
const STARTS: [[f64; 3]; 9] = [
    [0.0, 0.0, 0.0],
    [0.0, 15.0, 0.0],
    [0.0, -15.0, 0.0],
    [0.0, 30.0, 0.0],
    [0.0, -30.0, 0.0],
    [20.0, 0.0, 0.0],
    [-20.0, 0.0, 0.0],
    [0.0, 0.0, 20.0],
    [0.0, 0.0, -20.0],
];

/// What `kite trim` reports.
#[derive(Clone, Debug, Serialize)]
pub struct TrimReport {
    /// Kite name.
    pub name: String,
    /// A balanced orientation was found.
    pub found: bool,
    /// Attachment point used, body frame, m.
    pub attachment: [f64; 3],
    /// Trimmed orientation (or best found): x, y, z Euler angles, degrees.
    pub orientation_deg: [f64; 3],
    /// Rotation from the file's orientation to the trim, degrees.
    pub change_deg: f64,
    /// `|T_kite|` at the trim, N m.
    pub residual: f64,
    /// The static report at the trim (same attachment point).
    pub at_trim: Option<CheckReport>,
    /// Why none was found, if so.
    pub message: String,
}

impl TrimReport {
    /// One-line summary for tables.
    pub fn summary(&self) -> String {
        match &self.at_trim {
            Some(c) if self.found => format!(
                "{:?}, pitch {:+.0}° ({:+.0}°)",
                c.verdict, self.orientation_deg[1], self.change_deg
            )
            .to_lowercase(),
            _ => "none found".into(),
        }
    }
}

/// Trims the kite at wind `wind` (m/s; default the file's).
pub fn trim(design: &Design, wind: Option<f64>) -> Result<TrimReport> {
    let r0 = design.orientation();
    let p = check::attachment_point(design, wind, &r0)?;
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let cond = design.conditions(wind);
    let opts = TrimOptions {
        tolerance: 1e-6,
        ..TrimOptions::default()
    };
    let mut best: Option<(UnitQuaternion<f64>, f64, bool)> = None;
    for start in STARTS {
        let s = r0 * UnitQuaternion::from_scaled_axis(Vector3::from(start.map(f64::to_radians)));
        let t = solve(&kite, &cond, &s, &p, &opts).map_err(|e| anyhow!("trim: {e}"))?;
        let res = t.torque.norm();
        let better = match best {
            None => true,
            Some((_, b, conv)) => (t.converged && !conv) || (t.converged == conv && res < b),
        };
        if better {
            best = Some((t.orientation, res, t.converged));
        }
        if t.converged && r0.angle_to(&t.orientation) < 0.8 {
            break;
        }
    }
    let (r, residual, found) = best.ok_or_else(|| anyhow!("trim: no start"))?;
    let (x, y, z) = r.euler_angles();
    let at_trim = if found {
        Some(check::check_at(design, wind, &r, Some(p))?)
    } else {
        None
    };
    let message = if found {
        String::new()
    } else {
        format!("no orientation balances the torque with the string at this point (best |T_kite| = {residual:.3e} N m); move the attachment (gamma/offset) or the primitives")
    };
    Ok(TrimReport {
        name: design.spec.name.clone(),
        found,
        attachment: p.into(),
        orientation_deg: [x, y, z].map(f64::to_degrees),
        change_deg: r0.angle_to(&r).to_degrees(),
        residual,
        at_trim,
        message,
    })
}

/// Human-readable report.
pub fn render(t: &TrimReport) -> String {
    let mut s = format!(
        "kite {:?}: attachment P = [{:+.4}, {:+.4}, {:+.4}] m\n",
        t.name, t.attachment[0], t.attachment[1], t.attachment[2]
    );
    if t.found {
        let [x, y, z] = t.orientation_deg;
        s += &format!("  trim found: orientation (x, y, z) = ({x:+.2}, {y:+.2}, {z:+.2}) deg, {:.1} deg from the file's, |T_kite| = {:.1e} N m\n", t.change_deg, t.residual);
        if let Some(c) = &t.at_trim {
            s += &crate::check::render(c);
        }
    } else {
        s += &format!("  NO TRIM: {}\n", t.message);
    }
    s
}
