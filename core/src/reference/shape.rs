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

/// The largest thickness, relative to the smaller of its other two
/// extents, of a body that [`Shape::of_body`] calls a plate: the paper's
/// foam plate is 0.07.
pub const PLATE_THINNESS: f64 = 0.1;

/// How far below zero, relative to the sum of the three, a squared
/// extent from rounded moments may fall and still be read as zero (a
/// lamina) by [`Shape::of_body`]: moments given to three significant
/// figures err by up to half a per cent each.
pub const LAMINA_TOLERANCE: f64 = 1e-2;

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

    /// The uniform solid box with a body's `mass` (kg) and moments of
    /// inertia `moments` (kg m², about body x, y, z): the inverse of
    /// [`Self::inertia`], `x² = 6 (I_yy + I_zz - I_xx) / M` and cyclic (the
    /// body's equivalent box; for a uniform plate or box, the shape itself).
    /// A [`ShapeKind::Plate`] when z is its thinnest extent and at most
    /// [`PLATE_THINNESS`] of the smaller of x and y (a plate's faces lie in
    /// x-y; a rod is a box). A lamina's moments give a zero thickness,
    /// which moments rounded to three figures can push a little below zero:
    /// a squared extent down to [`LAMINA_TOLERANCE`] of their sum below zero
    /// is a zero extent (a zero-thickness box is a two-sided plate in
    /// whichever plane it lies). `None` when the moments are no box's (one
    /// clearly exceeds the sum of the other two: no mass distribution has
    /// such moments) or a number is not finite and positive. Only the
    /// moments along the axes are used: products of inertia are not a
    /// shape's.
    pub fn of_body(mass: f64, moments: &Vector3<f64>) -> Option<Shape> {
        let (a, b, c) = (moments.x, moments.y, moments.z);
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(mass) && positive(a) && positive(b) && positive(c)) {
            return None;
        }
        let squared = Vector3::new(b + c - a, a + c - b, a + b - c) * (6.0 / mass);
        let tolerance = LAMINA_TOLERANCE * squared.sum();
        if squared.min() < -tolerance {
            return None;
        }
        let size = squared.map(|x| libm::sqrt(x.max(0.0)));
        let kind = if size.z <= PLATE_THINNESS * size.x.min(size.y) {
            ShapeKind::Plate
        } else {
            ShapeKind::Box
        };
        Some(Shape { kind, size, mass })
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
    #![allow(clippy::expect_used)]
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

    /// The equivalent box of a uniform plate or box is that shape, a plate
    /// only when thin along z; moments no mass distribution has give none.
    #[test]
    fn a_body_gives_back_its_box() {
        let moments = |s: &Shape| s.inertia().diagonal();
        let plate = Shape::PAPER_PLATE;
        let back = Shape::of_body(plate.mass, &moments(&plate)).expect("a plate");
        assert_eq!(back.kind, ShapeKind::Plate);
        assert!((back.size - plate.size).norm() < 1e-12);
        let cube = Shape {
            kind: ShapeKind::Box,
            size: Vector3::new(0.2, 0.3, 0.25),
            mass: 0.5,
        };
        let back = Shape::of_body(cube.mass, &moments(&cube)).expect("a box");
        assert_eq!(back.kind, ShapeKind::Box);
        assert!((back.size - cube.size).norm() < 1e-12);
        // Thin along x, a rod, a thick slab: boxes (a plate's faces are
        // x-y, and thin against both of them).
        for size in [[0.02, 0.5, 0.3], [0.3, 0.02, 0.02], [0.3, 0.5, 0.06]] {
            let s = Shape {
                size: Vector3::from(size),
                ..plate
            };
            let back = Shape::of_body(plate.mass, &moments(&s)).expect("a box");
            assert_eq!(back.kind, ShapeKind::Box, "{size:?}");
            assert!((back.size - s.size).norm() < 1e-12);
        }
        // A lamina (zero thickness) is a plate, also from moments rounded
        // to three figures (I_zz 1.65e-6 for 1.64e-6).
        let lamina = Vector3::new(1.0, 2.0, 3.0) * 1e-4;
        let back = Shape::of_body(0.1, &lamina).expect("a lamina");
        assert_eq!(back.kind, ShapeKind::Plate);
        assert!(back.size.z < 1e-9);
        let card = Shape::of_body(0.002, &Vector3::new(8.2e-7, 8.2e-7, 1.65e-6)).expect("a card");
        assert_eq!(card.kind, ShapeKind::Plate);
        assert!((card.size.x - 0.0701).abs() < 1e-3 && card.size.z == 0.0);
        assert_eq!(Shape::of_body(0.1, &Vector3::new(1.0, 1.0, 5.0)), None);
        assert_eq!(Shape::of_body(0.0, &Vector3::new(1.0, 1.0, 1.0)), None);
        assert_eq!(Shape::of_body(0.1, &Vector3::new(f64::NAN, 1.0, 1.0)), None);
    }
}
