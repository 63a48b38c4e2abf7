//! Extension payloads of fixed-size `f32` arrays (little-endian), shared by
//! the extensions this build evaluates ([`crate::spin_coupling`],
//! [`crate::gravity_coupling`]).

use crate::error::ModelError;
use crate::extension::Extension;
use crate::math::Real;

/// An extension of `kind`, `version` holding `values` as `f32`s; `field`
/// names the values in errors (a non-finite value is one).
pub(crate) fn encode<T: Real>(
    kind: u16,
    version: u8,
    values: impl Iterator<Item = T>,
    field: &'static str,
) -> Result<Extension, ModelError> {
    let mut data = heapless::Vec::new();
    for x in values {
        let value = x.as_f64();
        if !value.is_finite() {
            return Err(ModelError::NonFinite(field));
        }
        data.extend_from_slice(&(value as f32).to_le_bytes())
            .map_err(|_| ModelError::CapacityExceeded("extension.data"))?;
    }
    Ok(Extension {
        kind,
        version,
        data,
    })
}

/// The `N` values of an extension of `kind` and `version`: `Ok(None)` for
/// another kind or version (kept, not evaluated), an error for a payload of
/// the wrong size or with a non-finite value (`field`, `size_field` name
/// them).
pub(crate) fn decode<T: Real, const N: usize>(
    e: &Extension,
    kind: u16,
    version: u8,
    field: &'static str,
    size_field: &'static str,
) -> Result<Option<[T; N]>, ModelError> {
    if e.kind != kind || e.version != version {
        return Ok(None);
    }
    if e.data.len() != 4 * N {
        return Err(ModelError::OutOfRange(size_field));
    }
    let mut out = [T::zero(); N];
    for (x, bytes) in out.iter_mut().zip(e.data.chunks_exact(4)) {
        let v = match bytes {
            [a, b, c, d] => f32::from_le_bytes([*a, *b, *c, *d]),
            _ => return Err(ModelError::OutOfRange(size_field)),
        };
        if !v.is_finite() {
            return Err(ModelError::NonFinite(field));
        }
        *x = T::of_f64(f64::from(v));
    }
    Ok(Some(out))
}
