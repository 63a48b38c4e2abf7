//! The moves of `kite optimise`'s compass search ([`crate::optimise`]):
//! one parameter at a time, and for each mirror pair of primitives the
//! pair moved together, mirrored.
//!
//! Why pair moves: most kites are built left-right symmetric, and the
//! changes that make such a kite fly keep the symmetry — both wings moved
//! aft behind the cell, both tilted into more dihedral, both spread. Moved
//! one at a time, the first half of such a change makes the kite lopsided
//! and scores worse, so a compass search never takes it (measured on
//! winged-box: its wings 0.4 m aft with the string offset at 0.1-0.2 m is
//! `stable` and flies on seeds 1-3; the single-primitive moves never get
//! there, BENCHMARKS, issue 17). The single moves stay, so asymmetric
//! designs (Fig. 15) are searched as before.

use crate::geometry::corners;
use crate::spec::KiteSpec;

/// One search direction: `(parameter, unit)` pairs, moved by the step of
/// the first parameter's kind.
pub type Move = Vec<(usize, f64)>;

/// How close two primitives must be to each other's mirror image across
/// the design's x-z plane to count as a pair, m (or m of size).
const MIRROR_TOLERANCE: f64 = 1e-3;

/// Mirror pairs `(i, j)`, `i < j`: same kind and size, and `j` at `i`'s
/// position mirrored across the design x-z plane (`y -> -y`), off that
/// plane. Each primitive is in at most one pair.
pub fn mirror_pairs(spec: &KiteSpec) -> Vec<(usize, usize)> {
    let near = |a: &[f64; 3], b: &[f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < MIRROR_TOLERANCE);
    let mut used = vec![false; spec.primitives.len()];
    let mut pairs = Vec::new();
    for (i, a) in spec.primitives.iter().enumerate() {
        for (j, b) in spec.primitives.iter().enumerate().skip(i + 1) {
            let mirrored = [a.position[0], -a.position[1], a.position[2]];
            if used[i] || used[j] || a.position[1].abs() < MIRROR_TOLERANCE {
                continue;
            }
            if a.kind == b.kind && near(&a.size, &b.size) && near(&mirrored, &b.position) {
                (used[i], used[j]) = (true, true);
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The compass search's moves over `n` parameters: each parameter alone,
/// then for each mirror pair (primitive parameters from `first`, `per`
/// each, in the order yaw, roll, shift across, shift along) the mirrored
/// joint moves: yaws and rolls opposite (a mirrored turn), shifts across
/// opposite (spread), shifts along equal.
pub fn moves(n: usize, pairs: &[(usize, usize)], first: usize, per: usize) -> Vec<Move> {
    let mut out: Vec<Move> = (0..n).map(|k| vec![(k, 1.0)]).collect();
    const MIRROR: [f64; 4] = [-1.0, -1.0, -1.0, 1.0];
    for &(i, j) in pairs {
        for (q, sign) in MIRROR.iter().enumerate().take(per) {
            let (a, b) = (first + i * per + q, first + j * per + q);
            if a < n && b < n {
                out.push(vec![(a, 1.0), (b, *sign)]);
            }
        }
    }
    out
}

/// The kite's length along the design x axis (the primitives' corners;
/// an object's bounding box), m: how far the search may move a primitive
/// along the kite — far enough to put a wing behind the cell it flies
/// beside, scaled to the kite (a fixed reach would be too far for a small
/// kite and too short for a long one).
pub fn length(spec: &KiteSpec) -> f64 {
    let xs = spec
        .primitives
        .iter()
        .flat_map(|p| corners(p).into_iter().map(|c| c[0]));
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    });
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KITE: &str = r#"
name = "t"
[[primitive]]
name = "cell"
kind = "box"
size = [0.3, 0.36, 0.3]
position = [0.1, 0.0, 0.0]
rotation = [0.0, 0.0, -90]
[[primitive]]
name = "l"
kind = "plate"
size = [0.28, 0.4, 0.0]
position = [-0.05, -0.38, 0.05]
rotation = [0.0, -15, -90]
[[primitive]]
name = "r"
kind = "plate"
size = [0.28, 0.4, 0.0]
position = [-0.05, 0.38, 0.05]
rotation = [0.0, 15, -90]
"#;

    #[test]
    fn wings_are_a_pair_and_move_mirrored() {
        let mut spec = KiteSpec::parse(KITE).expect("parses");
        assert_eq!(mirror_pairs(&spec), vec![(1, 2)]);
        let m = moves(3 + 3 * 4, &mirror_pairs(&spec), 3, 4);
        assert_eq!(m.len(), 15 + 4);
        // yaw of l (3 + 4) with yaw of r (3 + 8) opposite; along equal.
        assert!(m.contains(&vec![(7, 1.0), (11, -1.0)]));
        assert!(m.contains(&vec![(10, 1.0), (14, 1.0)]));
        // A wing of another size, or not at the mirror place, is no pair.
        spec.primitives[2].size[1] = 0.5;
        assert!(mirror_pairs(&spec).is_empty());
        spec.primitives[2].size[1] = 0.4;
        spec.primitives[2].position[0] = 0.0;
        assert!(mirror_pairs(&spec).is_empty());
    }

    #[test]
    fn length_spans_the_primitives_along_x() {
        let spec = KiteSpec::parse(KITE).expect("parses");
        // The cell's open axis (0.36) and the wings' 0.4 lie along x.
        let want = (0.1 + 0.18) - (-0.05 - 0.2);
        assert!((length(&spec) - want).abs() < 1e-9, "{}", length(&spec));
    }
}
