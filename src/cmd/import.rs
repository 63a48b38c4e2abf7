//! `omniad import-tracks`: DLTdv / DeepLabCut marker tracks to the recording
//! format's `frame,marker,u,v` (see `omniad_acquire::input::import` for the
//! conventions).

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use omniad_acquire::input::import::{self, ImportOptions};
use std::path::PathBuf;

/// Tracker export format.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TrackFormat {
    /// DLTdv `*xypts.csv` (MATLAB pixels: 1-based, Y up; see --height).
    Dltdv,
    /// DeepLabCut CSV (OpenCV pixels).
    Dlc,
}

/// Arguments of `omniad import-tracks`.
#[derive(Args, Debug)]
pub struct ImportArgs {
    /// Tracker export file.
    pub input: PathBuf,
    /// Output marker-track CSV.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Format of the input.
    #[arg(long, value_enum)]
    pub format: TrackFormat,
    /// Point to marker, `POINT=MARKER` (DLTdv `pt1`, DeepLabCut body part); repeatable.
    #[arg(long = "map", required = true)]
    pub map: Vec<String>,
    /// Image height (px, positive); flips Y (`v = height - Y`). DLTdv: give it.
    #[arg(long)]
    pub height: Option<f64>,
    /// Pixels are 1-based (MATLAB, DLTdv): subtract 1 from u (and v when not flipped).
    #[arg(long)]
    pub one_based: bool,
    /// DLTdv camera number.
    #[arg(long, default_value_t = 1)]
    pub camera: usize,
    /// DeepLabCut: minimum likelihood (0 to 1) of a point to count as visible.
    #[arg(long, default_value_t = 0.9)]
    pub min_likelihood: f64,
    /// Frame index of the first data row.
    #[arg(long, default_value_t = 0)]
    pub first_frame: i64,
}

/// Runs `omniad import-tracks`.
pub fn run(a: &ImportArgs) -> Result<()> {
    let mut mapping = Vec::with_capacity(a.map.len());
    for m in &a.map {
        let (p, k) = m
            .split_once('=')
            .with_context(|| format!("--map `{m}`: expected POINT=MARKER"))?;
        mapping.push((p.to_owned(), k.to_owned()));
    }
    let o = ImportOptions {
        mapping,
        camera: a.camera,
        y_up_height: a.height,
        pixel_offset: if a.one_based { 1.0 } else { 0.0 },
        min_likelihood: a.min_likelihood,
        first_frame: a.first_frame,
    };
    super::common::refuse_input(&a.output, &[&a.input])?;
    let rows = match a.format {
        TrackFormat::Dltdv => import::read_dltdv(&a.input, &o),
        TrackFormat::Dlc => import::read_deeplabcut(&a.input, &o),
    }
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    import::write_marker_csv(&a.output, &rows).map_err(|e| anyhow::anyhow!("{e}"))?;
    println!("wrote {} rows to {}", rows.len(), a.output.display());
    Ok(())
}
