//! The kite being designed: primitives in the kite-file layout
//! (`data/kites/README.md` of the kite crate), their mass, and the statics
//! and stability from `omniad_core::kite` (paper §7).
//!
//! Aerodynamics: each plate is the bundled plate model at the plate's
//! diagonal; a box (open along y) is its four walls as plates. This keeps
//! the view on `omniad-core` alone; [`Analyser`] is the seam where the
//! kite crate's blended primitive library plugs in.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use omniad_core::kite::{stability, statics, Conditions, Kite, Primitive};
use omniad_core::Coefficients;
use std::fmt::Write as _;

/// Kind of primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A covered rectangle in the x-y plane.
    Plate,
    /// A cuboid open on its two y faces.
    Box,
    /// A fitted `.omni` object (kept and saved; drawn and analysed only
    /// by the kite crate's analyser).
    Object,
}

impl Kind {
    /// Name as in the kite file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Plate => "plate",
            Self::Box => "box",
            Self::Object => "object",
        }
    }
}

/// One primitive, as in a kite file's `[[primitive]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Unique name.
    pub name: String,
    /// Plate or box.
    pub kind: Kind,
    /// `[l_x, l_y, l_z]`, m.
    pub size: [f64; 3],
    /// Centre, body frame, m.
    pub position: [f64; 3],
    /// Rotations about x, then y, then z (fixed axes), degrees.
    pub rotation: [f64; 3],
    /// Kite-file lines kept as read (`file`, `mass`, `frame`).
    pub extra: String,
}

/// A kite design: the kite file's fields the view edits.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// Short name.
    pub name: String,
    /// Wind speed along world +x, m/s.
    pub wind_speed: f64,
    /// Air density, kg/m³.
    pub air_density: f64,
    /// String attachment: distance along the string from the foot of the
    /// optimal line (eq. 16), m.
    pub offset: f64,
    /// Orientation R, degrees about x, y, z.
    pub orientation: [f64; 3],
    /// Primitives.
    pub parts: Vec<Part>,
    /// Free text.
    pub description: String,
    /// Line length for flight, m.
    pub line_length: f64,
    /// Kite-file tables kept as read and written back after the
    /// primitives (`[materials]`, `[[rod]]`s).
    pub tables: String,
}

/// Rotation from x-then-y-then-z fixed-axis angles in degrees.
pub fn rotation(deg: &[f64; 3]) -> Matrix3<f64> {
    let [x, y, z] = deg.map(f64::to_radians);
    *(Rotation3::from_axis_angle(&Vector3::z_axis(), z)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), y)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), x))
    .matrix()
}

/// Covering areal density, kg/m² (plastic wrap), and rod mass per metre
/// (2 mm carbon), kg/m: the kite file's default materials.
const COVERING: f64 = 0.011;
const ROD: f64 = 1600.0 * std::f64::consts::PI * 0.001 * 0.001;

/// A flat panel: centre, rotation (panel normal = its z), edge lengths.
struct Panel {
    centre: Vector3<f64>,
    rotation: Matrix3<f64>,
    edges: (f64, f64),
}

fn panels(p: &Part) -> Vec<Panel> {
    let r = rotation(&p.rotation);
    let c = Vector3::from(p.position);
    let [lx, ly, lz] = p.size;
    match p.kind {
        Kind::Object => Vec::new(),
        Kind::Plate => vec![Panel {
            centre: c,
            rotation: r,
            edges: (lx, ly),
        }],
        Kind::Box => {
            let side = r * Matrix3::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0);
            let (ez, ex) = (r * Vector3::z() * (lz / 2.0), r * Vector3::x() * (lx / 2.0));
            vec![
                Panel {
                    centre: c + ez,
                    rotation: r,
                    edges: (lx, ly),
                },
                Panel {
                    centre: c - ez,
                    rotation: r,
                    edges: (lx, ly),
                },
                Panel {
                    centre: c + ex,
                    rotation: side,
                    edges: (lz, ly),
                },
                Panel {
                    centre: c - ex,
                    rotation: side,
                    edges: (lz, ly),
                },
            ]
        }
    }
}

/// Mass, kg, and centre of mass, body frame.
pub fn mass(design: &Design) -> (f64, Vector3<f64>) {
    let (mut m, mut moment) = (0.0, Vector3::zeros());
    for p in &design.parts {
        for panel in panels(p) {
            let (a, b) = panel.edges;
            let pm = COVERING * a * b + ROD * (a + b);
            m += pm;
            moment += panel.centre * pm;
        }
    }
    let com = if m > 0.0 {
        moment / m
    } else {
        Vector3::zeros()
    };
    (m, com)
}

/// Panel outlines for drawing: the index of their primitive and four
/// corners, body frame, relative to the centre of mass, m.
pub fn outlines(design: &Design) -> Vec<(usize, [Vector3<f64>; 4])> {
    let (_, com) = mass(design);
    let mut out = Vec::new();
    for (i, p) in design.parts.iter().enumerate() {
        for panel in panels(p) {
            let (a, b) = (panel.edges.0 / 2.0, panel.edges.1 / 2.0);
            let c = |x: f64, y: f64| panel.centre + panel.rotation * Vector3::new(x, y, 0.0) - com;
            out.push((i, [c(-a, -b), c(a, -b), c(a, b), c(-a, b)]));
        }
    }
    out
}

/// The numbers the view shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Analysis {
    /// Mass, kg.
    pub mass: f64,
    /// String tension, world frame, N.
    pub tension: Vector3<f64>,
    /// `f_string · g > 0`.
    pub pulls_down: bool,
    /// Unbalanced torque at the attachment point, body frame, N m.
    pub torque: Vector3<f64>,
    /// Attachment point, body frame (from the centre of mass), m.
    pub attachment: Vector3<f64>,
    /// γ of eq. (16), m/N.
    pub gamma: f64,
    /// Eigenvalues (ascending, N m/rad) and axes of the stability matrix.
    pub axes: [(f64, Vector3<f64>); 3],
}

/// Turns a design into the numbers; the kite crate can implement this.
pub trait Analyser {
    /// Statics and stability of `design`, or why there are none.
    fn analyse(&self, design: &Design) -> Result<Analysis, String>;
}

/// [`Analyser`] on `omniad-core` with one plate model for every panel.
pub struct PlateAnalyser {
    /// The plate's coefficients (any L; rescaled per panel).
    pub plate: Coefficients<f64>,
}

/// A design ready for `omniad_core::kite`: one sized plate model per
/// panel, each panel's rotation `Q_p` and offset `Y_p` from the centre of
/// mass, the mass and an inertia estimate (thin panels).
#[derive(Clone, Debug)]
pub struct Assembly {
    /// Coefficients per panel.
    pub models: Vec<Coefficients<f64>>,
    /// `(Q_p, Y_p)` per panel.
    pub frames: Vec<(Matrix3<f64>, Vector3<f64>)>,
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the centre of mass, body frame, kg m² (thin panels
    /// of uniform areal density).
    pub inertia: Matrix3<f64>,
}

impl Assembly {
    /// `plate` sized to every panel of `design`.
    pub fn new(design: &Design, plate: &Coefficients<f64>) -> Self {
        let (mass, com) = mass(design);
        let all: Vec<Panel> = design.parts.iter().flat_map(panels).collect();
        let mut inertia = Matrix3::identity() * (mass * 0.01 * 0.01);
        for p in &all {
            let (a, b) = p.edges;
            let m = COVERING * a * b + ROD * (a + b);
            let r = p.centre - com;
            let own =
                Matrix3::from_diagonal(&Vector3::new(b * b, a * a, a * a + b * b)) * (m / 12.0);
            inertia += p.rotation * own * p.rotation.transpose();
            inertia += (Matrix3::identity() * r.dot(&r) - r * r.transpose()) * m;
        }
        let models = all
            .iter()
            .map(|p| {
                let mut c = plate.clone();
                let _ = c.set_reference_length(p.edges.0.hypot(p.edges.1).max(1e-6));
                c
            })
            .collect();
        let frames = all.iter().map(|p| (p.rotation, p.centre - com)).collect();
        Self {
            models,
            frames,
            mass,
            inertia,
        }
    }

    /// The primitives, borrowing the models.
    pub fn primitives(&self) -> Vec<Primitive<'_, f64>> {
        self.models
            .iter()
            .zip(&self.frames)
            .map(|(c, (rotation, offset))| Primitive {
                coefficients: c,
                rotation: *rotation,
                offset: *offset,
            })
            .collect()
    }
}

impl Analyser for PlateAnalyser {
    fn analyse(&self, design: &Design) -> Result<Analysis, String> {
        let asm = Assembly::new(design, &self.plate);
        let prims = asm.primitives();
        let kite = Kite {
            primitives: &prims,
            mass: asm.mass,
        };
        let cond = Conditions {
            air_density: design.air_density,
            ..Conditions::standard(design.wind_speed)
        };
        let r = UnitQuaternion::from_matrix(&rotation(&design.orientation));
        let eq = statics::equilibrium(&kite, &cond, &r).map_err(|e| e.to_string())?;
        let gamma = statics::gamma_for_distance(&eq, design.offset).map_err(|e| e.to_string())?;
        let p = statics::attachment_point(&eq, gamma).map_err(|e| e.to_string())?;
        let st = stability::stability(&kite, &cond, &r, &p).map_err(|e| e.to_string())?;
        Ok(Analysis {
            mass: asm.mass,
            tension: eq.string_world,
            pulls_down: eq.pulls_down,
            torque: statics::unbalanced_torque(&eq, &p),
            attachment: p,
            gamma,
            axes: st.axes.map(|a| (a.eigenvalue, a.axis)),
        })
    }
}

impl Design {
    /// The bundled demo: a plate sail with a box cell behind it as a fin
    /// (stable on all three axes at 5 m/s).
    pub fn demo() -> Self {
        Self {
            name: "demo".into(),
            wind_speed: 5.0,
            air_density: 1.2,
            offset: -0.1,
            orientation: [0.0, 30.0, 0.0],
            parts: vec![
                Part {
                    name: "sail".into(),
                    kind: Kind::Plate,
                    size: [0.6, 0.6, 0.0],
                    position: [0.0, 0.0, 0.0],
                    rotation: [0.0, 0.0, 0.0],
                    extra: String::new(),
                },
                Part {
                    name: "cell".into(),
                    kind: Kind::Box,
                    size: [0.2, 0.2, 0.1],
                    position: [0.45, 0.0, 0.05],
                    rotation: [0.0, 0.0, 90.0],
                    extra: String::new(),
                },
            ],
            description: "plate sail with a box cell as a fin".into(),
            line_length: 20.0,
            tables: String::new(),
        }
    }

    /// The design as a kite file (TOML, the kite crate's format).
    pub fn to_toml(&self) -> String {
        let mut s = String::new();
        let v = |a: &[f64; 3]| format!("[{}, {}, {}]", a[0], a[1], a[2]);
        let _ = writeln!(
            s,
            "name = {:?}\ndescription = {:?}",
            self.name, self.description
        );
        let _ = writeln!(s, "orientation = {}\n", v(&self.orientation));
        let _ = writeln!(
            s,
            "[wind]\nspeed = {}\nair_density = {}\n",
            self.wind_speed, self.air_density
        );
        let _ = writeln!(
            s,
            "[string]\noffset = {}\nlength = {}\n",
            self.offset, self.line_length
        );
        for p in &self.parts {
            let _ = writeln!(
                s,
                "[[primitive]]\nname = {:?}\nkind = {:?}",
                p.name,
                p.kind.name()
            );
            let _ = writeln!(s, "size = {}\nposition = {}", v(&p.size), v(&p.position));
            let _ = writeln!(s, "rotation = {}\n{}", v(&p.rotation), p.extra);
        }
        s.push_str(&self.tables);
        s
    }
}
