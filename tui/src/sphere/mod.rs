//! View 1: the coefficient sphere of a `.omni` file (paper Figs. 4-5).
//!
//! State and keys live here; drawing is in [`render`].

pub mod render;

use crate::models::Model;
use nalgebra::{Rotation3, Vector3};
use omniad_core::coefficients::{COVERAGE_LAT, COVERAGE_LON};
use ratatui::crossterm::event::{KeyCode, KeyEvent, MouseButton, MouseEvent, MouseEventKind};

/// What the shading shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Drag `-C_F·E`, lift arrows.
    Force,
    /// `|C_T|`, torque arrows.
    Torque,
    /// Measurement coverage from the file's provenance.
    Coverage,
}

impl Mode {
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Force => "force",
            Self::Torque => "torque",
            Self::Coverage => "coverage",
        }
    }
    fn next(self) -> Self {
        match self {
            Self::Force => Self::Torque,
            Self::Torque => Self::Coverage,
            Self::Coverage => Self::Force,
        }
    }
}

/// The sphere view's state.
#[derive(Clone, Debug)]
pub struct SphereView {
    /// Models: `[0]` is shown; `[compare_with]` beside it in compare mode.
    pub models: Vec<Model>,
    /// Index of the second model in compare mode.
    pub compare_with: usize,
    /// Side-by-side comparison on.
    pub compare: bool,
    /// View yaw about the body z axis, degrees.
    pub yaw: f64,
    /// View pitch, degrees (positive looks down onto +z).
    pub pitch: f64,
    /// Shading mode.
    pub mode: Mode,
    /// Arrows on.
    pub arrows: bool,
    /// Probe direction: longitude about body z, degrees.
    pub probe_lon: f64,
    /// Probe direction: latitude from the x-y plane, degrees.
    pub probe_lat: f64,
    drag_from: Option<(u16, u16)>,
}

impl SphereView {
    /// A view of `models` (at least one; the second, if any, is compared).
    pub fn new(models: Vec<Model>) -> Self {
        Self {
            compare_with: usize::from(models.len() > 1),
            models,
            compare: false,
            yaw: 30.0,
            pitch: 20.0,
            mode: Mode::Force,
            arrows: true,
            probe_lon: -90.0,
            probe_lat: 0.0,
            drag_from: None,
        }
    }

    /// Camera rotation: body frame -> camera frame (x right, y up, z to
    /// the viewer). At yaw = pitch = 0 the viewer looks along body +y.
    pub fn camera(&self) -> Rotation3<f64> {
        let yaw = Rotation3::from_axis_angle(&Vector3::z_axis(), -self.yaw.to_radians());
        let to_cam = Rotation3::from_matrix_unchecked(nalgebra::Matrix3::new(
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0,
        ));
        let pitch = Rotation3::from_axis_angle(&Vector3::x_axis(), self.pitch.to_radians());
        pitch * to_cam * yaw
    }

    /// The probe direction, body frame (unit).
    pub fn probe(&self) -> Vector3<f64> {
        let (lon, lat) = (self.probe_lon.to_radians(), self.probe_lat.to_radians());
        Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    }

    /// Handles a key; returns whether it was used.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        let step = 10.0;
        match key.code {
            KeyCode::Left => self.yaw -= step,
            KeyCode::Right => self.yaw += step,
            KeyCode::Up => self.pitch = (self.pitch + step).min(90.0),
            KeyCode::Down => self.pitch = (self.pitch - step).max(-90.0),
            KeyCode::Char(c) => return self.on_char(c),
            _ => return false,
        }
        self.yaw = self.yaw.rem_euclid(360.0);
        true
    }

    fn on_char(&mut self, c: char) -> bool {
        let big = if c.is_ascii_uppercase() { 15.0 } else { 5.0 };
        match c.to_ascii_lowercase() {
            'h' => self.probe_lon -= big,
            'l' => self.probe_lon += big,
            'k' => self.probe_lat = (self.probe_lat + big).min(90.0),
            'j' => self.probe_lat = (self.probe_lat - big).max(-90.0),
            'm' => self.mode = self.mode.next(),
            'f' => self.mode = Mode::Force,
            't' => self.mode = Mode::Torque,
            'v' => self.mode = Mode::Coverage,
            'a' => self.arrows = !self.arrows,
            'c' => self.compare = !self.compare && self.models.len() > 1,
            'n' => self.next_compared(),
            'p' => self.probe_facing(),
            '0' => *self = Self::new(std::mem::take(&mut self.models)),
            _ => return false,
        }
        self.probe_lon = (self.probe_lon + 180.0).rem_euclid(360.0) - 180.0;
        true
    }

    fn next_compared(&mut self) {
        if self.models.len() > 1 {
            self.compare_with = self.compare_with % (self.models.len() - 1) + 1;
        }
    }

    /// Puts the probe on the direction facing the viewer.
    fn probe_facing(&mut self) {
        let d = self.camera().inverse() * Vector3::z();
        self.probe_lat = d.z.clamp(-1.0, 1.0).asin().to_degrees();
        self.probe_lon = d.y.atan2(d.x).to_degrees();
    }

    /// Mouse: left-drag rotates.
    pub fn on_mouse(&mut self, m: MouseEvent) -> bool {
        match m.kind {
            MouseEventKind::Down(MouseButton::Left) => self.drag_from = Some((m.column, m.row)),
            MouseEventKind::Drag(MouseButton::Left) => {
                if let Some((c, r)) = self.drag_from {
                    self.yaw =
                        (self.yaw + 4.0 * (f64::from(m.column) - f64::from(c))).rem_euclid(360.0);
                    let dp = 8.0 * (f64::from(m.row) - f64::from(r));
                    self.pitch = (self.pitch + dp).clamp(-90.0, 90.0);
                }
                self.drag_from = Some((m.column, m.row));
            }
            MouseEventKind::Up(_) => self.drag_from = None,
            _ => return false,
        }
        true
    }
}

/// Coverage cell index of a body-frame unit direction about `pole`
/// (longitude-major, latitude from +pole to -pole).
pub fn coverage_cell(d: &Vector3<f64>, pole: &Vector3<f64>) -> usize {
    let seed = if pole.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let u = (seed - pole * seed.dot(pole)).normalize();
    let v = pole.cross(&u);
    let theta = d.dot(pole).clamp(-1.0, 1.0).acos();
    let phi = d.dot(&v).atan2(d.dot(&u)).rem_euclid(std::f64::consts::TAU);
    let lat = ((theta / std::f64::consts::PI) * COVERAGE_LAT as f64) as usize;
    let lon = ((phi / std::f64::consts::TAU) * COVERAGE_LON as f64) as usize;
    lon.min(COVERAGE_LON - 1) * COVERAGE_LAT + lat.min(COVERAGE_LAT - 1)
}
