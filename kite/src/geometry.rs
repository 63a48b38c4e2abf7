//! Kite geometry in the design (body-before-centring) frame: primitive
//! frames, corners, frame rods, covered faces, and the paper's rule that no
//! two primitives may overlap along the wind direction.

use crate::rod_end::RodEnd;
use crate::spec::{Kind, KiteSpec, PrimitiveSpec, RodSpec};
use anyhow::{anyhow, bail, Result};
use nalgebra::{Matrix3, Rotation3, Vector2, Vector3};

/// `Q` from rotations about x, then y, then z (fixed axes), degrees.
pub fn rotation_from_degrees(angles: &[f64; 3]) -> Matrix3<f64> {
    let [x, y, z] = angles.map(f64::to_radians);
    *Rotation3::from_euler_angles(x, y, z).matrix()
}

/// A straight rod, design frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    /// One end, m.
    pub a: Vector3<f64>,
    /// Other end, m.
    pub b: Vector3<f64>,
    /// Diameter, m.
    pub diameter: f64,
    /// Where it comes from, e.g. `front edge 3` or `rod[0]`.
    pub label: String,
}

impl Rod {
    /// Length, m.
    pub fn length(&self) -> f64 {
        (self.b - self.a).norm()
    }
}

/// A covered rectangle, design frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Centre, m.
    pub center: Vector3<f64>,
    /// Half-edge vectors, m (the rectangle is `center ± u ± v`).
    pub u: Vector3<f64>,
    /// Second half-edge vector, m.
    pub v: Vector3<f64>,
    /// Which primitive and face, e.g. `front +x`.
    pub label: String,
}

impl Panel {
    /// Area, m².
    pub fn area(&self) -> f64 {
        4.0 * self.u.cross(&self.v).norm()
    }
    /// Edge lengths, m.
    pub fn edges(&self) -> (f64, f64) {
        (2.0 * self.u.norm(), 2.0 * self.v.norm())
    }
}

/// The design-frame point of primitive `p` at unit-box coordinates
/// `unit` (each component in `[-1, 1]`: `±1` a face, so `(±1, ±1, ±1)`
/// a corner): `position + Q_p (unit ∘ size/2)`, m. The one owner of a
/// primitive's corner geometry: corners, frame edges and named rod ends
/// ([`crate::rod_end`]) all come from here.
pub fn point_on(p: &PrimitiveSpec, unit: &Vector3<f64>) -> Vector3<f64> {
    let q = rotation_from_degrees(&p.rotation);
    let h = Vector3::from(p.size) / 2.0;
    Vector3::from(p.position) + q * unit.component_mul(&h)
}

/// The eight (or four, for `l_z = 0`) corners of a primitive, design frame.
pub fn corners(p: &PrimitiveSpec) -> Vec<Vector3<f64>> {
    let zs: &[f64] = if p.size[2] > 0.0 {
        &[-1.0, 1.0]
    } else {
        &[0.0]
    };
    let mut out = Vec::new();
    for &sx in &[-1.0, 1.0] {
        for &sy in &[-1.0, 1.0] {
            for &sz in zs {
                out.push(point_on(p, &Vector3::new(sx, sy, sz)));
            }
        }
    }
    out
}

/// A rod end's design-frame point, m: a bare point as written, a named
/// corner or edge point resolved from its primitive's current size,
/// position and rotation. Errors name `field` (`rod[2].from...`).
pub fn end_point(spec: &KiteSpec, end: &RodEnd, field: &str) -> Result<Vector3<f64>> {
    match end {
        RodEnd::Point(p) => Ok(Vector3::from(*p)),
        RodEnd::On(f) => {
            let p = spec
                .primitives
                .iter()
                .find(|p| p.name == f.primitive)
                .ok_or_else(|| {
                    anyhow!("{field}.primitive: no primitive named {:?}", f.primitive)
                })?;
            Ok(point_on(p, &f.unit(&p.size, field)?))
        }
    }
}

/// Both ends of `[[rod]]` number `i`, design frame, m.
pub fn rod_ends(spec: &KiteSpec, i: usize, r: &RodSpec) -> Result<[Vector3<f64>; 2]> {
    Ok([
        end_point(spec, &r.from, &format!("rod[{i}].from"))?,
        end_point(spec, &r.to, &format!("rod[{i}].to"))?,
    ])
}

/// The frame rods of a box (12 edges) or plate (4 edges).
pub fn frame_rods(p: &PrimitiveSpec, diameter: f64) -> Vec<Rod> {
    if p.kind == Kind::Object || !p.frame {
        return Vec::new();
    }
    let pts = corners(p);
    let mut rods = Vec::new();
    for (i, a) in pts.iter().enumerate() {
        for b in pts.iter().skip(i + 1) {
            // Edges join corners that differ in exactly one local axis.
            let q = rotation_from_degrees(&p.rotation);
            let d = q.transpose() * (b - a);
            let differing = d.iter().filter(|x| x.abs() > 1e-9).count();
            if differing == 1 {
                let label = format!("{} edge {}", p.name, rods.len() + 1);
                rods.push(Rod {
                    a: *a,
                    b: *b,
                    diameter,
                    label,
                });
            }
        }
    }
    rods
}

/// The covered faces: a box's four closed faces (±x, ±z), a plate's one.
pub fn panels(p: &PrimitiveSpec) -> Vec<Panel> {
    let q = rotation_from_degrees(&p.rotation);
    let c = Vector3::from(p.position);
    let [hx, hy, hz] = p.size.map(|s| s / 2.0);
    let ex = q * Vector3::x();
    let ey = q * Vector3::y();
    let ez = q * Vector3::z();
    let face = |center: Vector3<f64>, u: Vector3<f64>, v: Vector3<f64>, tag: &str| Panel {
        center,
        u,
        v,
        label: format!("{} {tag}", p.name),
    };
    match p.kind {
        Kind::Box => vec![
            face(c + ex * hx, ey * hy, ez * hz, "+x"),
            face(c - ex * hx, ey * hy, ez * hz, "-x"),
            face(c + ez * hz, ex * hx, ey * hy, "+z"),
            face(c - ez * hz, ex * hx, ey * hy, "-z"),
        ],
        Kind::Plate => vec![face(c, ex * hx, ey * hy, "face")],
        Kind::Object => Vec::new(),
    }
}

/// Every rod of the kite: primitive frames, then `[[rod]]`s (their named
/// ends resolved).
pub fn all_rods(spec: &KiteSpec) -> Result<Vec<Rod>> {
    let d = spec.materials.rod_diameter;
    let mut rods: Vec<Rod> = spec
        .primitives
        .iter()
        .flat_map(|p| frame_rods(p, d))
        .collect();
    for (i, r) in spec.rods.iter().enumerate() {
        let [a, b] = rod_ends(spec, i, r)?;
        if (b - a).norm() < 1e-3 {
            bail!("rod[{i}]: `from` and `to` are the same point");
        }
        rods.push(Rod {
            a,
            b,
            diameter: r.diameter.unwrap_or(d),
            label: format!("rod[{i}]"),
        });
    }
    Ok(rods)
}

/// Pairs of primitives whose silhouettes, seen along the wind direction
/// `wind_body` (body frame), overlap by more than `tolerance` m: the paper
/// forbids these because the upstream one would shadow the other (no
/// interference model, §7).
pub fn wind_overlaps(
    spec: &KiteSpec,
    wind_body: &Vector3<f64>,
    tolerance: f64,
) -> Vec<(usize, usize)> {
    let w = wind_body.normalize();
    let helper = if w.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = w.cross(&helper).normalize();
    let e2 = w.cross(&e1);
    let hulls: Vec<Vec<Vector2<f64>>> = spec
        .primitives
        .iter()
        .map(|p| {
            let pts: Vec<Vector2<f64>> = corners(p)
                .iter()
                .map(|c| Vector2::new(c.dot(&e1), c.dot(&e2)))
                .collect();
            convex_hull(pts)
        })
        .collect();
    let mut out = Vec::new();
    for i in 0..hulls.len() {
        for j in i + 1..hulls.len() {
            if overlap_depth(&hulls[i], &hulls[j]) > tolerance {
                out.push((i, j));
            }
        }
    }
    out
}

/// Andrew's monotone chain; counter-clockwise, no repeated end point.
pub fn convex_hull(mut pts: Vec<Vector2<f64>>) -> Vec<Vector2<f64>> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup_by(|a, b| (*a - *b).norm() < 1e-12);
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>| {
        (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
    };
    let mut hull: Vec<Vector2<f64>> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vector2<f64>>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// Smallest penetration depth of two convex polygons over the separating
/// axis candidates (edge normals of both); negative when they are apart.
/// Degenerate polygons (a plate seen edge-on) are segments: their
/// direction's normal is also tested.
pub fn overlap_depth(a: &[Vector2<f64>], b: &[Vector2<f64>]) -> f64 {
    let mut axes = Vec::new();
    for poly in [a, b] {
        let n = poly.len();
        for i in 0..n {
            let e = poly[(i + 1) % n] - poly[i];
            if e.norm() > 1e-12 {
                axes.push(Vector2::new(-e.y, e.x).normalize());
                axes.push(e.normalize());
            }
        }
    }
    if axes.is_empty() {
        return -1.0;
    }
    axes.iter()
        .map(|ax| {
            let (amin, amax) = extent(a, ax);
            let (bmin, bmax) = extent(b, ax);
            amax.min(bmax) - amin.max(bmin)
        })
        .fold(f64::INFINITY, f64::min)
}

fn extent(poly: &[Vector2<f64>], axis: &Vector2<f64>) -> (f64, f64) {
    poly.iter()
        .map(|p| p.dot(axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        })
}
