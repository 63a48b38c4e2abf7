//! The kite's line and the forces on a tethered kite: eqs. (14)-(15) air
//! wrench of every primitive plus a tension-only spring-damper string.

use crate::wind::Wind;
use nalgebra::Vector3;
use omniad_core::aero::Wrench;
use omniad_core::kite::{statics, Primitive};
use omniad_core::rigid_body::{Forces, State};

/// The forces on a tethered kite.
pub struct Tether<'a> {
    /// The primitives (offsets from the centre of mass).
    pub primitives: &'a [Primitive<'a, f64>],
    /// The line.
    pub line: &'a Line,
    /// Wind field.
    pub wind: &'a Wind,
    /// ρ, kg/m³.
    pub air_density: f64,
}

/// The elastic line: where it is tied on the kite and on the ground.
#[derive(Clone, Debug)]
pub struct Line {
    /// Attachment P, body frame, m.
    pub attachment: Vector3<f64>,
    /// Anchor, world frame, m.
    pub anchor: Vector3<f64>,
    /// Rest length ℓ, m.
    pub length: f64,
    /// k, N/m.
    pub stiffness: f64,
    /// c, N s/m.
    pub damping: f64,
}

impl Line {
    /// Elevation of the attachment point seen from the anchor, degrees:
    /// what the flight's outcome judges ([`crate::flight`]).
    pub fn elevation_deg(&self, s: &State<f64>) -> f64 {
        let at = s.position + s.orientation.transform_vector(&self.attachment) - self.anchor;
        let horizontal = (at.x * at.x + at.y * at.y).sqrt();
        at.z.atan2(horizontal).to_degrees()
    }

    /// The string's force on the kite, world frame, N.
    pub fn force(&self, s: &State<f64>) -> Vector3<f64> {
        let r = s.orientation;
        let at = s.position + r.transform_vector(&self.attachment);
        let v_at = s.velocity + r.transform_vector(&s.angular_velocity.cross(&self.attachment));
        let d = self.anchor - at;
        let dist = d.norm();
        if !(dist > self.length) {
            return Vector3::zeros();
        }
        let dir = d / dist;
        let stretch_rate = -dir.dot(&v_at);
        let tension =
            (self.stiffness * (dist - self.length) + self.damping * stretch_rate).max(0.0);
        dir * tension
    }
}

impl Forces<f64> for Tether<'_> {
    fn wrench(&self, t: f64, s: &State<f64>) -> Wrench<f64> {
        let v = s.air_velocity_body(&self.wind.at(t));
        let air = statics::air_wrench(self.primitives, &v, &s.angular_velocity, self.air_density);
        let f = s.orientation.inverse_transform_vector(&self.line.force(s));
        let p = self.line.attachment;
        Wrench {
            force: air.force + f,
            torque: air.torque + p.cross(&f),
        }
    }
}
