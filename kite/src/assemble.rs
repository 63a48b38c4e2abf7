//! A kite file turned into what the statics and the simulation need:
//! per-primitive coefficients (blended or loaded), `Q_p`, `Y_p` relative to
//! the centre of mass, and the rigid body.

use crate::geometry::{self, Panel, Rod};
use crate::joints::{self, Joint};
use crate::library::Library;
use crate::mass::{self, MassItem, MassProperties};
use crate::spec::{Kind, KiteSpec};
use anyhow::{bail, Context, Result};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use omniad_core::kite::{Conditions, Kite, Primitive};
use omniad_core::{Coefficients, RigidBody};
use std::path::Path;

/// An assembled kite.
#[derive(Clone, Debug)]
pub struct Design {
    /// The file as written.
    pub spec: KiteSpec,
    /// Coefficients per primitive (same order as `spec.primitives`).
    pub coefficients: Vec<Coefficients<f64>>,
    /// `Q_p` per primitive.
    pub rotations: Vec<Matrix3<f64>>,
    /// `Y_p` per primitive: centre relative to the kite's centre of mass, m.
    pub offsets: Vec<Vector3<f64>>,
    /// Mass properties (design frame centre).
    pub mass: MassProperties,
    /// Every rod.
    pub rods: Vec<Rod>,
    /// Every covered face.
    pub panels: Vec<Panel>,
    /// Every rod joint (one socket each).
    pub joints: Vec<Joint>,
}

impl Design {
    /// Loads, validates and assembles a kite file.
    pub fn load(path: &Path, library: &Library) -> Result<Self> {
        let spec = KiteSpec::load(path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::assemble(spec, base, library)
            .with_context(|| format!("in kite file {}", path.display()))
    }

    /// Assembles a validated spec; object files are relative to `base`.
    pub fn assemble(spec: KiteSpec, base: &Path, library: &Library) -> Result<Self> {
        let rods = geometry::all_rods(&spec)?;
        let panels: Vec<Panel> = spec.primitives.iter().flat_map(geometry::panels).collect();
        let joints = joints::joints(&rods);
        let mut extra: Vec<MassItem> = joints
            .iter()
            .map(|j| mass::point_item(spec.materials.socket_mass, j.position))
            .collect();
        let mut coefficients = Vec::new();
        let mut rotations = Vec::new();
        for (i, p) in spec.primitives.iter().enumerate() {
            let q = geometry::rotation_from_degrees(&p.rotation);
            let c = match p.kind {
                Kind::Box | Kind::Plate => library.blend(&p.size, &p.name)?,
                Kind::Object => {
                    let (c, item) = load_object(&spec, i, base, &q)?;
                    extra.push(item);
                    c
                }
            };
            coefficients.push(c);
            rotations.push(q);
        }
        let m = spec.materials.clone();
        let mass = mass::kite_mass(&rods, &panels, m.rod_density, m.covering_density, &extra)
            .context("the kite has no mass (no rods, coverings or objects)")?;
        let offsets = spec
            .primitives
            .iter()
            .map(|p| Vector3::from(p.position) - mass.center)
            .collect();
        Ok(Self {
            spec,
            coefficients,
            rotations,
            offsets,
            mass,
            rods,
            panels,
            joints,
        })
    }

    /// The core's view of the primitives (borrowing the coefficients).
    pub fn primitives(&self) -> Vec<Primitive<'_, f64>> {
        self.coefficients
            .iter()
            .zip(&self.rotations)
            .zip(&self.offsets)
            .map(|((c, q), y)| Primitive {
                coefficients: c,
                rotation: *q,
                offset: *y,
            })
            .collect()
    }

    /// The kite for the core statics.
    pub fn kite<'a>(&self, primitives: &'a [Primitive<'a, f64>]) -> Kite<'a, f64> {
        Kite {
            primitives,
            mass: self.mass.mass,
        }
    }

    /// Wind along +x at `speed` (m/s; default the file's), standard gravity.
    pub fn conditions(&self, speed: Option<f64>) -> Conditions<f64> {
        let mut c = Conditions::standard(speed.unwrap_or(self.spec.wind.speed));
        c.air_density = self.spec.wind.air_density;
        c
    }

    /// The file's orientation R.
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        let [x, y, z] = self.spec.orientation.map(f64::to_radians);
        UnitQuaternion::from_euler_angles(x, y, z)
    }

    /// The rigid body (mass, inertia about the centre of mass).
    pub fn body(&self) -> Result<RigidBody<f64>> {
        RigidBody::new(self.mass.mass, self.mass.inertia)
            .map_err(|e| anyhow::anyhow!("kite mass properties: {e}"))
    }

    /// Primitive pairs overlapping along the wind at orientation R (§7).
    pub fn overlaps(&self, orientation: &UnitQuaternion<f64>) -> Vec<(String, String)> {
        let wind_body = orientation.inverse_transform_vector(&Vector3::x());
        geometry::wind_overlaps(&self.spec, &wind_body, 0.005)
            .into_iter()
            .map(|(i, j)| {
                (
                    self.spec.primitives[i].name.clone(),
                    self.spec.primitives[j].name.clone(),
                )
            })
            .collect()
    }

    /// Rejects designs with primitives overlapping along the wind, naming them.
    pub fn reject_overlaps(&self, orientation: &UnitQuaternion<f64>) -> Result<()> {
        let o = self.overlaps(orientation);
        if let Some((a, b)) = o.first() {
            bail!(
                "primitive: {a:?} and {b:?} overlap along the wind direction (the paper forbids this: the upstream one would shadow the other); move or rotate one of them"
            );
        }
        Ok(())
    }
}

/// Loads an object primitive's `.omni` and its mass item (design frame).
fn load_object(
    spec: &KiteSpec,
    i: usize,
    base: &Path,
    q: &Matrix3<f64>,
) -> Result<(Coefficients<f64>, MassItem)> {
    let p = &spec.primitives[i];
    let at = format!("primitive[{i}]");
    let file = p
        .file
        .as_ref()
        .with_context(|| format!("{at}.file: missing"))?;
    let path = base.join(file);
    let bytes = std::fs::read(&path)
        .with_context(|| format!("{at}.file: cannot read {}", path.display()))?;
    let c = omniad_core::file::decode::<f64>(&bytes)
        .map_err(|e| anyhow::anyhow!("{at}.file: {}: {e}", path.display()))?;
    let center = Vector3::from(p.position);
    let item = match (p.mass, c.body) {
        (Some(m), _) => mass::point_item(m, center),
        (None, Some(b)) => {
            let local = omniad_core::math::symmetric_from_six(b.inertia);
            MassItem {
                mass: b.mass,
                center,
                inertia: q * local * q.transpose(),
            }
        }
        (None, None) => bail!(
            "{at}.mass: {} has no mass properties; give `mass`",
            path.display()
        ),
    };
    Ok((c, item))
}
