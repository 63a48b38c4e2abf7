//! The shapes the comparison models are built from: a thin plate or a
//! closed box, its extents and mass, and its surface as flat faces cut
//! into elements (the per-element models of [`super::drag_traction`] and
//! [`super::simplified`] sum over them).

use super::panel::Panel;
use nalgebra::{Matrix3, Vector3};

/// Which shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// A thin plate in the body x-y plane (normal +z), `size.z` its
    /// thickness; its surface is one two-sided face.
    Plate,
    /// A closed box; its surface is six one-sided faces (outward normals).
    Box,
}

/// A uniform solid plate or box, centred on its centre of mass, body axes
/// along its edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Plate or box.
    pub kind: ShapeKind,
    /// Extents along body x, y, z, m.
    pub size: Vector3<f64>,
    /// Mass, kg.
    pub mass: f64,
}

/// One flat face of a shape's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// The rectangle (centre, axes, half-extents), body frame; its normal
    /// `u × v` points outward.
    pub panel: Panel,
    /// Whether air acts on both sides (a thin plate) or only the outer one.
    pub two_sided: bool,
}

/// One surface element: centre, outward unit normal, area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Centre, body frame, m.
    pub at: Vector3<f64>,
    /// Outward unit normal, body frame.
    pub normal: Vector3<f64>,
    /// Area, m².
    pub area: f64,
    /// Whether air acts on both sides.
    pub two_sided: bool,
}

/// Elements per face edge: 8 x 8 per face (the panel model's rotational
/// grid), enough for the rotational damping integral to within ~1 %.
pub const GRID: usize = 8;

impl Shape {
    /// The paper's foam plate (§8): 30 x 50 x 2 cm, 48 g.
    pub const PAPER_PLATE: Shape = Shape {
        kind: ShapeKind::Plate,
        size: Vector3::new(0.3, 0.5, 0.02),
        mass: 0.048,
    };

    /// Inertia of a uniform solid box of the extents about its centre,
    /// body frame, kg m²: `I_xx = M (y² + z²) / 12` and cyclic.
    pub fn inertia(&self) -> Matrix3<f64> {
        let s = self.size.component_mul(&self.size) * (self.mass / 12.0);
        Matrix3::from_diagonal(&Vector3::new(s.y + s.z, s.x + s.z, s.x + s.y))
    }

    /// Reference length L (eq. 3): the bounding-box diagonal, m (as the
    /// synthetic sets and the bundled plate).
    pub fn reference_length(&self) -> f64 {
        self.size.norm()
    }

    /// The faces air acts on: one two-sided face for a plate, six
    /// one-sided faces for a box.
    pub fn faces(&self) -> heapless::Vec<Face, 6> {
        let h = self.size * 0.5;
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let face = |center: Vector3<f64>, axis_u, axis_v, half_u, half_v, two_sided| Face {
            panel: Panel {
                center,
                axis_u,
                axis_v,
                half_u,
                half_v,
            },
            two_sided,
        };
        let mut out = heapless::Vec::new();
        let faces: &[Face] = match self.kind {
            ShapeKind::Plate => &[face(Vector3::zeros(), x, y, h.x, h.y, true)],
            ShapeKind::Box => &[
                face(x * h.x, y, z, h.y, h.z, false),
                face(-x * h.x, z, y, h.z, h.y, false),
                face(y * h.y, z, x, h.z, h.x, false),
                face(-y * h.y, x, z, h.x, h.z, false),
                face(z * h.z, x, y, h.x, h.y, false),
                face(-z * h.z, y, x, h.y, h.x, false),
            ],
        };
        for f in faces {
            // Six faces at most: the capacity is never exceeded.
            let _ = out.push(*f);
        }
        out
    }

    /// Force and torque (N, N m, body frame, about the centre) of
    /// per-element forces `force(element, u)`, each element moving at
    /// `u = V + Ω × r` through still air (V, Ω body frame): the sum the
    /// per-element comparison models share.
    pub fn element_wrench(
        &self,
        v: &Vector3<f64>,
        w: &Vector3<f64>,
        force: impl Fn(&Element, &Vector3<f64>) -> Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (mut f_sum, mut t_sum) = (Vector3::zeros(), Vector3::zeros());
        self.for_each_element(|e| {
            let f = force(e, &(v + w.cross(&e.at)));
            f_sum += f;
            t_sum += e.at.cross(&f);
        });
        (f_sum, t_sum)
    }

    /// Calls `f` for every surface element (`GRID` x `GRID` per face).
    pub fn for_each_element(&self, mut f: impl FnMut(&Element)) {
        for face in &self.faces() {
            let p = &face.panel;
            let normal = p.normal();
            let area = p.area() / (GRID * GRID) as f64;
            for i in 0..GRID {
                for j in 0..GRID {
                    let a = ((i as f64 + 0.5) / GRID as f64 * 2.0 - 1.0) * p.half_u;
                    let b = ((j as f64 + 0.5) / GRID as f64 * 2.0 - 1.0) * p.half_v;
                    f(&Element {
                        at: p.center + p.axis_u * a + p.axis_v * b,
                        normal,
                        area,
                        two_sided: face.two_sided,
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_cover_the_surface_with_outward_normals() {
        let b = Shape {
            kind: ShapeKind::Box,
            size: Vector3::new(0.3, 0.4, 0.2),
            mass: 0.1,
        };
        let (mut area, mut outward) = (0.0, true);
        b.for_each_element(|e| {
            area += e.area;
            outward &= e.at.dot(&e.normal) > 0.0;
        });
        let expect = 2.0 * (0.3 * 0.4 + 0.4 * 0.2 + 0.3 * 0.2);
        assert!((area - expect).abs() < 1e-12 && outward);
        let mut plate_area = 0.0;
        Shape::PAPER_PLATE.for_each_element(|e| plate_area += e.area);
        assert!((plate_area - 0.15).abs() < 1e-12);
    }
}
