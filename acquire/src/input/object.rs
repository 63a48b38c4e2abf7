//! The recorded object (`[object]` of `recording.toml`): mass properties,
//! reference length, pole and markers, validated field by field.

use crate::error::{Error, Result};
use crate::input::validate::{finite, within};
use nalgebra::{Matrix3, Vector3};
use omniad_core::math::unit_vector;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The recorded object.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Mass M, kg.
    pub mass: f64,
    /// Inertia about the centre of mass, body frame, kg m².
    pub inertia: Matrix3<f64>,
    /// Reference length L (bounding-box diagonal), m.
    pub reference_length: f64,
    /// Unit pole Z of the SH vector basis, body frame.
    pub pole: Vector3<f64>,
    /// Markers: name and body-frame position (m), in name order.
    pub markers: Vec<(String, Vector3<f64>)>,
}

impl Object {
    /// Index of a marker by name.
    pub fn marker_index(&self, name: &str) -> Option<usize> {
        self.markers.iter().position(|(n, _)| n == name)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawObject {
    pub name: String,
    pub mass: f64,
    pub inertia: [[f64; 3]; 3],
    pub reference_length: f64,
    pub pole: [f64; 3],
    #[serde(default)]
    pub markers: BTreeMap<String, [f64; 3]>,
}

/// The heaviest object a recording may describe, kg (a kite with its
/// control unit is tens of kg).
pub const MAX_MASS: f64 = 1e4;
/// The longest reference length a recording may give, m.
pub const MAX_REFERENCE_LENGTH: f64 = 1e3;

/// The validated object of `recording.toml` at `path`.
pub(crate) fn object(path: &Path, o: RawObject) -> Result<Object> {
    within(
        path,
        "object.mass",
        o.mass,
        (1e-9, MAX_MASS),
        ("kg", "a body one camera films falling"),
    )?;
    within(
        path,
        "object.reference_length",
        o.reference_length,
        (1e-4, MAX_REFERENCE_LENGTH),
        ("m", "a body one camera films whole, its markers told apart"),
    )?;
    let flat: Vec<f64> = o.inertia.iter().flatten().copied().collect();
    finite(path, "object.inertia", &flat)?;
    let inertia = Matrix3::from_row_slice(&flat);
    if (inertia - inertia.transpose()).norm() > 1e-9 * inertia.norm()
        || inertia.cholesky().is_none()
    {
        return Err(Error::at_field(
            path,
            "object.inertia",
            "must be symmetric positive definite",
        ));
    }
    physical_inertia(path, &inertia)?;
    finite(path, "object.pole", &o.pole)?;
    let Some(pole) = unit_vector(&Vector3::from(o.pole)) else {
        return Err(Error::at_field(path, "object.pole", "must be non-zero"));
    };
    let mut markers = Vec::with_capacity(o.markers.len());
    for (name, p) in o.markers {
        finite(path, &format!("object.markers.{name}"), &p)?;
        markers.push((name, Vector3::from(p)));
    }
    distinct_markers(path, &markers, o.reference_length)?;
    Ok(Object {
        name: o.name,
        mass: o.mass,
        inertia,
        reference_length: o.reference_length,
        pole,
        markers,
    })
}

/// A rigid body's principal moments satisfy the triangle inequality
/// (`I1 <= I2 + I3`, ...): no mass distribution has one moment larger than
/// the other two together.
fn physical_inertia(path: &Path, inertia: &Matrix3<f64>) -> Result<()> {
    let m = inertia.symmetric_eigenvalues();
    let sum = m.sum();
    if m.iter().all(|&i| i <= (sum - i) * (1.0 + 1e-9)) {
        Ok(())
    } else {
        Err(Error::at_field(
            path,
            "object.inertia",
            format!(
                "principal moments {:.4e}, {:.4e}, {:.4e} kg m² break the triangle inequality \
                 (each must be at most the sum of the other two)",
                m[0], m[1], m[2]
            ),
        ))
    }
}

/// No two markers at one point (they could not be told apart, and a pose
/// is not observable from markers that all coincide): within 1e-6 of the
/// reference length.
fn distinct_markers(path: &Path, markers: &[(String, Vector3<f64>)], length: f64) -> Result<()> {
    for (i, (a, pa)) in markers.iter().enumerate() {
        if let Some((b, _)) = markers
            .iter()
            .skip(i + 1)
            .find(|(_, pb)| (pa - pb).norm() <= 1e-6 * length)
        {
            return Err(Error::at_field(
                path,
                format!("object.markers.{b}"),
                format!("at the same point as marker `{a}`"),
            ));
        }
    }
    Ok(())
}
