//! The recording set (`recording.toml`, format `omniad-recording/1`): object,
//! camera, world and takes, as `docs/recording-format.md` specifies.
//!
//! [`RecordingSet::load`] reads the TOML and every take's track file
//! ([`crate::input::tracks`]); every error names the file and the field or line.

use crate::error::{Error, Result};
use crate::input::camera::{Camera, RawCamera};
use crate::input::object::{object, RawObject};
use crate::input::tracks::{self, Epoch};
use crate::input::validate::{finite, positive, unit_quaternion, within};
use nalgebra::{UnitQuaternion, Vector3};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The only format this reader accepts.
pub const FORMAT: &str = "omniad-recording/1";

pub use crate::input::object::Object;

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

/// The densest air a recording (or a simulation) may give, kg/m³: water's
/// density, a thousand times sea-level air's.
pub const MAX_AIR_DENSITY: f64 = 1e3;

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
    /// The files the set was read from: `recording.toml` and every take's
    /// track file (a command must not write its output over one, see
    /// `omniad_io::refuse_input`).
    pub files: Vec<PathBuf>,
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
        take_names(&path, &raw.take)?;
        let mut takes = Vec::with_capacity(raw.take.len());
        for (i, t) in raw.take.iter().enumerate() {
            takes.push(take(dir, &path, i, t, &object, camera.as_ref())?);
        }
        if takes.is_empty() {
            return Err(Error::at_field(&path, "take", "the set lists no takes"));
        }
        let tracks = raw
            .take
            .iter()
            .flat_map(|t| t.markers.iter().chain(&t.poses));
        let files = std::iter::once(path.clone())
            .chain(tracks.map(|name| dir.join(name)))
            .collect();
        Ok(Self {
            root: dir.to_path_buf(),
            world,
            object,
            camera,
            takes,
            files,
        })
    }
}

fn toml_message(e: &toml::de::Error) -> String {
    e.to_string().trim_end().replace('\n', " ")
}

fn world(path: &Path, w: &RawWorld) -> Result<World> {
    finite(path, "world.gravity", &w.gravity)?;
    within(
        path,
        "world.air_density",
        w.air_density,
        (1e-9, MAX_AIR_DENSITY),
        ("kg/m³", "air, not rock"),
    )?;
    if let Some(mu) = w.air_viscosity {
        positive(path, "world.air_viscosity", mu)?;
    }
    Ok(World {
        gravity: Vector3::from(w.gravity),
        air_density: w.air_density,
        air_viscosity: w.air_viscosity,
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
            let epochs = tracks::read_markers(&dir.join(m), object, cam.fps)?;
            in_front(path, i, &t.name, initial, &epochs, object, cam)?;
            (epochs, false)
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

/// Take names become file names (`omniad reconstruct` writes
/// `<name>.csv`): each must be a plain file name, and no two may be equal
/// even ignoring case (case-insensitive file systems), or one take's output
/// would overwrite another's.
fn take_names(path: &Path, takes: &[RawTake]) -> Result<()> {
    for (i, t) in takes.iter().enumerate() {
        let n = t.name.as_str();
        if n.is_empty()
            || n == "."
            || n == ".."
            || n.contains(['/', '\\'])
            || n.chars().any(char::is_control)
        {
            return Err(Error::at_field(
                path,
                format!("take[{i}].name"),
                format!("`{n}` is not a plain file name (it names the take's output files)"),
            ));
        }
        if let Some(j) = takes
            .iter()
            .take(i)
            .position(|o| o.name.eq_ignore_ascii_case(n))
        {
            return Err(Error::at_field(
                path,
                format!("take[{i}].name"),
                format!(
                    "takes {j} (`{}`) and {i} (`{n}`) have the same name; one's output would \
                     overwrite the other's",
                    takes.get(j).map_or("", |o| o.name.as_str())
                ),
            ));
        }
    }
    Ok(())
}

/// Every marker seen in a take's first frame must be in front of the
/// camera at the take's initial pose: a marker behind it cannot have been
/// seen, so the pose, `camera.rotation` or `camera.translation` is wrong
/// (the reconstruction would otherwise drift to a meaningless model).
fn in_front(
    path: &Path,
    i: usize,
    name: &str,
    initial: Option<(Vector3<f64>, UnitQuaternion<f64>)>,
    epochs: &[Epoch],
    object: &Object,
    camera: &Camera,
) -> Result<()> {
    let (Some((p, q)), Some(first)) = (initial, epochs.first()) else {
        return Ok(());
    };
    let tracks::Observation::Markers(seen) = &first.observation else {
        return Ok(());
    };
    for m in seen {
        let Some((marker, body)) = object.markers.get(m.marker) else {
            continue;
        };
        let depth = camera.to_camera(&(p + q * body)).z;
        if depth.is_nan() || depth <= crate::input::camera::MIN_DEPTH {
            return Err(Error::at_field(
                path,
                format!("take[{i}].initial_position"),
                format!(
                    "take `{name}`: marker `{marker}`, seen in its first frame, is {depth:.3} m \
                     deep in the camera frame at the initial pose (behind the camera); check \
                     initial_position, initial_orientation and camera.rotation/translation"
                ),
            ));
        }
    }
    Ok(())
}
