//! Field validation shared by the input readers: every error names the
//! file and the field.

use crate::error::{Error, Result};
use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion};
use std::path::Path;

/// Checks that every number of a field is finite.
pub(crate) fn finite(path: &Path, field: &str, values: &[f64]) -> Result<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::at_field(path, field, "must be finite"))
    }
}

/// Checks that a field is finite and positive.
pub(crate) fn positive(path: &Path, field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::at_field(
            path,
            field,
            format!("must be positive and finite, found {v}"),
        ))
    }
}

/// Checks that a field is finite and within `[lo, hi]` (`unit` and `why`
/// in the message): a number far outside what a recording can hold is a
/// typo, and let through it failed much later, blamed on something else.
pub(crate) fn within(
    path: &Path,
    field: &str,
    v: f64,
    (lo, hi): (f64, f64),
    (unit, why): (&str, &str),
) -> Result<()> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(Error::at_field(
            path,
            field,
            format!("must be from {lo:e} to {hi:e} {unit} ({why}), found {v:e}"),
        ))
    }
}

/// `[w, x, y, z]` normalised, or `None` when zero or non-finite.
pub fn unit_quaternion(q: &[f64; 4]) -> Option<UnitQuaternion<f64>> {
    let raw = Quaternion::new(q[0], q[1], q[2], q[3]);
    let n = raw.norm();
    (n.is_finite() && n > 0.0).then(|| UnitQuaternion::new_unchecked(raw / n))
}

/// A rotation matrix (rows) as a unit quaternion, if it is orthonormal with
/// determinant +1 to within 1e-3.
pub fn rotation_from_rows(rows: &[[f64; 3]; 3]) -> Option<UnitQuaternion<f64>> {
    let m = Matrix3::from_row_slice(&rows.iter().flatten().copied().collect::<Vec<_>>());
    let err = (m * m.transpose() - Matrix3::identity()).norm();
    if err.is_nan() || err >= 1e-3 || m.determinant() < 0.0 {
        return None;
    }
    Some(UnitQuaternion::from_rotation_matrix(
        &Rotation3::from_matrix(&m),
    ))
}
