//! `omniad info FILE [--json]`.

use super::common::read_coefficients;
use anyhow::Result;
use clap::Args;
use omniad_core::coefficients::{COVERAGE_CELLS, COVERAGE_LAT, COVERAGE_LON};
use omniad_core::math::six_from_symmetric;
use omniad_core::Coefficients;
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `omniad info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Coefficient file (.omni).
    pub file: PathBuf,
    /// Print machine-readable JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `omniad info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let m = read_coefficients(&args.file)?;
    let summary = summary(&m);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print_text(&m, &summary);
    }
    Ok(())
}

/// Drag coefficient `-C_F(E)·E` along the six body axes.
fn axis_drag(m: &Coefficients<f64>) -> Vec<(String, f64)> {
    let axes = [
        ("+x", [1., 0., 0.]),
        ("-x", [-1., 0., 0.]),
        ("+y", [0., 1., 0.]),
        ("-y", [0., -1., 0.]),
        ("+z", [0., 0., 1.]),
        ("-z", [0., 0., -1.]),
    ];
    axes.iter()
        .filter_map(|(n, a)| {
            let e = nalgebra::Vector3::from(*a);
            m.at_direction(&e)
                .map(|c| (n.to_string(), -c.force.dot(&e)))
        })
        .collect()
}

fn coverage_summary(m: &Coefficients<f64>) -> serde_json::Value {
    let cov = &m.provenance.coverage;
    if cov.len() != COVERAGE_CELLS {
        return serde_json::Value::Null;
    }
    let covered = cov.iter().filter(|&&c| c > 0).count();
    let dense = cov.iter().filter(|&&c| c >= 20).count();
    json!({
        "grid": [COVERAGE_LON, COVERAGE_LAT],
        "cells": COVERAGE_CELLS,
        "cells_with_frames": covered,
        "cells_with_20_frames": dense,
        "fraction_covered": covered as f64 / COVERAGE_CELLS as f64,
        "max_frames_in_cell": cov.iter().max().copied().unwrap_or(0),
    })
}

fn summary(m: &Coefficients<f64>) -> serde_json::Value {
    let p = &m.provenance;
    json!({
        "name": m.name(),
        "degree": m.degree(),
        "coefficients_per_component": m.coeff_count(),
        "torque_degree": m.torque_degree(),
        "torque_coefficients_per_component": m.torque_coeff_count(),
        "pole": [m.pole().x, m.pole().y, m.pole().z],
        "reference_length_m": m.reference_length(),
        "damping_xx_yy_zz_xy_xz_yz": six_from_symmetric(&m.damping()),
        "mass_kg": m.body.map(|b| b.mass),
        "inertia_kg_m2_xx_yy_zz_xy_xz_yz": m.body.map(|b| b.inertia),
        "axis_drag_coefficient": axis_drag(m).into_iter().map(|(k, v)| (k, json!(v))).collect::<serde_json::Map<_, _>>(),
        "provenance": {
            "method": p.method.as_str(),
            "source": p.source.as_str(),
            "frames_used": p.frames_used,
            "frames_dropped": p.frames_dropped,
            "force_residuals": p.force_residuals.as_slice(),
            "torque_residuals": p.torque_residuals.as_slice(),
            "coverage": coverage_summary(m),
        },
        "extensions": m.extensions().iter().map(|e| json!({"kind": e.kind, "version": e.version, "bytes": e.data.len()})).collect::<Vec<_>>(),
        "spin_coupling": m.spin_coupling().map(|s| json!({
            "tensor_k_ijk": s.k,
            "magnus_scale": s.magnus_scale(),
        })),
        "gravity_coupling": m.gravity_coupling().map(|g| json!({
            "matrix_g_rows": [g.g.row(0).iter().collect::<Vec<_>>(), g.g.row(1).iter().collect::<Vec<_>>(), g.g.row(2).iter().collect::<Vec<_>>()],
            "buoyancy_volume_m3": g.buoyancy_volume(m.reference_length()),
        })),
        "effects": m.effects().iter().map(|e| json!({
            "effect": e.kind.name(),
            "params": e.used_params(),
        })).collect::<Vec<_>>(),
    })
}

fn print_text(m: &Coefficients<f64>, s: &serde_json::Value) {
    println!("name:              {}", printable(m.name()));
    println!(
        "degree N:          {} ({} SH coefficients per component)",
        m.degree(),
        m.coeff_count()
    );
    println!(
        "torque degree N_T: {} ({} SH coefficients per component)",
        m.torque_degree(),
        m.torque_coeff_count()
    );
    let z = m.pole();
    println!("pole Z (body):     [{:.4}, {:.4}, {:.4}]", z.x, z.y, z.z);
    println!("reference length:  {:.4} m", m.reference_length());
    let d = six_from_symmetric(&m.damping());
    println!(
        "damping D:         xx {:.4e} yy {:.4e} zz {:.4e} xy {:.4e} xz {:.4e} yz {:.4e}",
        d[0], d[1], d[2], d[3], d[4], d[5]
    );
    match &m.body {
        Some(b) => println!(
            "mass:              {:.4} kg, inertia diag [{:.3e}, {:.3e}, {:.3e}] kg m^2",
            b.mass, b.inertia[0], b.inertia[1], b.inertia[2]
        ),
        None => println!("mass:              (not recorded)"),
    }
    println!("drag -C_F(E)·E along body axes:");
    for (axis, cd) in axis_drag(m) {
        println!("  E = {axis}: {cd:8.4}");
    }
    let p = &m.provenance;
    println!(
        "provenance:        method {:?}, source {:?}",
        p.method.as_str(),
        p.source.as_str()
    );
    println!(
        "frames:            {} used, {} dropped",
        p.frames_used, p.frames_dropped
    );
    if !p.force_residuals.is_empty() {
        println!("force residuals:   {:?}", p.force_residuals.as_slice());
        println!("torque residuals:  {:?}", p.torque_residuals.as_slice());
    }
    match s["provenance"]["coverage"].as_object() {
        Some(c) => println!(
            "coverage:          {} of {} direction cells have frames, {} have >= 20",
            c["cells_with_frames"], c["cells"], c["cells_with_20_frames"]
        ),
        None => println!("coverage:          (not recorded)"),
    }
    println!("extensions:        {}", m.extensions().len());
    if let Some(g) = m.gravity_coupling() {
        let v = g.buoyancy_volume(m.reference_length());
        let note = if v < 0.0 {
            " — negative: not buoyancy (added mass or a misattribution; see omniad residual)"
        } else {
            ""
        };
        println!("gravity coupling:  buoyancy-equivalent volume {v:.3e} m^3 (F = ρL³ G Rᵀg){note}");
    }
    for e in m.effects() {
        println!("effect:            {} {:?}", e.kind.name(), e.used_params());
    }
    if let Some(s) = m.spin_coupling() {
        println!(
            "spin coupling:     |K| {:.4}, Magnus part {:.4} (F = ½ρL³ K:(Ω⊗V))",
            s.norm(),
            s.magnus_scale()
        );
    }
}

/// `name` with its control characters escaped (`\u{1b}`): a file's name
/// is the file's, and printed raw an escape sequence in it would drive
/// the user's terminal.
fn printable(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn control_characters_of_a_name_are_escaped() {
        assert_eq!(super::printable("plate 30 cm"), "plate 30 cm");
        assert_eq!(super::printable("a\u{1b}[2Jb\n"), "a\\u{1b}[2Jb\\u{a}");
    }
}
