//! `omniad report SET -o DIR`: everything of [`crate::section`],
//! [`crate::release`] and [`crate::resolution`] that applies to a
//! recording set, as `DIR/report.md` with SVG figures and `DIR/report.json`
//! (every file written atomically through `omniad-io`).
//!
//! The set is fitted once with the full pipeline at N = 8 and the fitted
//! model written to `DIR/model.omni` (so every figure's OmniAD curve can be
//! re-simulated: `omniad simulate DIR/model.omni`). A synthetic set (with
//! `truth/coefficients.csv`) also gets the C_F and C_T errors of that fit
//! against its generating model (`omniad lab accept`'s metric). The lift/drag section is
//! drawn when the object is a plate (name starting `plate`; normal +z, the
//! chord along x), the Fig. 12 release always (a plate is the paper's
//! 30 x 50 x 2 cm plate with the set's mass; other objects a box of the
//! markers' extents), the Fig. 8 sweep when the set is synthetic.

use crate::{accuracy, release, resolution, section};
use anyhow::{anyhow, Context, Result};
use nalgebra::Vector3;
use omniad_acquire::input::recording::RecordingSet;
use omniad_acquire::pipeline::{self, FitConfig};
use omniad_acquire::reconstruct::run::Silent;
use omniad_core::model::{Model, ModelKind};
use omniad_core::reference::shape::{Shape, ShapeKind};
use omniad_core::reference::taira::{DRAG, LIFT};
use omniad_core::{Coefficients, Environment, RigidBody};
use omniad_plot::{Figure, Series};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// What the report is asked for.
pub struct Options<'a> {
    /// The command that regenerates it (printed at the top).
    pub command: &'a str,
    /// Another coefficient file to compare with the measured curves
    /// (e.g. the bundled `data/plate.omni`), with its name.
    pub compare: Option<(&'a str, &'a Coefficients<f64>)>,
    /// The files the command read besides the set (the comparison file):
    /// like the set's own, the report never writes over one.
    pub reads: &'a [&'a Path],
    /// Degrees of the Fig. 8 sweep (empty: none).
    pub degrees: &'a [u8],
    /// Writes a coefficient file atomically (the CLI's `.omni` writer),
    /// used for `DIR/model.omni`.
    pub save_model: fn(&Path, &Coefficients<f64>) -> Result<()>,
}

/// The fitted model's file name in the report folder.
pub const MODEL_FILE: &str = "model.omni";

fn write(dir: &Path, name: &str, text: &str) -> Result<()> {
    let path = dir.join(name);
    omniad_io::write_atomic(&path, text.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

/// The body shape of the Fig. 12 release for `set`'s object.
fn shape_of(set: &RecordingSet) -> Shape {
    if set.object.name.starts_with("plate") {
        return Shape {
            mass: set.object.mass,
            ..Shape::PAPER_PLATE
        };
    }
    let mut size = Vector3::zeros();
    for (_, p) in &set.object.markers {
        size = size.zip_map(&p.abs(), |a: f64, b: f64| a.max(2.0 * b));
    }
    Shape {
        kind: ShapeKind::Box,
        size: size.map(|x| x.max(0.01)),
        mass: set.object.mass,
    }
}

/// Writes the report of the set in `set_dir` into `out`; returns its JSON.
pub fn run(set_dir: &Path, out: &Path, opts: &Options<'_>) -> Result<Value> {
    let set = RecordingSet::load(set_dir).map_err(|e| anyhow!("{e}"))?;
    refuse_inputs(out, &set, opts.reads)?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let fit =
        pipeline::fit(&set, &FitConfig::default(), &Silent).map_err(|e| anyhow!("fit: {e}"))?;
    let mut md = format!(
        "# Validation report: `{}`\n\nRegenerate: `{}`\n\nObject `{}`, {} takes; fitted with the full pipeline (`omniad fit`, N = 8).\n",
        set_dir.display(), opts.command, set.object.name, set.takes.len()
    );
    let mut json = json!({ "set": set_dir.display().to_string(), "object": set.object.name });
    (opts.save_model)(&out.join(MODEL_FILE), &fit.model)?;
    json["model_file"] = MODEL_FILE.into();
    let _ = writeln!(
        md,
        "\nThe fitted model is `{MODEL_FILE}` in this folder (re-simulate it with `omniad simulate {MODEL_FILE}`).",
    );
    if let Some(acc) = accuracy::against_truth(set_dir, &fit, &mut md)? {
        json["accuracy"] = acc;
    }
    let shape = shape_of(&set);
    if set.object.name.starts_with("plate") {
        json["fig13"] = fig13(out, &mut md, &fit.model, &shape, opts)?;
    }
    json["fig12"] = fig12(out, &mut md, &fit.model, &shape, &set)?;
    if !opts.degrees.is_empty() {
        if let Some(rows) = resolution::sweep(set_dir, &set, opts.degrees)? {
            json["fig8"] = fig8(out, &mut md, &rows)?;
        }
    }
    write(out, "report.md", &md)?;
    write(out, "report.json", &serde_json::to_string_pretty(&json)?)?;
    Ok(json)
}

/// An error, before any work, when a file the report writes in `out` is
/// one the command reads: the set's or one of `reads`
/// (`omniad_io::refuse_input`).
fn refuse_inputs(out: &Path, set: &RecordingSet, reads: &[&Path]) -> Result<()> {
    let inputs: Vec<&Path> = set
        .files
        .iter()
        .map(|p| p.as_path())
        .chain(reads.iter().copied())
        .collect();
    for name in ["report.md", "report.json", MODEL_FILE] {
        omniad_io::refuse_input(&out.join(name), &inputs)?;
    }
    Ok(())
}

fn fig13(
    out: &Path,
    md: &mut String,
    fit: &Coefficients<f64>,
    shape: &Shape,
    opts: &Options<'_>,
) -> Result<Value> {
    let area = shape.size.x * shape.size.y;
    let mut models = vec![("fitted", fit)];
    if let Some(c) = opts.compare {
        models.push(c);
    }
    let mut drag = Figure::new(
        "Drag section (α in the chordwise symmetry plane)",
        "angle of attack α, deg",
        "C_D (planform area)",
    )
    .with(Series::points(
        "measured (Taira et al. 2007, Re 100)",
        DRAG.iter()
            .filter(|p| p.0 <= section::MAX_ALPHA)
            .copied()
            .collect(),
    ));
    let mut lift = Figure::new(
        "Lift section (α in the chordwise symmetry plane)",
        "angle of attack α, deg",
        "C_L (planform area)",
    )
    .with(Series::points(
        "measured (Taira et al. 2007, Re 100)",
        LIFT.iter()
            .filter(|p| p.0 <= section::MAX_ALPHA)
            .copied()
            .collect(),
    ));
    let _ = write!(md, "\n## Fig. 13: lift and drag against measured curves\n\nSection at α = 0-60° (chord along x, normal +z), planform area {area:.3} m²; deviation L1 = Σ|model - measured| / Σ|measured| over the measured points (the paper: 13 % drag, 16 % lift against CFD). The measurements are at Re 100; a real foam plate falls at Re ~ 10⁵.\n\n| model | drag L1 | lift L1 |\n|---|---|---|\n");
    let mut rows = Vec::new();
    for (name, m) in models {
        let d = section::deviation(m, area);
        let c = section::curve(m, area, 1.0);
        drag = drag.with(Series::line(name, c.iter().map(|p| (p.0, p.1)).collect()));
        lift = lift.with(Series::line(name, c.iter().map(|p| (p.0, p.2)).collect()));
        let _ = writeln!(
            md,
            "| {name} | {:.1} % | {:.1} % |",
            100.0 * d.drag,
            100.0 * d.lift
        );
        rows.push(json!({ "model": name, "drag_l1": d.drag, "lift_l1": d.lift }));
    }
    write(out, "fig13-drag.svg", &drag.to_svg())?;
    write(out, "fig13-lift.svg", &lift.to_svg())?;
    md.push_str("\n![drag](fig13-drag.svg) ![lift](fig13-lift.svg)\n");
    Ok(Value::Array(rows))
}

fn fig12(
    out: &Path,
    md: &mut String,
    fit: &Coefficients<f64>,
    shape: &Shape,
    set: &RecordingSet,
) -> Result<Value> {
    let env = Environment {
        gravity: set.world.gravity,
        air_density: set.world.air_density,
        wind: Vector3::zeros(),
    };
    let body = RigidBody::new(shape.mass, shape.inertia()).map_err(|e| anyhow!("{e}"))?;
    let fit_body =
        RigidBody::new(set.object.mass, set.object.inertia).map_err(|e| anyhow!("{e}"))?;
    let _ = write!(md, "\n## Fig. 12: one release under each model\n\nReleased at rest {} m up, tilted 20° about body y; {:?} {:.2} x {:.2} x {:.2} m, {:.3} kg (the OmniAD run uses the set's inertia). Descriptors measured from the trajectory (60 Hz samples, RK4 at 1 ms): glide = horizontal distance at landing, flips = sign changes of the body normal's vertical component, tilt = acos|n_z|.\n\n| model | glide, m | flips | max tilt, deg | time to fall {} m, s | mean descent, m/s |\n|---|---|---|---|---|---|\n",
        release::HEIGHT, shape.kind, shape.size.x, shape.size.y, shape.size.z, shape.mass, release::HEIGHT);
    let mut side = Figure::new("Release: side view", "x, m", "z, m");
    let mut height = Figure::new("Release: height", "t, s", "z, m");
    let mut rows = Vec::new();
    for kind in ModelKind::ALL {
        let model = Model::new(kind, Some(shape), Some(fit), env).map_err(|e| anyhow!("{e}"))?;
        let b = if kind == ModelKind::Omniad {
            &fit_body
        } else {
            &body
        };
        let traj = release::run(&model, b, &env);
        let d = release::descriptors(&traj);
        side = side.with(Series::line(
            kind.name(),
            traj.iter()
                .map(|(_, s)| (s.position.x, s.position.z))
                .collect(),
        ));
        height = height.with(Series::line(
            kind.name(),
            traj.iter().map(|(t, s)| (*t, s.position.z)).collect(),
        ));
        let opt = |x: Option<f64>| x.map_or("-".into(), |v| format!("{v:.2}"));
        let _ = writeln!(
            md,
            "| {} | {:.2} | {} | {:.0} | {} | {} |",
            kind.name(),
            d.glide_m,
            d.flips,
            d.max_tilt_deg,
            opt(d.fall_time_s),
            opt(d.mean_descent_m_s)
        );
        rows.push(json!({ "model": kind.name(), "descriptors": d }));
    }
    write(out, "fig12-side.svg", &side.to_svg())?;
    write(out, "fig12-height.svg", &height.to_svg())?;
    md.push_str("\n![side view](fig12-side.svg) ![height](fig12-height.svg)\n");
    Ok(Value::Array(rows))
}

fn fig8(out: &Path, md: &mut String, rows: &[resolution::Row]) -> Result<Value> {
    let _ = write!(md, "\n## Fig. 8: SH degree N\n\nEvery third take (2, 5, ...) held out; the rest fitted with the full pipeline at each N. Errors on the held-out takes' true states against the set's generating model: relative force and torque RMS; RMS position error of the fitted model re-simulated from each held-out take's true start for {} s.\n\n| N | force error | torque error | trajectory error, m | fit time, s |\n|---|---|---|---|---|\n", resolution::HORIZON);
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {:.3} | {:.1} |",
            r.degree, r.force_error, r.torque_error, r.trajectory_error_m, r.fit_seconds
        );
    }
    let pts = |f: fn(&resolution::Row) -> f64| {
        rows.iter()
            .map(|r| (f64::from(r.degree), f(r)))
            .collect::<Vec<_>>()
    };
    let fig = Figure::new("Held-out error against N", "SH degree N", "relative error")
        .with(Series::line("force", pts(|r| r.force_error)))
        .with(Series::line("torque", pts(|r| r.torque_error)));
    write(out, "fig8-error.svg", &fig.to_svg())?;
    md.push_str("\n![error against N](fig8-error.svg)\n");
    Ok(serde_json::to_value(rows)?)
}
