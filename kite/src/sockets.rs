//! The printed socket at each rod joint (§7, Fig. 9: "connectors that can
//! be printed"): its dimensions, how much of each rod it swallows, and
//! which of its bores run into each other.
//!
//! A socket is a hub sphere of radius `hub_r = 0.9 outer_d` with one tube
//! per rod; each bore starts `hub_r / 2` from the joint's centre (the
//! solid core that holds the tubes together) and runs [`DEPTH_MM`] out
//! along its rod. So a rod whose ends sit at two joint centres is cut
//! `hub_r / 2` shorter at each end, and two bores whose axes are closer
//! than one bore diameter where they start have no wall between them:
//! the socket cannot be printed as drawn.

use crate::assemble::Design;
use crate::joints::Joint;
use serde::Serialize;

/// Socket wall thickness, mm.
pub const WALL_MM: f64 = 1.2;
/// Clearance between rod and bore (on the diameter), mm.
pub const CLEARANCE_MM: f64 = 0.3;
/// Depth of each rod bore, mm.
pub const DEPTH_MM: f64 = 15.0;

/// Bore diameter for a rod of `rod_d_mm`, mm.
pub fn bore_mm(rod_d_mm: f64) -> f64 {
    rod_d_mm + CLEARANCE_MM
}

/// Distance from the joint's centre to the bottom of a bore, mm: what a
/// rod ending at the joint is cut shorter by.
pub fn inset_mm(rod_d_mm: f64) -> f64 {
    let outer = bore_mm(rod_d_mm) + 2.0 * WALL_MM;
    0.9 * outer / 2.0
}

/// Two bores of one socket that run into each other.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Clash {
    /// Joint index (as in `sockets.scad`).
    pub joint: usize,
    /// Joint position, design frame, mm.
    pub position_mm: [f64; 3],
    /// The two rods' labels.
    pub rods: [String; 2],
    /// Angle between them, degrees.
    pub angle_deg: f64,
    /// Smallest angle at which their bores keep a wall between them, deg.
    pub min_angle_deg: f64,
}

/// Smallest angle between two bores that keeps them apart where they
/// start (axes a bore diameter apart at `inset` from the centre), deg.
pub fn min_angle_deg(rod_d_mm: f64) -> f64 {
    let half = (bore_mm(rod_d_mm) / (2.0 * inset_mm(rod_d_mm))).min(1.0);
    2.0 * half.asin().to_degrees()
}

/// Every pair of bores that clash, joint by joint.
pub fn clashes(design: &Design) -> Vec<Clash> {
    let d_mm = design.spec.materials.rod_diameter * 1e3;
    let limit = min_angle_deg(d_mm);
    let mut out = Vec::new();
    for (k, j) in design.joints.iter().enumerate() {
        out.extend(joint_clashes(k, j, limit));
    }
    out
}

fn joint_clashes(k: usize, j: &Joint, limit: f64) -> Vec<Clash> {
    let mut out = Vec::new();
    for (a, (u, ra)) in j.directions.iter().zip(&j.rods).enumerate() {
        for (v, rb) in j.directions.iter().zip(&j.rods).skip(a + 1) {
            let angle = u.dot(v).clamp(-1.0, 1.0).acos().to_degrees();
            if angle < limit {
                let p = j.position * 1e3;
                out.push(Clash {
                    joint: k,
                    position_mm: [p.x, p.y, p.z],
                    rods: [ra.clone(), rb.clone()],
                    angle_deg: angle,
                    min_angle_deg: limit,
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn joint(dirs: &[[f64; 3]]) -> Joint {
        Joint {
            position: Vector3::zeros(),
            directions: dirs.iter().map(|d| Vector3::from(*d).normalize()).collect(),
            rods: (0..dirs.len()).map(|i| format!("r{i}")).collect(),
        }
    }

    #[test]
    fn right_angles_do_not_clash_but_a_shallow_diagonal_does() {
        let limit = min_angle_deg(2.0);
        assert!(limit > 10.0 && limit < 90.0, "{limit}");
        let corner = joint(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        assert!(joint_clashes(0, &corner, limit).is_empty());
        let shallow = joint(&[[1.0, 0.0, 0.0], [1.0, 0.2, 0.0]]);
        let c = joint_clashes(3, &shallow, limit);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].joint, 3);
        assert!(c[0].angle_deg < limit);
    }

    #[test]
    fn inset_is_the_hub_core() {
        // 2 mm rod: bore 2.3, outer 4.7, hub 4.23 mm, core half of it.
        assert!((inset_mm(2.0) - 2.115).abs() < 1e-9);
    }
}
