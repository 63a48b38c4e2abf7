//! The paper's Fig. 13: a plate model's lift and drag section against
//! measured curves ([`omniad_core::reference::taira`]).
//!
//! The section: body-frame air directions `E(α) = (cos α, 0, -sin α)` in
//! the plate's chordwise symmetry plane (normal `+z` = the model's pole
//! for the plate sets, chord along x), `α` the angle of attack. With A the
//! planform area and L the model's reference length, the coefficients on
//! planform area are drag `C_D = -(L²/A) C_F(E)·E` and lift
//! `C_L = (L²/A) C_F(E)·l̂`, `l̂ = unit(n + sin α E)` (perpendicular to
//! `E`, on the side the normal force pushes).
//!
//! The deviation, as the paper's "L1": `Σ|fit - measured| / Σ|measured|`
//! over the measured points with `α <= 60°` (the paper's range).

use nalgebra::Vector3;
use omniad_core::reference::taira::{DRAG, LIFT};
use omniad_core::Coefficients;
use serde::Serialize;

/// The paper's angle range for Fig. 13, degrees.
pub const MAX_ALPHA: f64 = 60.0;

/// `(C_D, C_L)` of `model` at angle of attack `alpha_deg` for planform
/// area `area` (m²).
pub fn drag_lift(model: &Coefficients<f64>, area: f64, alpha_deg: f64) -> (f64, f64) {
    let a = alpha_deg.to_radians();
    let e = Vector3::new(a.cos(), 0.0, -a.sin());
    let l = model.reference_length();
    let k = l * l / area;
    let Some(c) = model.at_direction(&e) else {
        return (f64::NAN, f64::NAN);
    };
    let lift_dir = (Vector3::z() + e * a.sin()).normalize();
    (-c.force.dot(&e) * k, c.force.dot(&lift_dir) * k)
}

/// The L1 deviations of a model from the measured curves.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Deviation {
    /// Drag, fraction (0.13 = 13 %).
    pub drag: f64,
    /// Lift, fraction.
    pub lift: f64,
}

fn l1(table: &[(f64, f64)], fitted: impl Fn(f64) -> f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for &(a, measured) in table.iter().filter(|p| p.0 <= MAX_ALPHA) {
        num += (fitted(a) - measured).abs();
        den += measured.abs();
    }
    num / den
}

/// The paper's L1 deviation of `model` (planform area `area`, m²) from
/// the measured drag and lift over 0-60°.
pub fn deviation(model: &Coefficients<f64>, area: f64) -> Deviation {
    Deviation {
        drag: l1(&DRAG, |a| drag_lift(model, area, a).0),
        lift: l1(&LIFT, |a| drag_lift(model, area, a).1),
    }
}

/// `(α, C_D, C_L)` every `step` degrees over 0-60°.
pub fn curve(model: &Coefficients<f64>, area: f64, step: f64) -> Vec<(f64, f64, f64)> {
    let n = (MAX_ALPHA / step).round() as usize;
    (0..=n)
        .map(|i| {
            let a = i as f64 * step;
            let (d, l) = drag_lift(model, area, a);
            (a, d, l)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bundled_reference_table_is_the_shared_data() {
        for (file, table) in [("Cd", &DRAG[..]), ("Cl", &LIFT[..])] {
            let path = format!(
                "{}/../data/reference/taira2007-plate-AR2-Re100-{file}.dat",
                env!("CARGO_MANIFEST_DIR")
            );
            let text = std::fs::read_to_string(&path).unwrap();
            let rows: Vec<(f64, f64)> = text
                .lines()
                .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
                .map(|l| {
                    let mut it = l.split_whitespace().map(|x| x.parse::<f64>().unwrap());
                    (it.next().unwrap(), it.next().unwrap())
                })
                .collect();
            assert_eq!(rows, table, "{file}");
        }
    }

    #[test]
    fn the_generating_model_of_the_measured_plate_is_close_to_the_curves() {
        use omniad_acquire::synth::{truth_model, ObjectSpec, SynthObject};
        let spec = ObjectSpec::of(SynthObject::TairaPlate);
        let m = truth_model(&spec, 8).unwrap();
        let d = deviation(&m, spec.size.x * spec.size.y);
        // The SH projection at N = 8 smooths the measured curves a little.
        assert!(d.drag < 0.05 && d.lift < 0.05, "{d:?}");
    }
}
