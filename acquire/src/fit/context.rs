//! What every fit needs: the object's constants and the SH values and
//! vector basis (§4.2) at a direction.

use crate::input::recording::RecordingSet;
use nalgebra::Vector3;
use omniad_core::basis::vector_basis;
use omniad_core::sh::{evaluate, MAX_COEFFS};

/// Object constants the fit needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitContext {
    /// Air density ρ, kg/m³.
    pub air_density: f64,
    /// Reference length L, m.
    pub reference_length: f64,
    /// Unit pole Z.
    pub pole: Vector3<f64>,
}

impl FitContext {
    /// The constants of the object and air recorded in `set`.
    pub fn of_set(set: &RecordingSet) -> Self {
        Self {
            air_density: set.world.air_density,
            reference_length: set.object.reference_length,
            pole: set.object.pole,
        }
    }
}

/// SH values `Y_lm(E)` and the basis at a unit direction.
pub(crate) fn sh_and_basis(
    degree: usize,
    e: &Vector3<f64>,
    pole: &Vector3<f64>,
) -> (Vec<f64>, [Vector3<f64>; 3]) {
    let mut y = [0.0; MAX_COEFFS];
    let n = evaluate(degree, e, &mut y);
    (y.get(..n).unwrap_or(&[]).to_vec(), vector_basis(e, pole))
}
