//! The parameters `kite optimise` searches ([`crate::optimise`]) and how
//! they change a kite file: pitch, string offset and heading of the whole
//! kite, and per primitive a yaw and a roll turn and shifts across the
//! wind and along the kite; how far and in what first steps each moves.

use crate::connect::move_primitive;
use crate::geometry::rotation_from_degrees;
use crate::spec::{KiteSpec, StringSpec};
use nalgebra::Vector3;

/// How far each kind of parameter may move from the search's start:
/// pitch 20°, offset 0.3 m (about a kite's size: further and the bridle
/// would leave the kite), the kite's heading 45° (with the quarter-turn
/// starts of [`quarter_turns`] every heading is within reach); per
/// primitive yaw 45°, roll 30°, 0.25 m across the wind, and along the
/// kite (design x) the kite's own length ([`crate::search_moves::length`]; the
/// last entry here is not used).
pub(crate) const REACH: [f64; 7] = [20.0, 0.3, 45.0, 45.0, 30.0, 0.25, f64::NAN];

/// Index of the heading in [`REACH`] and [`STEP`].
pub(crate) const HEADING: usize = 2;

/// Index of the shift along the kite in [`REACH`] and [`STEP`].
pub(crate) const ALONG: usize = 6;

/// First steps, same order as [`REACH`].
pub(crate) const STEP: [f64; 7] = [4.0, 0.03, 10.0, 10.0, 10.0, 0.05, 0.05];

/// Parameters of the whole kite: pitch, string offset, heading.
pub(crate) const WHOLE: usize = 3;

/// Parameters per primitive: yaw, roll, shift across the wind, shift
/// along the kite.
pub(crate) const PER_PRIMITIVE: usize = 4;

/// Which kind (index into [`REACH`]) parameter `k` is.
pub(crate) fn kind(k: usize) -> usize {
    if k < WHOLE {
        k
    } else {
        WHOLE + (k - WHOLE) % PER_PRIMITIVE
    }
}

/// The parameters: pitch (deg), offset (m), heading (the orientation's
/// turn about the vertical, deg), and per primitive a yaw and a roll
/// change (deg) and a shift along the design frame's y (across the wind)
/// and x (along the kite), m, applied to the file's spec.
pub(crate) fn apply(base: &KiteSpec, x: &[f64]) -> KiteSpec {
    let mut s = base.clone();
    s.orientation[1] = x[0];
    s.orientation[2] = x[2];
    s.string = StringSpec {
        gamma: None,
        offset: Some(x[1]),
        length: base.string.length,
    };
    for (i, [yaw, roll, dy, dx]) in per_primitive(x) {
        if yaw != 0.0 || roll != 0.0 || dy != 0.0 || dx != 0.0 {
            let turn =
                rotation_from_degrees(&[0.0, 0.0, yaw]) * rotation_from_degrees(&[roll, 0.0, 0.0]);
            move_primitive(&mut s, i, &turn, &Vector3::new(dx, dy, 0.0));
        }
    }
    s
}

/// Each primitive's index and parameters (yaw, roll, shift across,
/// shift along) in `x`.
pub(crate) fn per_primitive(x: &[f64]) -> impl Iterator<Item = (usize, [f64; PER_PRIMITIVE])> + '_ {
    x.get(WHOLE..)
        .unwrap_or(&[])
        .chunks_exact(PER_PRIMITIVE)
        .enumerate()
        .filter_map(|(i, p)| Some((i, p.try_into().ok()?)))
}

/// The file's parameters with the kite turned by 0, 90, 180 and 270°
/// about the vertical: which face of the kite meets the wind is the
/// builder's choice (where the bridle is tied), and a design flown on
/// the wrong face (a box kite's closed side into the wind: the string
/// pushes) has no neighbour within a compass step that is better — the
/// objective is flat there. The search starts from the best of the four
/// and then moves the heading by up to [`REACH`] (45°), so every heading
/// is within reach.
pub(crate) fn quarter_turns(x0: &[f64]) -> Vec<Vec<f64>> {
    (0..4)
        .map(|q| {
            let mut x = x0.to_vec();
            x[2] = wrap_degrees(x0[2] + 90.0 * f64::from(q));
            x
        })
        .collect()
}

/// `a` in (-180°, 180°].
fn wrap_degrees(a: f64) -> f64 {
    let w = a.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}
