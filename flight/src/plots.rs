//! The SVG figures of `omniad flight fit --plots`: measured against
//! predicted force over a held-out cycle, before and after the selected
//! effects, and the base model's residual against each candidate's channel.

use crate::fit::Design;
use crate::report::Cycles;
use crate::sample::Sample;
use nalgebra::DVector;
use omniad_plot::{Figure, Series};

/// A channel to plot the residual against: file stem, axis label, value.
type Channel = (&'static str, &'static str, fn(&Sample) -> f64);

/// The figures, `(file name, SVG text)`.
pub fn figures(
    base: &Design,
    base_theta: &DVector<f64>,
    design: &Design,
    theta: &DVector<f64>,
    train: &Cycles,
    test: &Cycles,
) -> Vec<(String, String)> {
    let mut out = Vec::new();
    if let Some((n, cycle)) = test.first() {
        let series = |name: &str, f: &dyn Fn(&Sample) -> f64| {
            Series::line(name, cycle.iter().map(|s| (s.time, f(s))).collect())
        };
        let fig = Figure::new(
            format!("cycle {n} (held out): aerodynamic force, body z (FRD)"),
            "time in cycle (s)",
            "F_z (N)",
        )
        .with(series("measured", &|s| s.aero_force.z))
        .with(series("base model", &|s| base.predict(base_theta, s).z))
        .with(series("with selected effects", &|s| {
            design.predict(theta, s).z
        }));
        out.push(("force-vs-time.svg".to_owned(), fig.to_svg()));
    }
    let channels: [Channel; 5] = [
        ("depower", "depower (fraction)", |s| s.depower),
        ("steering", "steering (fraction)", |s| s.steering),
        ("tether-length", "tether length (m)", |s| s.tether_length),
        ("acceleration", "|a| (m/s²)", |s| s.acceleration.norm()),
        ("rates", "|Ω| (rad/s)", |s| s.rates.norm()),
    ];
    for (file, label, f) in channels {
        let pts = train
            .iter()
            .flat_map(|c| c.1.iter())
            .step_by(5)
            .map(|s| (f(s), (s.aero_force - base.predict(base_theta, s)).norm()))
            .collect();
        let fig = Figure::new(
            format!("base model's residual against {label} (training cycles)"),
            label,
            "|F_measured - F_base| (N)",
        )
        .with(Series::points("samples", pts));
        out.push((format!("residual-vs-{file}.svg"), fig.to_svg()));
    }
    out
}
