//! View 2: kite design (KiteShop, paper §7). Edit primitives with keys;
//! the equilibrium numbers and stability eigenvalues update live.

pub mod design;
pub mod drawing;
pub mod files;
pub mod view;

use design::{Analyser, Analysis, Design, Kind, Part};
use ratatui::crossterm::event::{KeyCode, KeyEvent};

/// What the arrow keys change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Position, 1 cm steps.
    Move,
    /// Rotation, 5° steps.
    Rotate,
    /// Size, 10 % steps.
    Scale,
}

impl Tool {
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Move => "move",
            Self::Rotate => "rotate",
            Self::Scale => "scale",
        }
    }
}

/// The kite view's state.
pub struct KiteView {
    /// The design.
    pub design: Design,
    /// Selected primitive.
    pub selected: usize,
    /// Active tool.
    pub tool: Tool,
    /// Active axis, 0..3 = x, y, z.
    pub axis: usize,
    /// Where `w` saves.
    pub path: String,
    /// Last message (saved, error).
    pub message: String,
    /// Latest analysis.
    pub analysis: Result<Analysis, String>,
    analyser: Box<dyn Analyser>,
}

impl KiteView {
    /// A view of `design`, analysed by `analyser`, saving to `path`.
    pub fn new(design: Design, analyser: Box<dyn Analyser>, path: String) -> Self {
        let analysis = analyser.analyse(&design);
        Self {
            design,
            selected: 0,
            tool: Tool::Move,
            axis: 0,
            path,
            message: String::new(),
            analysis,
            analyser,
        }
    }

    /// Recomputes the analysis.
    pub fn reanalyse(&mut self) {
        self.analysis = self.analyser.analyse(&self.design);
    }

    /// Handles a key; returns whether it was used.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        let used = match key.code {
            KeyCode::Up => self.select(-1),
            KeyCode::Down => self.select(1),
            KeyCode::Left => self.adjust(-1.0),
            KeyCode::Right => self.adjust(1.0),
            KeyCode::Delete | KeyCode::Backspace => self.remove(),
            KeyCode::Char(c) => self.on_char(c),
            _ => false,
        };
        if used {
            self.reanalyse();
        }
        used
    }

    fn on_char(&mut self, c: char) -> bool {
        let d = &mut self.design;
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
            '[' => d.orientation[1] -= 2.0,
            ']' => d.orientation[1] += 2.0,
            '{' => d.wind_speed = (d.wind_speed - 0.5).max(0.5),
            '}' => d.wind_speed = (d.wind_speed + 0.5).min(40.0),
            ',' => d.offset -= 0.02,
            '.' => d.offset += 0.02,
            'w' => self.save(),
            _ => return false,
        }
        true
    }

    fn select(&mut self, step: isize) -> bool {
        let n = self.design.parts.len();
        if n > 0 {
            self.selected = self.selected.saturating_add_signed(step).min(n - 1);
        }
        true
    }

    fn adjust(&mut self, sign: f64) -> bool {
        let (tool, axis) = (self.tool, self.axis);
        let Some(p) = self.design.parts.get_mut(self.selected) else {
            return false;
        };
        let Some(slot) = (match tool {
            Tool::Move => p.position.get_mut(axis),
            Tool::Rotate => p.rotation.get_mut(axis),
            Tool::Scale => p.size.get_mut(axis),
        }) else {
            return false;
        };
        *slot = match tool {
            Tool::Move => *slot + 0.01 * sign,
            Tool::Rotate => (*slot + 5.0 * sign + 180.0).rem_euclid(360.0) - 180.0,
            Tool::Scale if *slot == 0.0 => 0.0,
            Tool::Scale => (*slot * 1.1f64.powf(sign)).clamp(0.01, 10.0),
        };
        true
    }

    fn add(&mut self, kind: Kind) {
        let base = self.design.parts.get(self.selected).cloned();
        let mut p = base.unwrap_or(Part {
            name: String::new(),
            kind,
            size: [0.3, 0.3, 0.0],
            position: [0.0; 3],
            rotation: [0.0; 3],
            extra: String::new(),
        });
        p.extra.clear();
        p.kind = kind;
        p.size[2] = if kind == Kind::Plate {
            0.0
        } else {
            p.size[0].min(p.size[1]) / 2.0
        };
        p.position[2] += 0.1;
        p.name = (1..)
            .map(|i| format!("{}-{i}", kind.name()))
            .find(|n| self.unused(n))
            .unwrap_or_default();
        self.design
            .parts
            .insert((self.selected + 1).min(self.design.parts.len()), p);
        self.selected = (self.selected + 1).min(self.design.parts.len() - 1);
    }

    fn unused(&self, name: &str) -> bool {
        self.design.parts.iter().all(|p| p.name != name)
    }

    fn remove(&mut self) -> bool {
        if self.selected < self.design.parts.len() && self.design.parts.len() > 1 {
            self.design.parts.remove(self.selected);
            self.selected = self.selected.min(self.design.parts.len() - 1);
        } else {
            self.message = "a kite keeps at least one primitive".into();
        }
        true
    }

    fn save(&mut self) {
        self.message = match std::fs::write(&self.path, self.design.to_toml()) {
            Ok(()) => format!("saved {}", self.path),
            Err(e) => format!("cannot save {}: {e}", self.path),
        };
    }
}
