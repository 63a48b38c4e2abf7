//! Named effects in `.omni` files: one extension per effect, tag
//! [`EffectKind::extension_kind`], payload version 2 = the parameters as
//! little-endian `f32`s in the order [`EffectKind`] documents (4 bytes per
//! parameter). Old readers keep the payload as an unknown extension.
//!
//! Why version 2: tags 1 (added mass) and 2 (buoyancy) were reserved
//! before this layout existed, and files were written with version-1
//! payloads of those tags as stand-ins for future terms (the golden file
//! `core/tests/golden/v1.omni` has one); they must keep loading, as
//! unknown versions are kept and not evaluated.

use super::{Effect, EffectKind};
use crate::error::ModelError;
use crate::extension::Extension;
use crate::math::Real;

/// Payload version written and understood by this build.
pub const PAYLOAD_VERSION: u8 = 2;

impl<T: Real> Effect<T> {
    /// The extension holding this effect.
    pub fn to_extension(&self) -> Result<Extension, ModelError> {
        let n = self.kind.param_count();
        crate::payload::encode(
            self.kind.extension_kind(),
            PAYLOAD_VERSION,
            self.params.iter().copied().take(n),
            "effect parameter",
        )
    }

    /// The effect an extension holds: `Ok(None)` for another tag or
    /// version (kept, not evaluated), an error for a malformed payload.
    pub fn from_extension(e: &Extension) -> Result<Option<Self>, ModelError> {
        let Some(kind) = EffectKind::from_extension_kind(e.kind) else {
            return Ok(None);
        };
        if e.version != PAYLOAD_VERSION {
            return Ok(None);
        }
        let params: Option<[T; super::MAX_PARAMS]> = match kind.param_count() {
            1 => decode::<T, 1>(e)?,
            6 => decode::<T, 6>(e)?,
            9 => decode::<T, 9>(e)?,
            _ => return Err(ModelError::OutOfRange("effect parameter count")),
        };
        Ok(params.map(|params| Self { kind, params }))
    }
}

/// The `N` parameters of `e`, padded to [`super::MAX_PARAMS`].
fn decode<T: Real, const N: usize>(
    e: &Extension,
) -> Result<Option<[T; super::MAX_PARAMS]>, ModelError> {
    let values: Option<[T; N]> = crate::payload::decode(
        e,
        e.kind,
        PAYLOAD_VERSION,
        "effect parameter",
        "effect payload size",
    )?;
    Ok(values.map(|v| {
        let mut out = [T::zero(); super::MAX_PARAMS];
        for (o, x) in out.iter_mut().zip(v) {
            *o = x;
        }
        out
    }))
}
