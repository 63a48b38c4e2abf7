//! Rod joints: where rod ends meet (and rods that pass through such a
//! point). Each joint gets one printed socket (§7, Fig. 9).

use crate::geometry::Rod;
use nalgebra::Vector3;

/// Ends closer than this are one joint, m.
pub const JOINT_TOLERANCE: f64 = 0.005;

/// One joint: its position and the rods leaving it.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Position, design frame, m.
    pub position: Vector3<f64>,
    /// Unit directions of the rods leaving the joint, design frame.
    pub directions: Vec<Vector3<f64>>,
    /// Labels of those rods (same order).
    pub rods: Vec<String>,
}

/// Groups rod ends into joints. A rod whose interior passes through a
/// joint contributes both of its directions there (a through socket).
pub fn joints(rods: &[Rod]) -> Vec<Joint> {
    let mut out: Vec<Joint> = Vec::new();
    for rod in rods {
        for (end, other) in [(rod.a, rod.b), (rod.b, rod.a)] {
            let dir = (other - end).normalize();
            match out
                .iter_mut()
                .find(|j| (j.position - end).norm() < JOINT_TOLERANCE)
            {
                Some(j) => {
                    j.directions.push(dir);
                    j.rods.push(rod.label.clone());
                }
                None => out.push(Joint {
                    position: end,
                    directions: vec![dir],
                    rods: vec![rod.label.clone()],
                }),
            }
        }
    }
    for rod in rods {
        for j in out.iter_mut() {
            if passes_through(rod, &j.position) {
                let d = (rod.b - rod.a).normalize();
                j.directions.push(d);
                j.directions.push(-d);
                j.rods.push(format!("{} (through)", rod.label));
                j.rods.push(format!("{} (through)", rod.label));
            }
        }
    }
    out
}

/// True when `p` lies on the rod's interior (not within tolerance of an end).
fn passes_through(rod: &Rod, p: &Vector3<f64>) -> bool {
    let ab = rod.b - rod.a;
    let len = ab.norm();
    let t = (p - rod.a).dot(&ab) / (len * len);
    let margin = JOINT_TOLERANCE / len;
    if t <= margin || t >= 1.0 - margin {
        return false;
    }
    (rod.a + ab * t - p).norm() < JOINT_TOLERANCE
}
