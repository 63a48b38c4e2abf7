//! The SVG figures of `omniad residual --plots`: the base model's held-out
//! force residual against |V|, |Ω|, |dV/dt| and time in take (binned RMS),
//! its direction map (azimuth/elevation of V in the body frame, frames
//! split at the median residual), and each candidate's share of it.

use crate::residual::Report;
use omniad_plot::{Figure, Series};

/// The figures, `(file name, SVG text)`.
pub fn figures(r: &Report) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let names = ["speed", "spin", "acceleration", "time"];
    for (p, stem) in r.diagnosis.profiles.iter().zip(names) {
        let fig = Figure::new(
            format!(
                "held-out force residual of the base model vs {}",
                p.quantity
            ),
            p.quantity.clone(),
            "RMS residual force (N)",
        )
        .with(Series::line(
            "base model, held out",
            p.bins.iter().map(|b| (b.0, b.1)).collect(),
        ));
        out.push((format!("residual-vs-{stem}.svg"), fig.to_svg()));
    }
    let mut mags: Vec<f64> = r.diagnosis.directions.iter().map(|d| d.1).collect();
    mags.sort_by(f64::total_cmp);
    let median = mags.get(mags.len() / 2).copied().unwrap_or(0.0);
    let point = |d: &nalgebra::Vector3<f64>| {
        (
            d.y.atan2(d.x).to_degrees(),
            d.z.clamp(-1.0, 1.0).asin().to_degrees(),
        )
    };
    let split = |above: bool| -> Vec<(f64, f64)> {
        r.diagnosis
            .directions
            .iter()
            .filter(|d| (d.1 > median) == above)
            .map(|d| point(&d.0))
            .collect()
    };
    let fig = Figure::new(
        "direction map of the held-out residual (body frame)",
        "azimuth of V (deg)",
        "elevation of V (deg)",
    )
    .with(Series::points("residual below median", split(false)))
    .with(Series::points("residual above median", split(true)));
    out.push(("residual-directions.svg".into(), fig.to_svg()));
    let fig = Figure::new(
        "share of the held-out residual each candidate explains",
        "candidate (order of the report)",
        "R²",
    )
    .with(Series::points(
        "R²",
        r.diagnosis
            .explained
            .iter()
            .enumerate()
            .map(|(i, e)| (i as f64, e.1))
            .collect(),
    ));
    out.push(("residual-explained.svg".into(), fig.to_svg()));
    out
}
