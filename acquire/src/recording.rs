//! The recording set (`recording.toml`, format `omniad-recording/1`): object,
//! camera, world and takes, as `docs/recording-format.md` specifies.
//!
//! [`RecordingSet::load`] reads the TOML and every take's track file
//! ([`crate::tracks`]); every error names the file and the field or line.

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::tracks::{self, Epoch};
use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The only format this reader accepts.
pub const FORMAT: &str = "omniad-recording/1";

/// The world the object moves in.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    /// Gravity, world frame, m/s².
    pub gravity: Vector3<f64>,
    /// Air density ρ, kg/m³.
    pub air_density: f64,
    /// Air viscosity μ, kg/(m s), if given.
    pub air_viscosity: Option<f64>,
}

/// The recorded object.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Mass M, kg.
    pub mass: f64,
    /// Inertia about the centre of mass, body frame, kg m².
    pub inertia: Matrix3<f64>,
    /// Reference length L (bounding-box diagonal), m.
    pub reference_length: f64,
    /// Unit pole Z of the SH vector basis, body frame.
    pub pole: Vector3<f64>,
    /// Markers: name and body-frame position (m), in name order.
    pub markers: Vec<(String, Vector3<f64>)>,
}

impl Object {
    /// Index of a marker by name.
    pub fn marker_index(&self, name: &str) -> Option<usize> {
        self.markers.iter().position(|(n, _)| n == name)
    }
}

/// What a take mainly excites (§5: the sets K1 and K2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TakeKind {
    /// Dropped: linear velocity dominant (K1).
    Drop,
    /// Thrown spinning: angular velocity dominant (K2).
    Spin,
}

/// One take: its observations, one [`Epoch`] per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Take {
    /// Name.
    pub name: String,
    /// Drop or spin.
    pub kind: TakeKind,
    /// Rough guess of the first frame's position (m, world) and orientation.
    pub initial: Option<(Vector3<f64>, UnitQuaternion<f64>)>,
    /// Observations in time order.
    pub epochs: Vec<Epoch>,
    /// True for 3-D pose tracks, false for 2-D marker tracks.
    pub poses: bool,
}

/// A whole recording set.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordingSet {
    /// The set's folder.
    pub root: PathBuf,
    /// World.
    pub world: World,
    /// Object.
    pub object: Object,
    /// Camera (required when any take has marker tracks).
    pub camera: Option<Camera>,
    /// Takes in file order.
    pub takes: Vec<Take>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSet {
    format: String,
    world: RawWorld,
    object: RawObject,
    camera: Option<RawCamera>,
    #[serde(default)]
    take: Vec<RawTake>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWorld {
    gravity: [f64; 3],
    air_density: f64,
    air_viscosity: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    name: String,
    mass: f64,
    inertia: [[f64; 3]; 3],
    reference_length: f64,
    pole: [f64; 3],
    #[serde(default)]
    markers: BTreeMap<String, [f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCamera {
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
    pub distortion: [f64; 5],
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
    pub pixel_noise: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTake {
    name: String,
    kind: String,
    markers: Option<String>,
    poses: Option<String>,
    initial_position: Option<[f64; 3]>,
    initial_orientation: Option<[f64; 4]>,
}

impl RecordingSet {
    /// Reads `<dir>/recording.toml` and every take file it lists.
    pub fn load(dir: &Path) -> Result<Self> {
        let path = dir.join("recording.toml");
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let raw: RawSet =
            toml::from_str(&text).map_err(|e| Error::in_file(&path, toml_message(&e)))?;
        if raw.format != FORMAT {
            return Err(Error::at_field(
                &path,
                "format",
                format!("expected \"{FORMAT}\", found \"{}\"", raw.format),
            ));
        }
        let world = world(&path, &raw.world)?;
        let object = object(&path, raw.object)?;
        let camera = raw
            .camera
            .as_ref()
            .map(|c| Camera::from_raw(&path, c))
            .transpose()?;
        let mut takes = Vec::with_capacity(raw.take.len());
        for (i, t) in raw.take.iter().enumerate() {
            takes.push(take(dir, &path, i, t, &object, camera.as_ref())?);
        }
        if takes.is_empty() {
            return Err(Error::at_field(&path, "take", "the set lists no takes"));
        }
        Ok(Self {
            root: dir.to_path_buf(),
            world,
            object,
            camera,
            takes,
        })
    }
}

fn toml_message(e: &toml::de::Error) -> String {
    e.to_string().trim_end().replace('\n', " ")
}

/// Checks that every number of a field is finite.
pub(crate) fn finite(path: &Path, field: &str, values: &[f64]) -> Result<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::at_field(path, field, "must be finite"))
    }
}

/// Checks that a field is finite and positive.
pub(crate) fn positive(path: &Path, field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::at_field(
            path,
            field,
            format!("must be positive and finite, found {v}"),
        ))
    }
}

fn world(path: &Path, w: &RawWorld) -> Result<World> {
    finite(path, "world.gravity", &w.gravity)?;
    positive(path, "world.air_density", w.air_density)?;
    if let Some(mu) = w.air_viscosity {
        positive(path, "world.air_viscosity", mu)?;
    }
    Ok(World {
        gravity: Vector3::from(w.gravity),
        air_density: w.air_density,
        air_viscosity: w.air_viscosity,
    })
}

fn object(path: &Path, o: RawObject) -> Result<Object> {
    positive(path, "object.mass", o.mass)?;
    positive(path, "object.reference_length", o.reference_length)?;
    let flat: Vec<f64> = o.inertia.iter().flatten().copied().collect();
    finite(path, "object.inertia", &flat)?;
    let inertia = Matrix3::from_row_slice(&flat);
    if (inertia - inertia.transpose()).norm() > 1e-9 * inertia.norm()
        || inertia.cholesky().is_none()
    {
        return Err(Error::at_field(
            path,
            "object.inertia",
            "must be symmetric positive definite",
        ));
    }
    finite(path, "object.pole", &o.pole)?;
    let pole = Vector3::from(o.pole);
    if pole.norm() == 0.0 {
        return Err(Error::at_field(path, "object.pole", "must be non-zero"));
    }
    let mut markers = Vec::with_capacity(o.markers.len());
    for (name, p) in o.markers {
        finite(path, &format!("object.markers.{name}"), &p)?;
        markers.push((name, Vector3::from(p)));
    }
    Ok(Object {
        name: o.name,
        mass: o.mass,
        inertia,
        reference_length: o.reference_length,
        pole: pole.normalize(),
        markers,
    })
}

fn take(
    dir: &Path,
    path: &Path,
    i: usize,
    t: &RawTake,
    object: &Object,
    camera: Option<&Camera>,
) -> Result<Take> {
    let field = |f: &str| format!("take[{i}].{f}");
    let kind = match t.kind.as_str() {
        "drop" => TakeKind::Drop,
        "spin" => TakeKind::Spin,
        other => {
            return Err(Error::at_field(
                path,
                field("kind"),
                format!("expected \"drop\" or \"spin\", found \"{other}\""),
            ))
        }
    };
    let initial = initial_guess(path, i, t)?;
    let (epochs, poses) = match (&t.markers, &t.poses) {
        (Some(m), None) => {
            let cam = camera.ok_or_else(|| {
                Error::at_field(path, "camera", "marker tracks need a [camera] table")
            })?;
            if initial.is_none() {
                return Err(Error::at_field(
                    path,
                    field("initial_position"),
                    "marker takes need initial_position and initial_orientation",
                ));
            }
            (tracks::read_markers(&dir.join(m), object, cam.fps)?, false)
        }
        (None, Some(p)) => (tracks::read_poses(&dir.join(p))?, true),
        _ => {
            return Err(Error::at_field(
                path,
                field("markers"),
                "give exactly one of `markers` and `poses`",
            ))
        }
    };
    Ok(Take {
        name: t.name.clone(),
        kind,
        initial,
        epochs,
        poses,
    })
}

fn initial_guess(
    path: &Path,
    i: usize,
    t: &RawTake,
) -> Result<Option<(Vector3<f64>, UnitQuaternion<f64>)>> {
    match (t.initial_position, t.initial_orientation) {
        (Some(p), Some(q)) => {
            finite(path, &format!("take[{i}].initial_position"), &p)?;
            let q = unit_quaternion(&q).ok_or_else(|| {
                Error::at_field(
                    path,
                    format!("take[{i}].initial_orientation"),
                    "must be a finite non-zero quaternion [w, x, y, z]",
                )
            })?;
            Ok(Some((Vector3::from(p), q)))
        }
        (None, None) => Ok(None),
        _ => Err(Error::at_field(
            path,
            format!("take[{i}].initial_position"),
            "give both initial_position and initial_orientation",
        )),
    }
}

/// `[w, x, y, z]` normalised, or `None` when zero or non-finite.
pub fn unit_quaternion(q: &[f64; 4]) -> Option<UnitQuaternion<f64>> {
    let raw = Quaternion::new(q[0], q[1], q[2], q[3]);
    let n = raw.norm();
    (n.is_finite() && n > 0.0).then(|| UnitQuaternion::new_unchecked(raw / n))
}

/// A rotation matrix (rows) as a unit quaternion, if it is orthonormal with
/// determinant +1 to within 1e-3.
pub fn rotation_from_rows(rows: &[[f64; 3]; 3]) -> Option<UnitQuaternion<f64>> {
    let m = Matrix3::from_row_slice(&rows.iter().flatten().copied().collect::<Vec<_>>());
    let err = (m * m.transpose() - Matrix3::identity()).norm();
    if err.is_nan() || err >= 1e-3 || m.determinant() < 0.0 {
        return None;
    }
    Some(UnitQuaternion::from_rotation_matrix(
        &Rotation3::from_matrix(&m),
    ))
}
