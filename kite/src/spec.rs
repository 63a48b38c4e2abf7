//! The kite file (TOML): what a designer writes. See `data/kites/README.md`
//! for the documented format. Parsing rejects unknown fields; validation
//! names the offending field (`primitive[1].size`, `string.gamma`, ...).

use crate::rod_end::RodEnd;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A whole kite file.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct KiteSpec {
    /// Short name.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Wind and air.
    #[serde(default)]
    pub wind: WindSpec,
    /// String attachment.
    #[serde(default)]
    pub string: StringSpec,
    /// Rod and covering materials.
    #[serde(default)]
    pub materials: Materials,
    /// The kite's orientation R in the wind (body -> world; world x is
    /// downwind, z up): rotations about x, then y, then z, degrees.
    #[serde(default)]
    pub orientation: [f64; 3],
    /// The primitives.
    #[serde(default, rename = "primitive")]
    pub primitives: Vec<PrimitiveSpec>,
    /// Extra rods (spars, longerons), besides each primitive's own frame.
    #[serde(default, rename = "rod", skip_serializing_if = "Vec::is_empty")]
    pub rods: Vec<RodSpec>,
}

/// `[wind]`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WindSpec {
    /// Mean wind speed along world +x, m/s.
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// Air density ρ, kg/m³.
    #[serde(default = "default_density")]
    pub air_density: f64,
}

impl Default for WindSpec {
    fn default() -> Self {
        Self {
            speed: default_speed(),
            air_density: default_density(),
        }
    }
}

fn default_speed() -> f64 {
    5.0
}
fn default_density() -> f64 {
    1.2
}

/// `[string]`: where the string is attached, on the line of eq. (16).
/// Give at most one of `gamma` and `offset`; neither means `offset = 0`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StringSpec {
    /// γ of eq. (16), m/N.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gamma: Option<f64>,
    /// The same as a distance along the string direction from the line's
    /// foot point, m (`γ |F_string|`); positive is towards the anchor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    /// Line length for the flight simulation, m.
    #[serde(default = "default_line")]
    pub length: f64,
}

impl Default for StringSpec {
    fn default() -> Self {
        Self {
            gamma: None,
            offset: None,
            length: default_line(),
        }
    }
}

fn default_line() -> f64 {
    20.0
}

/// `[materials]`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Materials {
    /// Default rod diameter, m (carbon rod, 2 mm as in the paper).
    #[serde(default = "default_rod_diameter")]
    pub rod_diameter: f64,
    /// Rod material density, kg/m³ (carbon fibre: 1600).
    #[serde(default = "default_rod_density")]
    pub rod_density: f64,
    /// Covering areal density, kg/m² (kitchen plastic wrap: about 0.011).
    #[serde(default = "default_covering")]
    pub covering_density: f64,
    /// Mass of one printed socket, kg.
    #[serde(default = "default_socket")]
    pub socket_mass: f64,
}

impl Default for Materials {
    fn default() -> Self {
        Self {
            rod_diameter: default_rod_diameter(),
            rod_density: default_rod_density(),
            covering_density: default_covering(),
            socket_mass: default_socket(),
        }
    }
}

fn default_rod_diameter() -> f64 {
    0.002
}
fn default_rod_density() -> f64 {
    1600.0
}
fn default_covering() -> f64 {
    0.011
}
fn default_socket() -> f64 {
    0.002
}

/// Kind of primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Cuboid open on its two y faces (a kite cell).
    Box,
    /// A covered rectangle in the x-y plane (`l_z = 0`).
    Plate,
    /// Any fitted `.omni` object (e.g. the foam heart).
    Object,
}

impl Kind {
    /// The name in a kite file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Box => "box",
            Self::Plate => "plate",
            Self::Object => "object",
        }
    }
}

/// `[[primitive]]`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PrimitiveSpec {
    /// Name (unique), used in reports and the cut list.
    pub name: String,
    /// `box`, `plate` or `object`.
    pub kind: Kind,
    /// `[l_x, l_y, l_z]`, m: y is the open axis of a box, x the longer
    /// edge of its closed face (`l_x >= l_z`); a plate has `l_z = 0`; an
    /// object gives its bounding box (for drawings and the overlap test).
    pub size: [f64; 3],
    /// Centre, design (body) frame, m.
    #[serde(default)]
    pub position: [f64; 3],
    /// Q_p: rotations about x, then y, then z (fixed axes), degrees.
    #[serde(default)]
    pub rotation: [f64; 3],
    /// Objects only: the `.omni` file, relative to the kite file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// Objects only: mass, kg (else the file's mass properties).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Boxes and plates: build the edges from rods (default true).
    #[serde(default = "yes")]
    pub frame: bool,
}

fn yes() -> bool {
    true
}

/// `[[rod]]`: a straight rod between two ends, each a named corner or
/// edge point of a primitive (or, in old files, a design-frame point);
/// see [`crate::rod_end`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// One end.
    pub from: RodEnd,
    /// Other end.
    pub to: RodEnd,
    /// Diameter, m (default `materials.rod_diameter`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
}

impl KiteSpec {
    /// Reads and validates a kite file; errors name the file and field.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read kite file {}", path.display()))?;
        Self::parse(&text).with_context(|| format!("in kite file {}", path.display()))
    }

    /// The spec as kite-file TOML text, rod ends as inline tables
    /// ([`crate::toml_writer`]); [`KiteSpec::parse`] reads it back to an
    /// equal spec.
    pub fn to_toml(&self) -> Result<String> {
        let head = Self {
            rods: Vec::new(),
            ..self.clone()
        };
        let mut text = toml::to_string(&head).context("cannot write the kite as TOML")?;
        for (k, r) in self.rods.iter().enumerate() {
            crate::toml_writer::write_rod(&mut text, &r.from, &r.to, r.diameter)
                .with_context(|| format!("cannot write rod[{k}] as TOML"))?;
        }
        Ok(text)
    }

    /// Writes the spec to `path` atomically (temporary file + rename), so
    /// a failed save leaves the old file whole.
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = self.to_toml()?;
        omniad_io::write_atomic(path, text.as_bytes())
            .with_context(|| format!("cannot write kite file {}", path.display()))
    }

    /// Parses and validates TOML text.
    pub fn parse(text: &str) -> Result<Self> {
        let spec: KiteSpec = toml::from_str(text).context("invalid kite TOML")?;
        spec.validate()?;
        Ok(spec)
    }

    /// Checks every number; the error names the field.
    pub fn validate(&self) -> Result<()> {
        positive("wind.speed", self.wind.speed)?;
        if self.wind.speed > MAX_WIND_SPEED {
            bail!(
                "wind.speed: must be at most {MAX_WIND_SPEED} m/s (got {})",
                self.wind.speed
            );
        }
        positive("wind.air_density", self.wind.air_density)?;
        positive("string.length", self.string.length)?;
        if self.string.gamma.is_some() && self.string.offset.is_some() {
            bail!("string: give `gamma` or `offset`, not both");
        }
        finite("string.gamma", self.string.gamma.unwrap_or(0.0))?;
        finite("string.offset", self.string.offset.unwrap_or(0.0))?;
        positive("materials.rod_diameter", self.materials.rod_diameter)?;
        positive("materials.rod_density", self.materials.rod_density)?;
        non_negative(
            "materials.covering_density",
            self.materials.covering_density,
        )?;
        non_negative("materials.socket_mass", self.materials.socket_mass)?;
        all_finite("orientation", &self.orientation)?;
        if self.primitives.is_empty() {
            bail!("primitive: a kite needs at least one [[primitive]]");
        }
        for (i, p) in self.primitives.iter().enumerate() {
            p.validate(&format!("primitive[{i}]"))?;
            if self.primitives.iter().take(i).any(|q| q.name == p.name) {
                bail!("primitive[{i}].name: duplicate name {:?}", p.name);
            }
        }
        for (i, r) in self.rods.iter().enumerate() {
            self.validate_rod(i, r)?;
        }
        Ok(())
    }

    /// A `[[rod]]`: both ends name a primitive of this kite and a corner
    /// or edge it has (or are finite points), and are not the same point.
    fn validate_rod(&self, i: usize, r: &RodSpec) -> Result<()> {
        let mut units = Vec::new();
        for (end, which) in [(&r.from, "from"), (&r.to, "to")] {
            let field = format!("rod[{i}].{which}");
            match end {
                RodEnd::Point(p) => all_finite(&field, p)?,
                RodEnd::On(f) => {
                    let Some(p) = self.primitives.iter().find(|p| p.name == f.primitive) else {
                        let names: Vec<&str> =
                            self.primitives.iter().map(|p| p.name.as_str()).collect();
                        bail!(
                            "{field}.primitive: no primitive named {:?} (the kite has: {})",
                            f.primitive,
                            names.join(", ")
                        );
                    };
                    units.push((&f.primitive, f.unit(&p.size, &field)?));
                }
            }
        }
        let same = match (&r.from, &r.to, &units[..]) {
            (RodEnd::Point(a), RodEnd::Point(b), _) => {
                (0..3).map(|k| (b[k] - a[k]).powi(2)).sum::<f64>() < 1e-6
            }
            (_, _, [(pa, ua), (pb, ub)]) => pa == pb && (ua - ub).norm() < 1e-9,
            _ => false,
        };
        if same {
            bail!("rod[{i}]: `from` and `to` are the same point");
        }
        if let Some(d) = r.diameter {
            positive(&format!("rod[{i}].diameter"), d)?;
        }
        Ok(())
    }

    /// γ (m/N) or offset (m) as given; `(None, None)` means offset 0.
    pub fn attachment(&self) -> Attachment {
        match (self.string.gamma, self.string.offset) {
            (Some(g), _) => Attachment::Gamma(g),
            (None, Some(d)) => Attachment::Offset(d),
            (None, None) => Attachment::Offset(0.0),
        }
    }
}

/// How the attachment point on the eq. (16) line is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attachment {
    /// γ, m/N.
    Gamma(f64),
    /// Distance along the string direction from the foot point, m.
    Offset(f64),
}

impl PrimitiveSpec {
    fn validate(&self, at: &str) -> Result<()> {
        if self.name.trim().is_empty() {
            bail!("{at}.name: must not be empty");
        }
        all_finite(&format!("{at}.position"), &self.position)?;
        all_finite(&format!("{at}.rotation"), &self.rotation)?;
        all_finite(&format!("{at}.size"), &self.size)?;
        bounded(&format!("{at}.position"), &self.position, MAX_EXTENT)?;
        bounded(&format!("{at}.size"), &self.size, MAX_EXTENT)?;
        let [lx, ly, lz] = self.size;
        let field = format!("{at}.size");
        match self.kind {
            Kind::Box => {
                if !(lx > 0.0 && ly > 0.0 && lz > 0.0) {
                    bail!(
                        "{field}: a box needs l_x, l_y, l_z > 0 (got {:?})",
                        self.size
                    );
                }
                if lz > lx {
                    bail!("{field}: l_x must be >= l_z (x is the longer edge of the closed face); rotate the box 90 degrees about y instead");
                }
            }
            Kind::Plate => {
                if !(lx > 0.0 && ly > 0.0) || lz != 0.0 {
                    bail!(
                        "{field}: a plate needs l_x, l_y > 0 and l_z = 0 (got {:?})",
                        self.size
                    );
                }
            }
            Kind::Object => {
                if !(lx >= 0.0 && ly >= 0.0 && lz >= 0.0) {
                    bail!("{field}: sizes must be >= 0 (got {:?})", self.size);
                }
                if self.file.is_none() {
                    bail!("{at}.file: an object primitive needs the .omni file");
                }
                if let Some(m) = self.mass {
                    positive(&format!("{at}.mass"), m)?;
                }
            }
        }
        if self.kind != Kind::Object && (self.file.is_some() || self.mass.is_some()) {
            bail!("{at}: `file` and `mass` are only for kind = \"object\"");
        }
        Ok(())
    }
}

fn finite(field: &str, x: f64) -> Result<()> {
    if !x.is_finite() {
        bail!("{field}: must be a finite number (got {x})");
    }
    Ok(())
}

/// The strongest wind a kite is checked or flown in, m/s (hurricane force
/// is 33 m/s): the kite file's `wind.speed` and the commands' `--wind`.
pub const MAX_WIND_SPEED: f64 = 60.0;

/// The largest length a kite file may give (a primitive's extent or
/// position), m: the largest kites flown are tens of metres; 1e308 was
/// reported as "primitive size is zero" or a non-finite wrench.
pub const MAX_EXTENT: f64 = 1e3;

/// Every value of `field` within `±max` (m).
fn bounded(field: &str, values: &[f64], max: f64) -> Result<()> {
    if let Some(v) = values.iter().find(|v| v.abs() > max) {
        bail!("{field}: each value must be within ±{max} m (got {v:e})");
    }
    Ok(())
}

fn positive(field: &str, x: f64) -> Result<()> {
    if !(x.is_finite() && x > 0.0) {
        bail!("{field}: must be a positive number (got {x})");
    }
    Ok(())
}

fn non_negative(field: &str, x: f64) -> Result<()> {
    if !(x.is_finite() && x >= 0.0) {
        bail!("{field}: must be zero or positive (got {x})");
    }
    Ok(())
}

fn all_finite(field: &str, xs: &[f64]) -> Result<()> {
    if xs.iter().any(|x| !x.is_finite()) {
        bail!("{field}: every component must be finite (got {xs:?})");
    }
    Ok(())
}
