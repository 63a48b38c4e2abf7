//! `omniad coeffs eval FILE`: C_F(E), C_T(E) for directions read as CSV.
//!
//! Contract (other tools depend on it): stdin is CSV with header `ex,ey,ez`;
//! each direction is normalised; stdout is CSV
//! `ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz` (the normalised direction, then the
//! body-frame non-dimensional coefficients of eqs. 5-8 at zero angular
//! velocity). Any bad row is an error naming its line; nothing is written
//! for a failing input, so no partial output is mistaken for a result.

use super::common::read_coefficients;
use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use nalgebra::Vector3;
use omniad_core::Coefficients;
use std::io::{BufRead, Write};
use std::path::PathBuf;

/// `omniad coeffs ...`.
#[derive(Subcommand, Debug)]
pub enum CoeffsCommand {
    /// Read directions `ex,ey,ez` (CSV with header) on stdin, write
    /// `ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz` to stdout.
    Eval(EvalArgs),
}

/// Arguments of `omniad coeffs eval`.
#[derive(Args, Debug)]
pub struct EvalArgs {
    /// Coefficient file (.omni).
    pub file: PathBuf,
}

/// Runs `omniad coeffs`.
pub fn run(cmd: &CoeffsCommand) -> Result<()> {
    match cmd {
        CoeffsCommand::Eval(a) => {
            let m = read_coefficients(&a.file)?;
            let stdin = std::io::stdin();
            let out = eval_csv(&m, stdin.lock())?;
            std::io::stdout().lock().write_all(out.as_bytes())?;
            Ok(())
        }
    }
}

/// Parses one data row `ex,ey,ez` (line number `line`, 1-based).
pub fn parse_direction(text: &str, line: usize) -> Result<Vector3<f64>> {
    let fields: Vec<&str> = text.split(',').map(str::trim).collect();
    if fields.len() != 3 {
        bail!(
            "stdin line {line}: expected 3 fields ex,ey,ez, found {}",
            fields.len()
        );
    }
    let mut v = [0.0; 3];
    for ((slot, field), name) in v.iter_mut().zip(&fields).zip(["ex", "ey", "ez"]) {
        *slot = field.parse::<f64>().map_err(|_| {
            anyhow::anyhow!("stdin line {line}: field {name}: {field:?} is not a number")
        })?;
        if !slot.is_finite() {
            bail!("stdin line {line}: field {name} is not finite");
        }
    }
    // Scale by the largest component first: |e| of (1e-200, 0, 0) squares
    // to zero in f64, yet it is a valid direction.
    let e = Vector3::from(v);
    let scale = e.amax();
    let e = if scale > 0.0 { e / scale } else { e };
    let n = e.norm();
    if !(n.is_finite() && n > 0.0) {
        bail!(
            "stdin line {line}: direction ({}, {}, {}) has zero or infinite length",
            v[0],
            v[1],
            v[2]
        );
    }
    Ok(e / n)
}

/// Evaluates every row of `input`; returns the whole output CSV.
pub fn eval_csv(model: &Coefficients<f64>, input: impl BufRead) -> Result<String> {
    let mut out = String::from("ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz\n");
    let mut header_seen = false;
    for (i, line) in input.lines().enumerate() {
        let line_no = i + 1;
        let line = line.map_err(|e| anyhow::anyhow!("stdin line {line_no}: {e}"))?;
        // A spreadsheet's export may start with a byte-order mark.
        let text = line.trim().trim_start_matches('\u{feff}');
        if text.is_empty() {
            continue;
        }
        if !header_seen {
            let cols: Vec<&str> = text.split(',').map(str::trim).collect();
            if cols != ["ex", "ey", "ez"] {
                bail!("stdin line {line_no}: expected header `ex,ey,ez`, found {text:?}");
            }
            header_seen = true;
            continue;
        }
        let e = parse_direction(text, line_no)?;
        let c = model.at_unit_direction(&e);
        let (f, t) = (c.force, c.torque);
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            e.x, e.y, e.z, f.x, f.y, f.z, t.x, t.y, t.z
        ));
    }
    if !header_seen {
        bail!("stdin: empty input, expected header `ex,ey,ez`");
    }
    Ok(out)
}
