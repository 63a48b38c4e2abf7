//! The recorded object (`[object]` of `recording.toml`): mass properties,
//! reference length, pole and markers, validated field by field.

use crate::error::{Error, Result};
use crate::input::validate::{finite, positive};
use nalgebra::{Matrix3, Vector3};
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

/// The validated object of `recording.toml` at `path`.
pub(crate) fn object(path: &Path, o: RawObject) -> Result<Object> {
    positive(path, "object.mass", o.mass)?;
    positive(path, "object.reference_length", o.reference_length)?;
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
    finite(path, "object.pole", &o.pole)?;
    let pole = Vector3::from(o.pole);
    if pole.norm() == 0.0 {
        return Err(Error::at_field(path, "object.pole", "must be non-zero"));
    }
    let mut markers = Vec::with_capacity(o.markers.len());
    for (name, p) in o.markers {
        finite(path, &format!("object.markers.{name}"), &p)?;
        markers.push((name, Vector3::from(p)));
    }
    Ok(Object {
        name: o.name,
        mass: o.mass,
        inertia,
        reference_length: o.reference_length,
        pole: pole.normalize(),
        markers,
    })
}
