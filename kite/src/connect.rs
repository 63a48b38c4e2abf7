//! Which parts of the frame hold together: a `[[rod]]` end naming a
//! primitive's corner or edge ([`crate::rod_end`]) joins the rod to that
//! primitive; an old-style end given by coordinates joins the primitive
//! it sits on (within [`CONTACT`] of one of its frame edges, or inside
//! an object's bounding box); rods join where an end meets another rod,
//! and primitives join where a corner of one lies on an edge of the
//! other. The frame is connected when all of it is one
//! piece — a kite whose cells are not tied together falls apart on the
//! line. `kite optimise` turns rods with the primitive they sit on and
//! refuses trials that come apart.

use crate::geometry::{corners, end_point, frame_rods, rotation_from_degrees};
use crate::rod_end::RodEnd;
use crate::spec::{Kind, KiteSpec, PrimitiveSpec};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// How close a rod end must be to count as sitting on an edge, m: a
/// socket's reach (the 2 mm rod in a socket a few mm deep).
pub const CONTACT: f64 = 0.01;

/// Distance from `p` to the segment `a`-`b`, m.
fn segment_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + ab * t - p).norm()
}

/// Whether `point` sits on primitive `p`'s frame (or in an object).
fn touches(p: &PrimitiveSpec, point: &Vector3<f64>) -> bool {
    if p.kind == Kind::Object || !p.frame {
        let q = rotation_from_degrees(&p.rotation);
        let local = q.transpose() * (point - Vector3::from(p.position));
        return (0..3).all(|k| local[k].abs() <= p.size[k] / 2.0 + CONTACT);
    }
    frame_rods(p, 0.0)
        .iter()
        .any(|r| segment_distance(point, &r.a, &r.b) < CONTACT)
}

/// The primitive a rod end sits on, if any (the first).
fn holder(spec: &KiteSpec, point: &Vector3<f64>) -> Option<usize> {
    spec.primitives.iter().position(|p| touches(p, point))
}

/// The primitives a rod end at `point` joins: the one it names, or (an
/// end given by coordinates) every one it sits on.
fn holders(spec: &KiteSpec, end: &RodEnd, point: &Vector3<f64>) -> Vec<usize> {
    match end {
        RodEnd::On(f) => spec
            .primitives
            .iter()
            .position(|p| p.name == f.primitive)
            .into_iter()
            .collect(),
        RodEnd::Point(_) => (spec.primitives.iter().enumerate())
            .filter(|(_, p)| touches(p, point))
            .map(|(i, _)| i)
            .collect(),
    }
}

/// The piece each part of the frame belongs to: one label per primitive
/// (first) and per `[[rod]]` (after); equal labels are one rigid piece.
fn piece_labels(spec: &KiteSpec) -> Vec<usize> {
    let n = spec.primitives.len();
    let mut parent: Vec<usize> = (0..n + spec.rods.len()).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let join = |p: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (root(p, a), root(p, b));
        p[ra] = rb;
    };
    for (i, a) in spec.primitives.iter().enumerate() {
        for (j, b) in spec.primitives.iter().enumerate().skip(i + 1) {
            if corners(a).iter().any(|c| touches(b, c)) || corners(b).iter().any(|c| touches(a, c))
            {
                join(&mut parent, i, j);
            }
        }
    }
    // A named end that no longer resolves (its primitive removed) joins
    // nothing.
    let ends: Vec<[Option<Vector3<f64>>; 2]> = spec
        .rods
        .iter()
        .map(|r| [&r.from, &r.to].map(|e| end_point(spec, e, "rod").ok()))
        .collect();
    for (k, r) in spec.rods.iter().enumerate() {
        for (end, point) in [&r.from, &r.to].into_iter().zip(ends[k]) {
            let Some(pt) = point else { continue };
            for i in holders(spec, end, &pt) {
                join(&mut parent, n + k, i);
            }
            for (m, other) in ends.iter().enumerate().filter(|(m, _)| *m != k) {
                if let [Some(oa), Some(ob)] = other {
                    if segment_distance(&pt, oa, ob) < CONTACT {
                        join(&mut parent, n + k, n + m);
                    }
                }
            }
        }
    }
    (0..parent.len()).map(|i| root(&mut parent, i)).collect()
}

/// Number of separate pieces of the frame (primitives and rods).
pub fn pieces(spec: &KiteSpec) -> usize {
    let mut roots = piece_labels(spec);
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}

/// The parts not joined to the first primitive's piece, by name
/// (`primitive "rear"`, `rod[3]`): what `kite check` names when it
/// refuses a frame that would fall apart on the line.
pub fn unjoined(spec: &KiteSpec) -> Vec<String> {
    let labels = piece_labels(spec);
    let Some(&main) = labels.first() else {
        return Vec::new();
    };
    let n = spec.primitives.len();
    labels
        .iter()
        .enumerate()
        .filter(|(_, l)| **l != main)
        .map(|(i, _)| match spec.primitives.get(i) {
            Some(p) => format!("primitive {:?}", p.name),
            None => format!("rod[{}]", i - n),
        })
        .collect()
}

/// Turns primitive `i` by `turn` about its centre and then shifts it by
/// `shift` (design frame, m). Rod ends naming it follow by themselves
/// (they are resolved from its pose); old-style coordinate ends sitting
/// on it are carried along, so rods stay in their sockets (a rod joining
/// it to another part stretches or swings with it). Rotations are about fixed axes, so the
/// new `Q' = turn Q`, written back as x-y-z angles.
pub fn move_primitive(spec: &mut KiteSpec, i: usize, turn: &Matrix3<f64>, shift: &Vector3<f64>) {
    let Some(p) = spec.primitives.get(i).cloned() else {
        return;
    };
    let c = Vector3::from(p.position);
    let moved = |end: [f64; 3]| -> [f64; 3] {
        let v = Vector3::from(end);
        (c + shift + turn * (v - c)).into()
    };
    let ends: Vec<[bool; 2]> = spec
        .rods
        .iter()
        .map(|r| {
            [&r.from, &r.to].map(|e| match e {
                RodEnd::Point(p) => holder(spec, &Vector3::from(*p)) == Some(i),
                RodEnd::On(_) => false,
            })
        })
        .collect();
    for (r, carry) in spec.rods.iter_mut().zip(ends) {
        for (end, c) in [&mut r.from, &mut r.to].into_iter().zip(carry) {
            if let (RodEnd::Point(p), true) = (&mut *end, c) {
                *p = moved(*p);
            }
        }
    }
    if let Some(q) = spec.primitives.get_mut(i) {
        let r = Rotation3::from_matrix_unchecked(turn * rotation_from_degrees(&q.rotation));
        let (x, y, z) = r.euler_angles();
        q.rotation = [x.to_degrees(), y.to_degrees(), z.to_degrees()];
        q.position = (c + shift).into();
    }
}

/// Removes primitive `i`; rod ends naming it are first frozen at their
/// current points (old-style coordinate ends), so the rods stay where
/// they were and `kite check` reports them if nothing holds them.
pub fn remove_primitive(spec: &mut KiteSpec, i: usize) {
    let Some(name) = spec.primitives.get(i).map(|p| p.name.clone()) else {
        return;
    };
    let frozen: Vec<[Option<[f64; 3]>; 2]> = spec
        .rods
        .iter()
        .map(|r| {
            [&r.from, &r.to].map(|e| {
                (e.primitive() == Some(name.as_str()))
                    .then(|| end_point(spec, e, "rod").ok().map(Into::into))
                    .flatten()
            })
        })
        .collect();
    for (r, f) in spec.rods.iter_mut().zip(frozen) {
        for (end, point) in [&mut r.from, &mut r.to].into_iter().zip(f) {
            if let Some(p) = point {
                *end = RodEnd::Point(p);
            }
        }
    }
    spec.primitives.remove(i);
}

/// Rods with an end given by coordinates, not by a named corner or edge:
/// `kite check` reports them (old files are accepted; naming the ends
/// makes them follow their primitive when it moves).
pub fn coordinate_rods(spec: &KiteSpec) -> Vec<String> {
    spec.rods
        .iter()
        .enumerate()
        .filter(|(_, r)| [&r.from, &r.to].iter().any(|e| e.primitive().is_none()))
        .map(|(k, _)| format!("rod[{k}]"))
        .collect()
}

/// Turns primitive `i` by `degrees` about the design frame's z axis
/// through its centre (see [`move_primitive`]).
pub fn turn_primitive(spec: &mut KiteSpec, i: usize, degrees: f64) {
    let turn = rotation_from_degrees(&[0.0, 0.0, degrees]);
    move_primitive(spec, i, &turn, &Vector3::zeros());
}
