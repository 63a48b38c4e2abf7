//! Measured lift and drag of a thin flat plate of aspect ratio 2 at
//! Reynolds number 100, 0-90° angle of attack, coefficients on planform
//! area: Dickson's oil-tank experiment as reported by Taira et al. (2007)
//! and Taira (2008), from the PetIBM project's data files (BSD-3-Clause;
//! the same numbers as `data/reference/*.dat`, checked by a test in the
//! validation crate). The OmniAD paper's Fig. 13 compares its fitted plate
//! with Taira & Colonius (2009) in the same way. Re 100 is far below a
//! falling foam plate's (~10⁵): these curves are a measured reference of
//! the right shape, not the paper plate's own aerodynamics.
//!
//! [`normal_and_axial`] turns them into the body-frame normal and chordwise
//! force coefficients a plate model needs, by linear interpolation.

/// (angle of attack, deg; drag coefficient C_D).
pub const DRAG: [(f64, f64); 62] = [
    (1.07856, 0.39189),
    (2.15712, 0.38176),
    (3.11585, 0.38851),
    (5.03329, 0.38176),
    (6.11185, 0.39527),
    (7.19041, 0.40878),
    (8.02929, 0.39865),
    (9.22770, 0.39527),
    (10.30626, 0.40878),
    (11.26498, 0.41554),
    (12.22370, 0.42568),
    (14.14114, 0.43919),
    (16.05859, 0.45608),
    (17.13715, 0.46959),
    (19.05459, 0.49324),
    (20.13316, 0.50676),
    (23.12916, 0.54730),
    (24.08788, 0.56081),
    (25.04660, 0.58108),
    (27.08389, 0.60811),
    (29.00133, 0.64189),
    (30.19973, 0.63851),
    (31.15845, 0.65541),
    (32.11718, 0.67905),
    (33.07590, 0.69932),
    (35.11318, 0.72973),
    (36.07190, 0.74324),
    (37.03062, 0.75676),
    (38.10919, 0.78041),
    (39.18775, 0.80068),
    (41.10519, 0.83108),
    (43.14248, 0.86824),
    (45.17976, 0.90541),
    (47.09720, 0.92905),
    (48.05593, 0.95946),
    (49.01465, 0.97635),
    (50.21305, 1.00000),
    (52.13049, 1.02365),
    (54.04794, 1.06419),
    (55.96538, 1.09122),
    (58.00266, 1.11149),
    (58.84155, 1.14527),
    (60.03995, 1.14527),
    (61.11851, 1.16216),
    (62.91611, 1.19257),
    (65.07323, 1.23311),
    (67.11052, 1.27027),
    (69.02796, 1.30405),
    (71.18509, 1.35135),
    (71.90413, 1.37838),
    (73.22237, 1.39189),
    (75.01997, 1.42905),
    (76.09853, 1.46284),
    (77.29694, 1.45946),
    (78.01598, 1.48649),
    (78.97470, 1.50676),
    (80.05326, 1.51689),
    (81.85087, 1.53716),
    (84.12783, 1.54392),
    (86.04527, 1.53716),
    (87.72304, 1.53041),
    (90.00000, 1.52703),
];

/// (angle of attack, deg; lift coefficient C_L).
pub const LIFT: [(f64, f64); 76] = [
    (0.95872, 0.03547),
    (2.03728, 0.06757),
    (2.99601, 0.10980),
    (3.95473, 0.15372),
    (5.03329, 0.20270),
    (5.99201, 0.22973),
    (6.95073, 0.28716),
    (8.02929, 0.29899),
    (9.10786, 0.34122),
    (9.94674, 0.37838),
    (11.02530, 0.41723),
    (11.98402, 0.45101),
    (13.06258, 0.48649),
    (13.90146, 0.51689),
    (15.09987, 0.54392),
    (15.93875, 0.57264),
    (17.01731, 0.59628),
    (17.97603, 0.63682),
    (18.93475, 0.65203),
    (20.01332, 0.67568),
    (20.97204, 0.70101),
    (22.05060, 0.71453),
    (23.00932, 0.72466),
    (23.96804, 0.72973),
    (25.04660, 0.74493),
    (26.00533, 0.74662),
    (26.96405, 0.75845),
    (28.04261, 0.75169),
    (28.88149, 0.76182),
    (31.03861, 0.75507),
    (32.23702, 0.75338),
    (33.91478, 0.75000),
    (35.95206, 0.74662),
    (38.94807, 0.74662),
    (40.98535, 0.73818),
    (43.02264, 0.72804),
    (44.94008, 0.72635),
    (47.09720, 0.70608),
    (48.89481, 0.70101),
    (50.81225, 0.68581),
    (51.89081, 0.67736),
    (52.96938, 0.66047),
    (53.92810, 0.65203),
    (54.88682, 0.63007),
    (55.96538, 0.63851),
    (56.92410, 0.61993),
    (58.00266, 0.60642),
    (58.96138, 0.59628),
    (59.92010, 0.58953),
    (60.99867, 0.56757),
    (62.07723, 0.55912),
    (63.99467, 0.53885),
    (66.03196, 0.52027),
    (66.99068, 0.51182),
    (67.94940, 0.49155),
    (68.90812, 0.48480),
    (70.94540, 0.45777),
    (71.90413, 0.44764),
    (72.98269, 0.42736),
    (73.82157, 0.40878),
    (74.90013, 0.39696),
    (75.97870, 0.38514),
    (77.05726, 0.36318),
    (78.01598, 0.33953),
    (78.97470, 0.32432),
    (79.93343, 0.30236),
    (81.01199, 0.28209),
    (81.85087, 0.26689),
    (82.92943, 0.22804),
    (84.00799, 0.21115),
    (84.96671, 0.19257),
    (85.92543, 0.16216),
    (86.88416, 0.13851),
    (87.96272, 0.11655),
    (88.92144, 0.08446),
    (90.00000, 0.06926),
];

/// Linear interpolation in a table sorted by angle, clamped at its ends;
/// NaN for an empty table or a NaN angle.
pub fn interpolate(table: &[(f64, f64)], alpha_deg: f64) -> f64 {
    let (Some(first), Some(last)) = (table.first(), table.last()) else {
        return f64::NAN;
    };
    if alpha_deg.is_nan() {
        return f64::NAN;
    }
    if alpha_deg <= first.0 {
        return first.1;
    }
    if alpha_deg >= last.0 {
        return last.1;
    }
    for w in table.windows(2) {
        if let [a, b] = w {
            if alpha_deg <= b.0 {
                let t = (alpha_deg - a.0) / (b.0 - a.0);
                return a.1 + t * (b.1 - a.1);
            }
        }
    }
    last.1
}

/// Measured `(C_D, C_L)` at `alpha_deg` (0-90°), interpolated. Below the
/// first measured angle C_L goes linearly to 0 at 0° (a symmetric plate
/// has no lift edge-on); C_D is held.
pub fn drag_lift(alpha_deg: f64) -> (f64, f64) {
    let a = alpha_deg.clamp(0.0, 90.0);
    let cd = interpolate(&DRAG, a);
    let cl = match LIFT.first() {
        Some(f) if a < f.0 => f.1 * a / f.0,
        _ => interpolate(&LIFT, a),
    };
    (cd, cl)
}

/// Normal and chordwise coefficients `(C_N, C_A)` at `alpha_deg` from the
/// measured drag and lift: `C_N = C_L cos α + C_D sin α` (along the plate
/// normal, against the flow's normal component), `C_A = C_D cos α - C_L sin α`
/// (in plane, against the flow's in-plane component).
pub fn normal_and_axial(alpha_deg: f64) -> (f64, f64) {
    let (cd, cl) = drag_lift(alpha_deg);
    let a = alpha_deg.clamp(0.0, 90.0).to_radians();
    let (s, c) = (libm::sin(a), libm::cos(a));
    (cl * c + cd * s, cd * c - cl * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_hits_the_table_and_the_ends() {
        assert!((interpolate(&DRAG, 90.0) - 1.52703).abs() < 1e-12);
        assert!((interpolate(&DRAG, 0.0) - 0.39189).abs() < 1e-12);
        let (cd, cl) = drag_lift(0.0);
        assert!(cl == 0.0 && cd > 0.3);
        // Broadside: the normal force is the drag.
        let (n, a) = normal_and_axial(90.0);
        assert!((n - 1.52703).abs() < 1e-9 && a.abs() < 0.07);
    }
}
