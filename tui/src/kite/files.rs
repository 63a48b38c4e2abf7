//! Kite files and the KiteShop analyser from the kite crate
//! (`omniad-kite`): load a `.toml` kite file into the view's [`Design`],
//! and analyse designs with the crate's blended primitive library.

use super::design::{rotation, Analyser, Analysis, Design, Kind, Part};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::kite::{stability, statics};
use omniad_kite::spec::{self, Attachment, KiteSpec};
use omniad_kite::Library;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The bundled demo kite file (the kite crate's classic box kite).
pub const BUNDLED_KITE: &str = include_str!("../../../data/kites/box-classic.toml");

/// [`Analyser`] on the kite crate: primitives blended from the library
/// (or loaded objects), the crate's mass model, the core's statics.
pub struct KiteShopAnalyser {
    /// The primitive library.
    pub library: Library,
    /// Directory object files are relative to.
    pub base: PathBuf,
}

impl KiteShopAnalyser {
    /// The library at its default place (`$OMNIAD_PRIMITIVES` or the
    /// repository's `data/primitives`).
    pub fn load_default(base: PathBuf) -> Result<Self, String> {
        let dir = omniad_kite::library::default_dir();
        let library = Library::load(&dir).map_err(|e| format!("{e:#}"))?;
        Ok(Self { library, base })
    }

    fn assemble(&self, design: &Design) -> Result<omniad_kite::Design, String> {
        let spec = KiteSpec::parse(&design.to_toml()).map_err(|e| format!("{e:#}"))?;
        omniad_kite::Design::assemble(spec, &self.base, &self.library).map_err(|e| format!("{e:#}"))
    }
}

impl Analyser for KiteShopAnalyser {
    fn analyse(&self, design: &Design) -> Result<Analysis, String> {
        let d = self.assemble(design)?;
        let prims = d.primitives();
        let kite = d.kite(&prims);
        let cond = d.conditions(None);
        let r = UnitQuaternion::from_matrix(&rotation(&design.orientation));
        let eq = statics::equilibrium(&kite, &cond, &r).map_err(|e| e.to_string())?;
        let gamma = statics::gamma_for_distance(&eq, design.offset).map_err(|e| e.to_string())?;
        let p = statics::attachment_point(&eq, gamma).map_err(|e| e.to_string())?;
        let st = stability::stability(&kite, &cond, &r, &p).map_err(|e| e.to_string())?;
        Ok(Analysis {
            mass: d.mass.mass,
            tension: eq.string_world,
            pulls_down: eq.pulls_down,
            torque: statics::unbalanced_torque(&eq, &p),
            attachment: p,
            gamma,
            axes: st.axes.map(|a| (a.eigenvalue, a.axis)),
        })
    }
}

/// Reads a kite file into a [`Design`]; `γ` is turned into the offset
/// along the string with `analyser` (the view edits offsets).
pub fn load(path: &Path, library: &Library) -> Result<Design, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    parse(&text, &base, library)
}

/// Parses kite-file text into a [`Design`] (see [`load`]).
pub fn parse(text: &str, base: &Path, library: &Library) -> Result<Design, String> {
    let spec = KiteSpec::parse(text).map_err(|e| format!("{e:#}"))?;
    let offset = match spec.attachment() {
        Attachment::Offset(d) => d,
        Attachment::Gamma(g) => {
            let d = omniad_kite::Design::assemble(spec.clone(), base, library)
                .map_err(|e| format!("{e:#}"))?;
            let prims = d.primitives();
            let eq = statics::equilibrium(&d.kite(&prims), &d.conditions(None), &d.orientation())
                .map_err(|e| e.to_string())?;
            statics::gamma_distance(&eq, g)
        }
    };
    Ok(from_spec(&spec, offset))
}

fn from_spec(spec: &KiteSpec, offset: f64) -> Design {
    let parts = spec.primitives.iter().map(part).collect();
    Design {
        name: spec.name.clone(),
        wind_speed: spec.wind.speed,
        air_density: spec.wind.air_density,
        offset,
        orientation: spec.orientation,
        parts,
        description: spec.description.clone(),
        line_length: spec.string.length,
        tables: tables(spec),
    }
}

fn part(p: &spec::PrimitiveSpec) -> Part {
    let kind = match p.kind {
        spec::Kind::Box => Kind::Box,
        spec::Kind::Plate => Kind::Plate,
        spec::Kind::Object => Kind::Object,
    };
    let mut extra = String::new();
    if let Some(f) = &p.file {
        let _ = writeln!(extra, "file = {:?}", f.to_string_lossy());
    }
    if let Some(m) = p.mass {
        let _ = writeln!(extra, "mass = {m}");
    }
    if !p.frame {
        let _ = writeln!(extra, "frame = false");
    }
    Part {
        name: p.name.clone(),
        kind,
        size: p.size,
        position: p.position,
        rotation: p.rotation,
        extra,
    }
}

fn tables(spec: &KiteSpec) -> String {
    let m = &spec.materials;
    let mut s = format!(
        "[materials]\nrod_diameter = {}\nrod_density = {}\ncovering_density = {}\nsocket_mass = {}\n\n",
        m.rod_diameter, m.rod_density, m.covering_density, m.socket_mass
    );
    for r in &spec.rods {
        let v = |a: &[f64; 3]| {
            Vector3::from(*a)
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(s, "[[rod]]\nfrom = [{}]\nto = [{}]", v(&r.from), v(&r.to));
        if let Some(d) = r.diameter {
            let _ = writeln!(s, "diameter = {d}");
        }
        s.push('\n');
    }
    s
}

/// The kite view for a real run: the kite file at `path` if it exists
/// (else the bundled box kite), analysed with the kite crate. Falls back
/// to the built-in demo on the plate model `plate`, with the reason shown.
pub fn kite_view(path: Option<&str>, plate: &omniad_core::Coefficients<f64>) -> super::KiteView {
    let save = path.unwrap_or("kite.toml").to_string();
    let file = path.map(Path::new).filter(|p| p.exists());
    let base = file
        .and_then(Path::parent)
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let loaded = KiteShopAnalyser::load_default(base.clone()).and_then(|a| {
        let design = match file {
            Some(f) => load(f, &a.library)?,
            None => parse(BUNDLED_KITE, &base, &a.library)?,
        };
        Ok((a, design))
    });
    match loaded {
        Ok((a, design)) => super::KiteView::new(design, Box::new(a), save),
        Err(e) => {
            let analyser = super::design::PlateAnalyser {
                plate: plate.clone(),
            };
            let mut v = super::KiteView::new(Design::demo(), Box::new(analyser), save);
            v.message = format!("kite crate unavailable, plate panels used: {e}");
            v
        }
    }
}
