//! Generates the primitive library in `data/primitives/`: example boxes and
//! plates, each made by projecting the independent quasi-steady panel model
//! (`omniad_core::reference::panel`) onto OmniAD coefficients (eqs. 11, 13
//! via `omniad_core::projection`), with the damping tensor D fitted to the
//! same panel model (eq. 12).
//!
//! Regenerate with `cargo run --release -p omniad-kite --example gen_primitives -- data/primitives`.

use anyhow::{Context, Result};
use nalgebra::Vector3;
use omniad_core::projection::project;
use omniad_core::reference::panel::PanelModel;
use omniad_core::Coefficients;
use std::fmt::Write as _;
use std::path::Path;

/// SH degree of the examples.
pub const DEGREE: u8 = 8;

/// Example sizes `[l_x, l_y, l_z]`, m (y open; `l_z = 0` is a plate).
pub const EXAMPLES: [[f64; 3]; 16] = [
    [0.3, 0.3, 0.3],
    [0.3, 0.15, 0.3],
    [0.3, 0.6, 0.3],
    [0.3, 0.3, 0.15],
    [0.3, 0.6, 0.15],
    [0.3, 0.15, 0.15],
    [0.3, 0.3, 0.075],
    [0.3, 0.9, 0.3],
    [0.3, 0.45, 0.225],
    [0.3, 0.1, 0.05],
    [0.3, 0.3, 0.0],
    [0.3, 0.15, 0.0],
    [0.3, 0.6, 0.0],
    [0.3, 1.2, 0.0],
    [0.3, 0.05, 0.0],
    [0.3, 0.9, 0.1],
];

/// The panel model of a box (or plate when `l_z = 0`).
pub fn panel_model(size: &[f64; 3]) -> PanelModel {
    let [lx, ly, lz] = *size;
    if lz == 0.0 {
        PanelModel::plate(lx, ly)
    } else {
        PanelModel::open_box(lx, ly, lz)
    }
}

/// Projects the panel model of `size` onto OmniAD coefficients of `degree`
/// with pole +y (the open axis) and `L = |l|`.
pub fn example(size: &[f64; 3], degree: u8) -> Result<Coefficients<f64>> {
    let model = panel_model(size);
    let l = Vector3::from(*size).norm();
    // Unit speed, unit density: F = ½ C_F L², T = ½ C_T L³.
    let f = |e: &Vector3<f64>| {
        let (force, torque) = model.translation_wrench(e, 1.0);
        (force * (2.0 / (l * l)), torque * (2.0 / (l * l * l)))
    };
    let mut c =
        project(degree, Vector3::y(), l, f).map_err(|e| anyhow::anyhow!("projection: {e}"))?;
    c.set_damping(&model.damping_tensor(l))
        .map_err(|e| anyhow::anyhow!("damping: {e}"))?;
    let kind = if size[2] == 0.0 { "plate" } else { "box" };
    c.set_name(&format!(
        "{kind} {:.3}x{:.3}x{:.3}",
        size[0], size[1], size[2]
    ))
    .map_err(|e| anyhow::anyhow!("name: {e}"))?;
    c.provenance.method = heapless::String::try_from("projection").unwrap_or_default();
    c.provenance.source = heapless::String::try_from(
        "omniad_core::reference::panel quasi-steady panel model, projected (eqs. 11, 13)",
    )
    .unwrap_or_default();
    Ok(c)
}

/// File name of an example.
pub fn file_name(size: &[f64; 3]) -> String {
    let kind = if size[2] == 0.0 { "plate" } else { "box" };
    format!(
        "{kind}-{:.0}x{:.0}x{:.0}mm.omni",
        size[0] * 1e3,
        size[1] * 1e3,
        size[2] * 1e3
    )
}

/// Writes every example and `library.toml` into `dir`.
pub fn write_library(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut index = String::from(
        "# KiteShop primitive library (generated; do not edit).\n# Regenerate: cargo run --release -p omniad-kite --example gen_primitives -- data/primitives\n\n",
    );
    let mut buf = vec![0u8; 64 * 1024];
    for size in &EXAMPLES {
        let c = example(size, DEGREE)?;
        let n =
            omniad_core::file::encode(&c, &mut buf).map_err(|e| anyhow::anyhow!("encode: {e}"))?;
        let name = file_name(size);
        std::fs::write(dir.join(&name), &buf[..n])
            .with_context(|| format!("cannot write {name}"))?;
        let _ = writeln!(
            index,
            "[[example]]\nfile = \"{name}\"\nsize = [{}, {}, {}]\n",
            size[0], size[1], size[2]
        );
    }
    std::fs::write(dir.join(crate::library::INDEX), index).context("cannot write library.toml")?;
    Ok(())
}
