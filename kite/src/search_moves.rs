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

use crate::design_params::{kind, ALONG, HEADING, PER_PRIMITIVE, WHOLE};
use crate::geometry::corners;
pub use crate::multi_start::Move;
use crate::multi_start::Plan;
use crate::objective::{Score, Search, STARTS};
use crate::spec::KiteSpec;

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

/// Each parameter alone, in the order `order` (the search takes the first
/// move that improves, so the order is its path).
pub fn singles(order: impl IntoIterator<Item = usize>) -> Vec<Move> {
    order.into_iter().map(|k| vec![(k, 1.0)]).collect()
}

/// For each mirror pair (primitive parameters from `first`, `per` each,
/// in the order yaw, roll, shift across, shift along; `n` parameters in
/// all) the mirrored joint moves: yaws and rolls opposite (a mirrored
/// turn), shifts across opposite (spread), shifts along equal.
pub fn pair_moves(n: usize, pairs: &[(usize, usize)], first: usize, per: usize) -> Vec<Move> {
    const MIRROR: [f64; 4] = [-1.0, -1.0, -1.0, 1.0];
    let mut out = Vec::new();
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

/// A coarse scan of the pair moves from `x`: each pair move at a half
/// and a whole of its lead parameter's `reach` either way (both wings
/// moved aft behind the cell, both spread, both turned). Why: such a
/// change is several compass steps long and the objective need not rise
/// along the way (winged-box's wings 0.4 m aft fly, 0.3 m aft the kite
/// still diverges: BENCHMARKS, issue 17), so one of the searches starts
/// from the best point of this scan.
pub fn pair_scan(x: &[f64], pair_moves: &[Move], reach: &[f64]) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for m in pair_moves {
        let Some(r) = m.first().and_then(|&(lead, _)| reach.get(lead)) else {
            continue;
        };
        for a in [-1.0, -0.5, 0.5, 1.0] {
            let mut t = x.to_vec();
            for &(k, unit) in m {
                if let Some(v) = t.get_mut(k) {
                    *v += a * unit * r;
                }
            }
            out.push(t);
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

/// The searches ([`crate::multi_start`]) from `x` (the best quarter turn, scored
/// `score`), each with its own move order and start, so that no one path
/// decides the result (BENCHMARKS, issue 17: each order turned a
/// different subset of the crashing designs into flyers):
/// 1. every parameter in the file's order (pitch, offset, heading, then
///    each primitive's yaw, roll, shift across and along), then the mirror
///    pairs;
/// 2. the trim and the turns first, the heading and the shifts along the
///    kite last (the larger, structural moves only when no trim or turn
///    improves), then the mirror pairs;
/// 3. with mirror pairs: the pair moves first, from the best point of a
///    coarse scan of them ([`pair_scan`], evaluated here,
///    at most a tenth of the `budget`); without: the primitives' moves
///    first, last primitive first, the kite's trim last.
pub(crate) fn plans(
    search: &mut Search,
    x: &[f64],
    score: &Score,
    reach: &[f64],
    bounds: &[(f64, f64)],
    budget: usize,
) -> Vec<Plan> {
    let n = x.len();
    let pairs = pair_moves(n, &mirror_pairs(search.base), WHOLE, PER_PRIMITIVE);
    let with_pairs = |mut singles: Vec<Move>| {
        singles.extend(pairs.iter().cloned());
        singles
    };
    let late = |k: &usize| matches!(kind(*k), HEADING | ALONG);
    let (early, structural): (Vec<usize>, Vec<usize>) = (0..n).partition(|k| !late(k));
    let mut plans = vec![
        Plan {
            name: "file order, then mirror pairs".into(),
            start: x.to_vec(),
            moves: with_pairs(singles(0..n)),
        },
        Plan {
            name: "trim and turns first, heading and shifts along last, then mirror pairs".into(),
            start: x.to_vec(),
            moves: with_pairs(singles(early.into_iter().chain(structural))),
        },
    ];
    let reversed = singles((WHOLE..n).rev().chain(0..WHOLE));
    if pairs.is_empty() {
        plans.push(Plan {
            name: "primitives first (last first), trim last".into(),
            start: x.to_vec(),
            moves: reversed,
        });
        return plans;
    }
    let (mut best_x, mut best) = (x.to_vec(), score.objective);
    let inside = |t: &[f64]| t.iter().zip(bounds).all(|(v, (lo, hi))| v >= lo && v <= hi);
    let scan = pair_scan(x, &pairs, reach);
    for t in scan.into_iter().filter(|t| inside(t)).take(budget / 10) {
        if let Some(s) = search.evaluate(STARTS, &t) {
            if s.objective > best + 1e-6 {
                (best_x, best) = (t, s.objective);
            }
        }
    }
    let mut moves = pairs.clone();
    moves.extend(reversed);
    plans.push(Plan {
        name: "mirror pairs first, from the best of a coarse pair scan".into(),
        start: best_x,
        moves,
    });
    plans
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
        let m = pair_moves(3 + 3 * 4, &mirror_pairs(&spec), 3, 4);
        assert_eq!(m.len(), 4);
        // The scan moves each pair move a half and a whole reach either
        // way: both wings aft by the whole reach moves both along-shifts.
        let reach = vec![1.0; 15];
        let scan = pair_scan(&[0.0; 15], &m, &reach);
        assert_eq!(scan.len(), 4 * 4);
        assert!(scan.iter().any(|x| x[10] == -1.0 && x[14] == -1.0));
        assert!(scan.iter().any(|x| x[7] == 0.5 && x[11] == -0.5));
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
