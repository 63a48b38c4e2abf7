//! `omniad synth`: a recording set with `truth/` from a known coefficient
//! model (the project's generator; used by the tests).

use anyhow::Result;
use clap::{Args, ValueEnum};
use omniad_acquire::synth::{Effect, SynthConfig, SynthObject, ThrowSpeed};
use std::path::{Path, PathBuf};

/// Object to simulate.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ObjectArg {
    /// Foam plate 30 x 50 x 2 cm, 48 g.
    Plate,
    /// Box-kite cell 30 x 40 x 20 cm open along y, 40 g.
    Box,
    /// The plate (30 x 50 x 2 cm, 48 g) with the measured flat-plate lift
    /// and drag of Taira et al. 2007 (Re 100) instead of the panel model.
    TairaPlate,
}

/// Arguments of `omniad synth`.
#[derive(Args, Debug)]
pub struct SynthArgs {
    /// Output folder (created). An existing non-empty folder is refused
    /// unless --force is given (its files would be replaced).
    pub out: PathBuf,
    /// Write into OUT even if it already holds files (replacing them).
    #[arg(long)]
    pub force: bool,
    /// Object.
    #[arg(long, value_enum, default_value_t = ObjectArg::Plate)]
    pub object: ObjectArg,
    /// Effect outside the OmniAD model, `NAME[=SCALE]`, repeatable; SCALE 1
    /// is physical: buoyancy (V_b = SCALE x the bounding box's volume),
    /// added_mass (SCALE x the potential-flow added-mass tensor of the
    /// ellipsoid inscribed in the bounding box, Lamb §114),
    /// added_mass_coupling (the same M_a's velocity terms -Ω×(M_a V) and
    /// -V×(M_a V) without the acceleration reaction -M_a dV/dt: the air of
    /// a stateless fluid model such as MuJoCo's), rotational_lift
    /// (ρL³ c Ω×V, c = SCALE), magnus (rotational_lift with c = SCALE/2,
    /// i.e. ½ρL³ SCALE Ω×V), linear_drag (-k μ L V, k = SCALE x 3π, Stokes),
    /// propeller_thrust (½ρL⁴|Ω| K Ω, K = SCALE x Z Zᵀ with Z the pole).
    /// The force each effect then has is measured over the generated
    /// frames, RMS|F_effect| / RMS|F_aero| (F_aero the coefficient model's
    /// force; a --wind's force is the model's at the air velocity minus at
    /// the ground velocity), printed and written to truth/model.toml
    /// [force_fraction]; it grows linearly with SCALE only while the effect
    /// changes the trajectories little (issue 15's realistic strength:
    /// 0.15-0.5).
    #[arg(long)]
    pub effect: Vec<String>,
    /// Steady wind of the recording, world frame `x,y,z`, m/s (the physics
    /// sees the air velocity v - w; recorded in truth/model.toml).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub wind: Option<Vec<f64>>,
    /// Tracking noise, 1 sigma, px.
    #[arg(long, default_value_t = 0.7)]
    pub noise: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of drops (at most 1000; drops + spins at least 1).
    #[arg(long, default_value_t = 8)]
    pub drops: usize,
    /// Number of spinning throws (at most 1000).
    #[arg(long, default_value_t = 5)]
    pub spins: usize,
    /// Release speed of the spinning throws, `MIN,MAX` m/s: each throw
    /// leaves the hand at 1 m (the paper's K2 takes, §6) with a speed
    /// uniform in [MIN, MAX], 45-90° above the horizon at any azimuth
    /// (MAX at most 15 m/s). Without it a throw leaves at 3-4 m/s upward,
    /// ±0.5 m/s sideways (the default sets). Faster throws fly each
    /// body-frame direction at several speeds while they slow down, which
    /// is what separates a force linear in the air speed from C_F's |V|².
    #[arg(long, value_delimiter = ',', num_args = 1, allow_hyphen_values = true)]
    pub throw_speed: Option<Vec<f64>>,
    /// Fraction of marker rows replaced by tracker jumps (outliers).
    #[arg(long, default_value_t = 0.0)]
    pub outliers: f64,
}

/// The most drops (or spins) one set may hold: bounded work.
const MAX_TAKES: usize = 1000;

/// Largest tracking noise, px: beyond it the markers of the 720 x 1280
/// image say nothing about the pose (the largest marker spread seen is a
/// few hundred pixels), and `1e20` wrote a `recording.toml` TOML cannot
/// read back.
const MAX_NOISE_PX: f64 = 100.0;

/// Refuses an existing output that is a file or a non-empty folder,
/// unless `force`: `omniad synth` replaces files it writes.
fn refuse_existing(out: &Path, force: bool) -> Result<()> {
    if out.is_file() {
        anyhow::bail!("{} is a file, not a folder", out.display());
    }
    let non_empty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
    anyhow::ensure!(
        force || !non_empty,
        "{} already exists and is not empty; give --force to replace its files",
        out.display()
    );
    Ok(())
}

/// The `--wind` vector (zero when not given).
fn wind(w: Option<&[f64]>) -> Result<nalgebra::Vector3<f64>> {
    let Some(w) = w else {
        return Ok(nalgebra::Vector3::zeros());
    };
    anyhow::ensure!(
        w.len() == 3 && w.iter().all(|v| v.is_finite() && v.abs() <= 50.0),
        "--wind must be three finite components x,y,z in m/s (each at most 50)"
    );
    Ok(nalgebra::Vector3::new(w[0], w[1], w[2]))
}

/// The `--throw-speed` range (`None` when not given: the default throw).
fn throw_speed(t: Option<&[f64]>) -> Result<Option<ThrowSpeed>> {
    let Some(t) = t else {
        return Ok(None);
    };
    let [min, max] = t else {
        anyhow::bail!(
            "--throw-speed must be two speeds MIN,MAX in m/s, found {} numbers",
            t.len()
        );
    };
    ThrowSpeed::new(*min, *max)
        .map(Some)
        .map_err(|e| anyhow::anyhow!("--throw-speed: {e}"))
}

/// Runs `omniad synth`.
pub fn run(a: &SynthArgs) -> Result<()> {
    let effects = a
        .effect
        .iter()
        .map(|e| Effect::parse(e))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    anyhow::ensure!(
        a.noise.is_finite() && (0.0..=MAX_NOISE_PX).contains(&a.noise),
        "--noise must be a number of pixels in [0, {MAX_NOISE_PX}], found {}",
        a.noise
    );
    anyhow::ensure!(
        (0.0..=1.0).contains(&a.outliers),
        "--outliers must be a fraction in [0, 1]"
    );
    for (name, n) in [("--drops", a.drops), ("--spins", a.spins)] {
        anyhow::ensure!(
            n <= MAX_TAKES,
            "{name} must be at most {MAX_TAKES}, found {n}"
        );
    }
    anyhow::ensure!(
        a.drops + a.spins > 0,
        "--drops and --spins are both 0: a recording set needs at least one take"
    );
    refuse_existing(&a.out, a.force)?;
    let object = match a.object {
        ObjectArg::Plate => SynthObject::Plate,
        ObjectArg::Box => SynthObject::Box,
        ObjectArg::TairaPlate => SynthObject::TairaPlate,
    };
    let cfg = SynthConfig {
        object,
        effects,
        noise: a.noise,
        seed: a.seed,
        takes: (a.drops, a.spins),
        outliers: a.outliers,
        wind: wind(a.wind.as_deref())?,
        throw_speed: throw_speed(a.throw_speed.as_deref())?,
        ..SynthConfig::default()
    };
    let strengths =
        omniad_acquire::synth::write::generate(&a.out, &cfg).map_err(|e| anyhow::anyhow!("{e}"))?;
    println!("wrote {}", a.out.display());
    for (name, f) in strengths {
        println!(
            "effect {name}: RMS force {:.1} % of the aerodynamic force's",
            f * 100.0
        );
    }
    Ok(())
}
