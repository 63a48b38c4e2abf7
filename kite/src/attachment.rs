//! The string's attachment point P for the file's γ/offset on the eq. (16)
//! line: shared by the static check and the flight model's line.

use crate::assemble::Design;
use crate::spec::Attachment;
use anyhow::{anyhow, Result};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::kite::statics;

/// P in the body frame for the file's attachment setting at orientation R.
pub fn attachment_point(
    design: &Design,
    wind: Option<f64>,
    r: &UnitQuaternion<f64>,
) -> Result<Vector3<f64>> {
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let eq = statics::equilibrium(&kite, &design.conditions(wind), r)
        .map_err(|e| anyhow!("equilibrium: {e}"))?;
    let gamma = match design.spec.attachment() {
        Attachment::Gamma(g) => g,
        Attachment::Offset(d) => {
            statics::gamma_for_distance(&eq, d).map_err(|e| anyhow!("string: {e}"))?
        }
    };
    statics::attachment_point(&eq, gamma).map_err(|e| anyhow!("string: {e}"))
}
