//! The kite view's editing keys, applied to the kite crate's
//! [`KiteSpec`]: select, add, move/rotate/scale, remove a primitive,
//! the kite's roll, pitch and yaw, wind speed and the attachment point
//! along the string; `o` / `u` run the optimiser / restore
//! ([`super::optimiser`]). Rod ends naming a primitive's corner follow
//! it when it is moved, turned or scaled; old coordinate ends sitting on
//! it are carried by the kite crate's
//! [`omniad_kite::connect::move_primitive`], so the frame stays joined.

use super::{KiteView, Tool};
use nalgebra::Vector3;
use omniad_kite::connect::{move_primitive, remove_primitive};
use omniad_kite::geometry::rotation_from_degrees;
use omniad_kite::spec::{Kind, PrimitiveSpec};

impl KiteView {
    pub(super) fn on_char(&mut self, c: char) -> bool {
        let s = &mut self.spec;
        match c {
            'k' => return self.select(-1),
            'j' => return self.select(1),
            'h' => return self.adjust(-1.0),
            'l' => return self.adjust(1.0),
            'a' => self.add(Kind::Plate),
            'b' => self.add(Kind::Box),
            'm' => self.tool = Tool::Move,
            'r' => self.tool = Tool::Rotate,
            's' => self.tool = Tool::Scale,
            'x' => self.axis = 0,
            'y' => self.axis = 1,
            'z' => self.axis = 2,
            '(' => s.orientation[0] -= 2.0,
            ')' => s.orientation[0] += 2.0,
            '[' => s.orientation[1] -= 2.0,
            ']' => s.orientation[1] += 2.0,
            '<' => s.orientation[2] -= 2.0,
            '>' => s.orientation[2] += 2.0,
            'o' => self.start_optimise(),
            'u' => self.restore(),
            '{' => s.wind.speed = (s.wind.speed - 0.5).max(0.5),
            '}' => s.wind.speed = (s.wind.speed + 0.5).min(40.0),
            ',' => self.shift_attachment(-0.02),
            '.' => self.shift_attachment(0.02),
            'w' => return self.save(),
            _ => return false,
        }
        true
    }

    pub(super) fn select(&mut self, step: isize) -> bool {
        let n = self.spec.primitives.len();
        if n > 0 {
            self.selected = self.selected.saturating_add_signed(step).min(n - 1);
        }
        true
    }

    /// The arrow keys: the tool's step along the axis on the selected
    /// primitive. Move and rotate go through the kite crate's
    /// `move_primitive` so the rods on it follow; the x-y-z angles are
    /// then written back exactly as stepped (the same attitude).
    pub(super) fn adjust(&mut self, sign: f64) -> bool {
        let (tool, axis, i) = (self.tool, self.axis, self.selected);
        let Some(p) = self.spec.primitives.get(i) else {
            return false;
        };
        let (old, mut new) = (p.rotation, p.rotation);
        let mut shift = Vector3::zeros();
        let mut size = p.size;
        let (Some(angle), Some(d), Some(length)) =
            (new.get_mut(axis), shift.get_mut(axis), size.get_mut(axis))
        else {
            return false;
        };
        match tool {
            Tool::Move => *d = 0.01 * sign,
            Tool::Rotate => *angle = (*angle + 5.0 * sign + 180.0).rem_euclid(360.0) - 180.0,
            Tool::Scale if *length == 0.0 => {}
            Tool::Scale => *length = (*length * 1.1f64.powf(sign)).clamp(0.01, 10.0),
        }
        if tool == Tool::Scale {
            if let Some(p) = self.spec.primitives.get_mut(i) {
                p.size = size;
            }
            return true;
        }
        let turn = rotation_from_degrees(&new) * rotation_from_degrees(&old).transpose();
        move_primitive(&mut self.spec, i, &turn, &shift);
        if let Some(p) = self.spec.primitives.get_mut(i) {
            p.rotation = new;
        }
        true
    }

    /// Moves the attachment point `by` m along the string. A file that
    /// gives γ switches to the equivalent offset (what `kite check`
    /// reports) so the step is the same 2 cm either way.
    fn shift_attachment(&mut self, by: f64) {
        let string = &mut self.spec.string;
        let now = match (string.offset, string.gamma, &self.analysis) {
            (Some(d), _, _) => d,
            (None, None, _) => 0.0,
            (None, Some(_), Ok(a)) => a.attachment_offset,
            (None, Some(_), Err(_)) => {
                self.message = "no equilibrium: γ cannot become an offset".into();
                return;
            }
        };
        string.gamma = None;
        string.offset = Some(now + by);
    }

    /// A copy of the selected primitive (or a 30 cm one), 10 cm higher,
    /// turned into a `kind`, with a fresh name.
    fn add(&mut self, kind: Kind) {
        let base = self.spec.primitives.get(self.selected).cloned();
        let mut p = base.unwrap_or(PrimitiveSpec {
            name: String::new(),
            kind,
            size: [0.3, 0.3, 0.0],
            position: [0.0; 3],
            rotation: [0.0; 3],
            file: None,
            mass: None,
            frame: true,
        });
        (p.file, p.mass, p.frame) = (None, None, true);
        p.kind = kind;
        p.size[2] = if kind == Kind::Plate {
            0.0
        } else {
            p.size[0].min(p.size[1]) / 2.0
        };
        p.position[2] += 0.1;
        p.name = (1..)
            .map(|i| format!("{}-{i}", kind.name()))
            .find(|n| self.spec.primitives.iter().all(|q| &q.name != n))
            .unwrap_or_default();
        let parts = &mut self.spec.primitives;
        parts.insert((self.selected + 1).min(parts.len()), p);
        self.selected = (self.selected + 1).min(parts.len() - 1);
    }

    pub(super) fn remove(&mut self) -> bool {
        let n = self.spec.primitives.len();
        if self.selected < n && n > 1 {
            // Rod ends naming it stay where they were, by coordinates.
            remove_primitive(&mut self.spec, self.selected);
            self.selected = self.selected.min(n - 2);
        } else {
            self.message = "a kite keeps at least one primitive".into();
        }
        true
    }
}
