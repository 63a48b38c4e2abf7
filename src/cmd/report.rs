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
    // The report's files must not replace what it reads: the set's files
    // or the file it compares with.
    let set_files = omniad_acquire::input::recording::RecordingSet::load(&a.set)
        .map(|s| s.files)
        .unwrap_or_default();
    let inputs: Vec<&std::path::Path> = set_files
        .iter()
        .map(|p| p.as_path())
        .chain(a.compare.as_deref())
        .collect();
    for name in [
        "report.md",
        "report.json",
        omniad_validate::report::MODEL_FILE,
    ] {
        super::common::refuse_input(&a.output.join(name), &inputs)?;
    }
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
    let opts = omniad_validate::report::Options {
        command: &command,
        compare: compare.as_ref().map(|m| (name.as_str(), m)),
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
