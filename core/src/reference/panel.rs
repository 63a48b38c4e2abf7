//! An independent quasi-steady panel model of thin plates and open boxes.
//!
//! This is *not* the OmniAD model: it is a classical strip/panel estimate
//! used to make honest example coefficients (the bundled plate, the
//! KiteShop primitives, the synthetic recording sets) by projecting it onto
//! spherical harmonics ([`crate::projection`]), and as a generator physics
//! independent of the SH representation.
//!
//! Each flat rectangular panel feels, for an air-relative velocity `u` of
//! its centre (the body moving at `u` through still air):
//! * a normal force `-½ρA C_N(α)|u|² sign(u·n) n`, with `sin α = |û·n|`
//!   and the flat-plate normal-force law `C_N(α) = C_N90 · 2 sin α / (1 +
//!   sin α)` (slope `2 C_N90` per radian at small α, `C_N90` at 90°; after
//!   Hoerner's flat-plate data, `C_N90 = 1.17`);
//! * skin friction `-½ρA C_f |u| u_t` along the in-plane part `u_t`;
//! * the normal force acts at the centre of pressure, shifted from the
//!   panel centre toward the leading edge by `½ h cos α` (quarter chord at
//!   α → 0, mid chord at 90°), `h` the panel's half-extent along `u_t`.
//!
//! Rotation (eq. 4's damping) is integrated over a grid of panel elements
//! with local velocity `Ω × r`, normal force `-½ρ C_N90 |u_n| u_n n dA`.
//! Panels do not shadow one another (KiteShop forbids overlap along the
//! wind, §7).

use crate::math::{nearest_psd, symmetric_from_six, symmetric_times_vector_rows};
use crate::quadrature::fibonacci_sphere;
use nalgebra::{Matrix3, Vector3};

/// Flat-plate normal-force coefficient at 90°, after Hoerner.
pub const NORMAL_COEFFICIENT_90: f64 = 1.17;
/// Skin-friction coefficient per wetted panel (both faces).
pub const FRICTION_COEFFICIENT: f64 = 0.02;
/// Elements per panel edge for the rotational integral.
const GRID: usize = 8;
/// Most panels in one model (an open box has four).
pub const MAX_PANELS: usize = 4;

/// One thin rectangular panel, body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Centre, m.
    pub center: Vector3<f64>,
    /// In-plane unit axis u.
    pub axis_u: Vector3<f64>,
    /// In-plane unit axis v (`n = u × v`).
    pub axis_v: Vector3<f64>,
    /// Half-extent along u, m.
    pub half_u: f64,
    /// Half-extent along v, m.
    pub half_v: f64,
}

impl Panel {
    /// Unit normal `u × v`.
    pub fn normal(&self) -> Vector3<f64> {
        self.axis_u.cross(&self.axis_v)
    }
    /// Area, m².
    pub fn area(&self) -> f64 {
        4.0 * self.half_u * self.half_v
    }
    /// Half-extent along an in-plane unit direction, m.
    fn half_extent(&self, dir: &Vector3<f64>) -> f64 {
        self.half_u * dir.dot(&self.axis_u).abs() + self.half_v * dir.dot(&self.axis_v).abs()
    }
}

/// A rigid set of panels.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelModel {
    /// The panels, body frame (origin at the centre of mass).
    pub panels: heapless::Vec<Panel, MAX_PANELS>,
}

/// Flat-plate normal-force law `C_N(α)`, α from `sin α`.
pub fn normal_coefficient(sin_alpha: f64) -> f64 {
    let s = sin_alpha.clamp(0.0, 1.0);
    NORMAL_COEFFICIENT_90 * 2.0 * s / (1.0 + s)
}

impl PanelModel {
    /// A thin plate `lx` x `ly` (m) in the body x-y plane, normal +z.
    pub fn plate(lx: f64, ly: f64) -> Self {
        Self {
            panels: heapless::Vec::from_array([Panel {
                center: Vector3::zeros(),
                axis_u: Vector3::x(),
                axis_v: Vector3::y(),
                half_u: lx / 2.0,
                half_v: ly / 2.0,
            }]),
        }
    }

    /// A box-kite cell `lx` x `ly` x `lz` (m), open on its two y faces:
    /// four panels with normals ±x (`ly` x `lz`) and ±z (`lx` x `ly`).
    pub fn open_box(lx: f64, ly: f64, lz: f64) -> Self {
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let side = |c: Vector3<f64>, u: Vector3<f64>, v: Vector3<f64>, hu: f64, hv: f64| Panel {
            center: c,
            axis_u: u,
            axis_v: v,
            half_u: hu,
            half_v: hv,
        };
        let panels = heapless::Vec::from_array([
            side(x * (lx / 2.0), y, z, ly / 2.0, lz / 2.0),
            side(-x * (lx / 2.0), z, y, lz / 2.0, ly / 2.0),
            side(z * (lz / 2.0), x, y, lx / 2.0, ly / 2.0),
            side(-z * (lz / 2.0), y, x, ly / 2.0, lx / 2.0),
        ]);
        Self { panels }
    }

    /// Total panel area, m².
    pub fn area(&self) -> f64 {
        self.panels.iter().map(Panel::area).sum()
    }

    /// Force (N) and torque (N m) at zero angular velocity for body
    /// velocity `v` relative to the air (body frame, m/s), density `rho`.
    pub fn translation_wrench(&self, v: &Vector3<f64>, rho: f64) -> (Vector3<f64>, Vector3<f64>) {
        let speed = v.norm();
        let (mut f, mut t) = (Vector3::zeros(), Vector3::zeros());
        if speed.is_nan() || speed <= 0.0 {
            return (f, t);
        }
        let q = 0.5 * rho * speed * speed;
        for p in &self.panels {
            let n = p.normal();
            let un = v.dot(&n) / speed;
            let sin_a = un.abs();
            let tangential = v / speed - n * un;
            let t_len = tangential.norm();
            let normal_force = -n * (q * p.area() * normal_coefficient(sin_a) * un.signum());
            let friction = -tangential * (q * p.area() * FRICTION_COEFFICIENT);
            let mut at = p.center;
            if t_len > 1e-12 {
                let dir = tangential / t_len;
                at += dir * (0.5 * p.half_extent(&dir) * t_len);
            }
            f += normal_force + friction;
            t += at.cross(&normal_force) + p.center.cross(&friction);
        }
        (f, t)
    }

    /// Torque (N m) of pure rotation `omega` (body frame, rad/s).
    pub fn rotation_torque(&self, omega: &Vector3<f64>, rho: f64) -> Vector3<f64> {
        let mut t = Vector3::zeros();
        for p in &self.panels {
            let n = p.normal();
            let da = p.area() / (GRID * GRID) as f64;
            for i in 0..GRID {
                for j in 0..GRID {
                    let a = ((i as f64 + 0.5) / GRID as f64 * 2.0 - 1.0) * p.half_u;
                    let b = ((j as f64 + 0.5) / GRID as f64 * 2.0 - 1.0) * p.half_v;
                    let r = p.center + p.axis_u * a + p.axis_v * b;
                    let un = omega.cross(&r).dot(&n);
                    let df = -n * (0.5 * rho * NORMAL_COEFFICIENT_90 * un.abs() * un * da);
                    t += r.cross(&df);
                }
            }
        }
        t
    }

    /// Non-dimensional damping tensor D of eq. (6) for reference length
    /// `l` (m): the symmetric D minimising `Σ |T(Ω) + ½ρ D |Ω| Ω L⁵|²` over
    /// unit rotation directions (eq. 12 applied to this model), projected
    /// to the positive semi-definite cone.
    pub fn damping_tensor(&self, l: f64) -> Matrix3<f64> {
        let rho = 1.0;
        // Unknowns d = [xx, yy, zz, xy, xz, yz]; T = -½ρL⁵ D w for unit w.
        let mut ata = nalgebra::SMatrix::<f64, 6, 6>::zeros();
        let mut atb = nalgebra::SVector::<f64, 6>::zeros();
        // L⁵ as (L²)² L, the rounding of `powi(5)`.
        let l2 = l * l;
        let scale = -0.5 * rho * (l * (l2 * l2));
        for w in fibonacci_sphere(200) {
            let t = self.rotation_torque(&w, rho);
            for (row, ti) in symmetric_times_vector_rows(&w).iter().zip(t.iter()) {
                let a = nalgebra::SVector::<f64, 6>::from(*row) * scale;
                ata += a * a.transpose();
                atb += a * *ti;
            }
        }
        let d = ata
            .cholesky()
            .map(|c| c.solve(&atb))
            .unwrap_or_else(nalgebra::SVector::zeros);
        nearest_psd(&symmetric_from_six(d.into()))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::indexing_slicing)]
    use super::*;

    #[test]
    fn plate_broadside_drag_matches_normal_coefficient() {
        let m = PanelModel::plate(0.3, 0.5);
        let (f, t) = m.translation_wrench(&Vector3::new(0.0, 0.0, -2.0), 1.2);
        let expected = 0.5 * 1.2 * 4.0 * 0.15 * NORMAL_COEFFICIENT_90;
        assert!((f.z - expected).abs() < 1e-12, "{f:?}");
        assert!(t.norm() < 1e-12);
    }

    #[test]
    fn forces_oppose_motion_and_torque_is_restoring_for_a_plate() {
        let m = PanelModel::open_box(0.3, 0.4, 0.2);
        for v in fibonacci_sphere(50) {
            let (f, _) = m.translation_wrench(&v, 1.2);
            assert!(f.dot(&v) < 0.0, "thrust at {v:?}");
        }
        // A plate moving mostly in-plane (+x) with a little -z: the CP sits
        // ahead of the centre, so the torque turns the plate broadside.
        let p = PanelModel::plate(0.3, 0.5);
        let (_, t) = p.translation_wrench(&Vector3::new(1.0, 0.0, -0.2), 1.2);
        assert!(t.y.abs() > 1e-4);
    }

    #[test]
    fn damping_is_positive_semidefinite_and_plate_spins_freely_about_its_normal() {
        let p = PanelModel::plate(0.3, 0.5);
        let d = p.damping_tensor(0.58);
        let eig = d.symmetric_eigen().eigenvalues;
        assert!(eig.iter().all(|&x| x >= -1e-12));
        // Rotation about the normal moves the plate in-plane only.
        assert!(d[(2, 2)].abs() < 1e-9 && d[(1, 1)] > 0.0 && d[(0, 0)] > d[(1, 1)]);
    }
}
