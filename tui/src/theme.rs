//! Colours and symbols. With `NO_COLOR` set every style is plain and the
//! views rely on symbols (shading characters, `+`/`-` marks, arrows) alone.

use ratatui::style::{Color, Modifier, Style};

/// The look of every view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Theme {
    /// Colours on (false under `NO_COLOR`).
    pub color: bool,
}

impl Theme {
    /// Colour unless the `NO_COLOR` environment variable is set and
    /// non-empty (<https://no-color.org>).
    pub fn from_env() -> Self {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        Self { color: !no_color }
    }

    /// Plain theme (symbols only).
    pub const fn plain() -> Self {
        Self { color: false }
    }

    fn fg(self, c: Color) -> Style {
        if self.color {
            Style::new().fg(c)
        } else {
            Style::new()
        }
    }

    /// Titles and the active tab.
    pub fn title(self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    /// Selected row / active item (reverse video works without colour).
    pub fn selected(self) -> Style {
        Style::new().add_modifier(Modifier::REVERSED)
    }
    /// Secondary text.
    pub fn dim(self) -> Style {
        if self.color {
            Style::new().fg(Color::DarkGray)
        } else {
            Style::new()
        }
    }
    /// Key names in help and hints.
    pub fn key(self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }
    /// Good / stable (blue in the paper's stability plots).
    pub fn good(self) -> Style {
        self.fg(Color::Blue).add_modifier(Modifier::BOLD)
    }
    /// Bad / unstable (red).
    pub fn bad(self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    /// Arrows drawn over a shaded sphere.
    pub fn arrow(self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    /// A value in `[0, 1]` on a blue-to-red ramp (plain when colourless).
    pub fn ramp(self, v: f64) -> Style {
        if !self.color {
            return Style::new();
        }
        let v = v.clamp(0.0, 1.0);
        let r = (60.0 + 195.0 * v) as u8;
        let b = (255.0 - 195.0 * v) as u8;
        let g = (80.0 + 100.0 * (1.0 - (2.0 * v - 1.0).abs())) as u8;
        Style::new().fg(Color::Rgb(r, g, b))
    }
    /// Series colour `i` for plots.
    pub fn series(self, i: usize) -> Style {
        const C: [Color; 4] = [Color::Cyan, Color::Yellow, Color::Magenta, Color::Green];
        self.fg(C.get(i % C.len()).copied().unwrap_or(Color::White))
    }
}
