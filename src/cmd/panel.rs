//! `omniad panel`: coefficients of an independent quasi-steady panel model
//! (thin plate or open box, `omniad_core::reference::panel`) projected onto the
//! OmniAD SH model (eqs. 11, 13 by quadrature; D by eq. 12 on the panel
//! model's rotational torques). This is how the bundled `data/plate.omni`
//! is made:
//!
//! ```text
//! omniad panel --shape plate --size 0.30,0.50,0.02 --mass 0.048 --degree 8 -o data/plate.omni
//! ```

use super::common::write_coefficients;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use nalgebra::Vector3;
use omniad_core::coefficients::MassProperties;
use omniad_core::projection::project;
use omniad_core::reference::panel::PanelModel;
use std::path::PathBuf;

/// Panel-model shapes.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Shape {
    /// Thin plate in the body x-y plane (lz is its thickness, for inertia).
    Plate,
    /// Box-kite cell open along its y axis.
    Box,
}

/// Arguments of `omniad panel`.
#[derive(Args, Debug)]
pub struct PanelArgs {
    /// Shape.
    #[arg(long, value_enum)]
    pub shape: Shape,
    /// Dimensions lx,ly,lz, m, each positive.
    #[arg(long)]
    pub size: String,
    /// Mass, kg (inertia from a uniform solid cuboid for plates, thin walls for boxes).
    #[arg(long)]
    pub mass: f64,
    /// SH degree N.
    #[arg(long, default_value_t = 8)]
    pub degree: u8,
    /// Object name stored in the file.
    #[arg(long)]
    pub name: Option<String>,
    /// Output coefficient file.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Parses `lx,ly,lz` (m, positive, finite).
pub fn parse_size(s: &str) -> Result<[f64; 3]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("--size: expected lx,ly,lz in metres, got {s:?}"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|d| d.is_finite() && *d > 0.0) => Ok([*x, *y, *z]),
        _ => bail!("--size: expected three positive finite numbers lx,ly,lz (m), got {s:?}"),
    }
}

/// Inertia `[xx, yy, zz, 0, 0, 0]` of a solid cuboid, kg m².
fn cuboid_inertia(m: f64, [x, y, z]: [f64; 3]) -> [f64; 6] {
    [
        m * (y * y + z * z) / 12.0,
        m * (x * x + z * z) / 12.0,
        m * (x * x + y * y) / 12.0,
        0.0,
        0.0,
        0.0,
    ]
}

/// Inertia of an open box's four thin walls (area-weighted), kg m².
fn open_box_inertia(m: f64, [x, y, z]: [f64; 3]) -> [f64; 6] {
    let (ax, az) = (y * z, x * y); // walls normal to x (two), normal to z (two)
    let total = 2.0 * (ax + az);
    let (mx, mz) = (m * ax / total, m * az / total);
    // Wall normal to x at ±x/2: thin plate y by z, offset x/2.
    let wall_x = [
        mx * (y * y + z * z) / 12.0,
        mx * (z * z / 12.0 + x * x / 4.0),
        mx * (y * y / 12.0 + x * x / 4.0),
    ];
    let wall_z = [
        mz * (y * y / 12.0 + z * z / 4.0),
        mz * (x * x / 12.0 + z * z / 4.0),
        mz * (x * x + y * y) / 12.0,
    ];
    [
        2.0 * (wall_x[0] + wall_z[0]),
        2.0 * (wall_x[1] + wall_z[1]),
        2.0 * (wall_x[2] + wall_z[2]),
        0.0,
        0.0,
        0.0,
    ]
}

/// Runs `omniad panel`.
pub fn run(a: &PanelArgs) -> Result<()> {
    let size = parse_size(&a.size)?;
    if !(a.mass > 0.0 && a.mass.is_finite()) {
        bail!("--mass must be positive");
    }
    let [x, y, z] = size;
    let (panels, inertia, pole) = match a.shape {
        Shape::Plate => (
            PanelModel::plate(x, y),
            cuboid_inertia(a.mass, size),
            Vector3::z(),
        ),
        Shape::Box => (
            PanelModel::open_box(x, y, z),
            open_box_inertia(a.mass, size),
            Vector3::y(),
        ),
    };
    let l = (x * x + y * y + z * z).sqrt();
    if l.is_nan() || l <= 0.0 {
        bail!("--size: all dimensions are zero");
    }
    let model = panel_coefficients(&panels, a.degree, pole, l)?;
    let mut model = model;
    let name = a
        .name
        .clone()
        .unwrap_or_else(|| format!("{:?} {x}x{y}x{z} m", a.shape).to_lowercase());
    model
        .set_name(&name)
        .map_err(|e| anyhow::anyhow!("--name: {e}"))?;
    model.body = Some(MassProperties {
        mass: a.mass,
        inertia,
    });
    model.provenance.method = heapless::String::try_from("projection").unwrap_or_default();
    let source = format!("panel model {:?} {x},{y},{z} m, N={}", a.shape, a.degree).to_lowercase();
    model.provenance.source = heapless::String::try_from(source.as_str()).unwrap_or_default();
    write_coefficients(&a.output, &model)?;
    eprintln!(
        "wrote {} (degree {}, L = {l:.4} m)",
        a.output.display(),
        a.degree
    );
    Ok(())
}

/// Projects a panel model onto coefficients (C_F, C_T per eqs. 5-6 with
/// ρ = 1, |V| = 1) and fits D.
pub fn panel_coefficients(
    p: &PanelModel,
    degree: u8,
    pole: Vector3<f64>,
    l: f64,
) -> Result<omniad_core::Coefficients<f64>> {
    let mut model = project(degree, pole, l, |e| {
        let (f, t) = p.translation_wrench(e, 1.0);
        (f / (0.5 * l * l), t / (0.5 * l * l * l))
    })
    .map_err(|e| anyhow::anyhow!("projection: {e}"))?;
    model
        .set_damping(&p.damping_tensor(l))
        .map_err(|e| anyhow::anyhow!("damping: {e}"))?;
    Ok(model)
}
