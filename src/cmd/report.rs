//! `omniad report SET -o DIR [--json]`: the validation report of a
//! recording set (the paper's Figs. 8, 12, 13; `omniad_validate::report`).

use super::common::{read_coefficients, write_coefficients};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `omniad report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Recording set folder.
    pub set: PathBuf,
    /// Output folder for report.md, report.json, the SVG figures and the
    /// fitted model.omni.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also compare this coefficient file with the measured lift and drag
    /// (plates only), e.g. data/plate.omni.
    #[arg(long)]
    pub compare: Option<PathBuf>,
    /// Skip the SH-degree sweep (Fig. 8; five more fits).
    #[arg(long)]
    pub no_sweep: bool,
    /// Print the report's JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `omniad report`.
pub fn run(a: &ReportArgs) -> Result<()> {
    let compare = a
        .compare
        .as_ref()
        .map(|p| read_coefficients(p))
        .transpose()?;
    let name = a
        .compare
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    let mut command = format!(
        "omniad report {} -o {}",
        a.set.display(),
        a.output.display()
    );
    if let Some(p) = &a.compare {
        command += &format!(" --compare {}", p.display());
    }
    if a.no_sweep {
        command += " --no-sweep";
    }
    let degrees: &[u8] = if a.no_sweep {
        &[]
    } else {
        &omniad_validate::resolution::DEGREES
    };
    let reads: Vec<&std::path::Path> = a.compare.as_deref().into_iter().collect();
    let opts = omniad_validate::report::Options {
        command: &command,
        compare: compare.as_ref().map(|m| (name.as_str(), m)),
        reads: &reads,
        degrees,
        save_model: write_coefficients,
    };
    let json = omniad_validate::report::run(&a.set, &a.output, &opts)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        println!("wrote {}", a.output.join("report.md").display());
    }
    Ok(())
}
