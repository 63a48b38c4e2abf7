//! The application: four views, global keys, and the frame around them
//! (tabs, status line, help, "terminal too small").

use crate::event::Event;
use crate::kite::KiteView;
use crate::models::{self, Model};
use crate::sim::SimView;
use crate::sphere::SphereView;
use crate::telemetry::TelemetryView;
use crate::theme::Theme;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

/// Smallest usable terminal; below it a notice is shown instead.
pub const MIN_SIZE: (u16, u16) = (40, 12);

/// The views, in tab order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewId {
    /// Coefficient sphere.
    Sphere,
    /// Kite design.
    Kite,
    /// Falling bodies.
    Sim,
    /// Telemetry.
    Telemetry,
}

impl ViewId {
    /// All views in tab order.
    pub const ALL: [Self; 4] = [Self::Sphere, Self::Kite, Self::Sim, Self::Telemetry];

    /// Tab title.
    pub fn title(self) -> &'static str {
        match self {
            Self::Sphere => "Sphere",
            Self::Kite => "Kite",
            Self::Sim => "Simulation",
            Self::Telemetry => "Telemetry",
        }
    }

    fn index(self) -> usize {
        Self::ALL.iter().position(|v| *v == self).unwrap_or(0)
    }
}

/// Frame timing shown in the status line (set by the run loop only, so
/// renders in tests are deterministic).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Frames per second (smoothed); 0 when unknown.
    pub fps: f64,
    /// Time to build and flush the last frame, ms.
    pub draw_ms: f64,
}

/// The whole UI state.
pub struct App {
    /// Current view.
    pub view: ViewId,
    /// Help overlay shown.
    pub help: bool,
    /// Set when the user asked to quit.
    pub quit: bool,
    /// Look.
    pub theme: Theme,
    /// Frame timing.
    pub stats: FrameStats,
    /// View 1.
    pub sphere: SphereView,
    /// View 2.
    pub kite: KiteView,
    /// View 3.
    pub sim: SimView,
    /// View 4.
    pub telemetry: TelemetryView,
}

impl App {
    /// The app on `models` (first = main model; others compared). With no
    /// models the bundled plate is used; the isotropic-drag model is
    /// always added as a comparison, and the sphere view also gets the
    /// steady coefficients of the paper's per-element comparison models
    /// on the main model's body ([`models::comparison_spheres`]).
    pub fn new(models: Vec<Model>, theme: Theme) -> Self {
        Self::with_default(models, models::default_model(), theme)
    }

    /// As [`App::new`] with `default` used when `models` is empty.
    pub fn with_default(mut models: Vec<Model>, default: Model, theme: Theme) -> Self {
        if models.is_empty() {
            models.push(default.clone());
        }
        let main = models.first().cloned().unwrap_or_else(|| default.clone());
        let drag = models::isotropic_drag(&main.coefficients, 0.3);
        models.push(drag.clone());
        models.extend(models::comparison_spheres(&main.coefficients));
        Self {
            view: ViewId::Sphere,
            help: false,
            quit: false,
            theme,
            stats: FrameStats::default(),
            sphere: SphereView::new(models),
            kite: crate::kite::files::demo_view(),
            sim: SimView::new(vec![main, drag]),
            telemetry: TelemetryView::bundled(),
        }
    }

    /// The app on the built-in plate (not the data file) with the plain
    /// theme: deterministic, for tests and snapshots.
    pub fn demo() -> Self {
        Self::with_default(Vec::new(), models::builtin_model(), Theme::plain())
    }

    /// Whether the current view animates (then the loop ticks; else it
    /// sleeps until input arrives).
    pub fn animating(&self) -> bool {
        match self.view {
            ViewId::Sim => self.sim.running,
            ViewId::Telemetry => self.telemetry.playing,
            ViewId::Kite => self.kite.optimising(),
            _ => false,
        }
    }

    /// Applies one event; returns whether a redraw is needed.
    pub fn handle(&mut self, event: &Event) -> bool {
        match event {
            Event::Key(k) => self.on_key(*k),
            Event::Mouse(m) => self.view == ViewId::Sphere && self.sphere.on_mouse(*m),
            Event::Resize(..) => true,
            Event::Tick => self.tick(),
        }
    }

    fn tick(&mut self) -> bool {
        match self.view {
            ViewId::Sim if self.sim.running => {
                let t = std::time::Instant::now();
                self.sim.step();
                self.sim.step_ms = t.elapsed().as_secs_f64() * 1e3;
                true
            }
            ViewId::Telemetry if self.telemetry.playing => {
                self.telemetry.tick();
                true
            }
            ViewId::Kite => self.kite.poll_optimise(),
            _ => false,
        }
    }

    /// Applies a key press; returns whether a redraw is needed.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        if key.kind == KeyEventKind::Release {
            return false;
        }
        let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
        match key.code {
            KeyCode::Char('c') if ctrl => self.quit = true,
            KeyCode::Char('q') => self.quit = true,
            KeyCode::Esc if self.help => self.help = false,
            KeyCode::Esc => self.quit = true,
            KeyCode::Char('?') => self.help = !self.help,
            KeyCode::Tab => self.switch(1),
            KeyCode::BackTab => self.switch(ViewId::ALL.len() - 1),
            KeyCode::Char(c @ '1'..='4') => {
                let i = c as usize - '1' as usize;
                self.view = ViewId::ALL.get(i).copied().unwrap_or(self.view);
            }
            _ if self.help => return false,
            _ => return self.view_key(key),
        }
        true
    }

    fn switch(&mut self, by: usize) {
        let i = (self.view.index() + by) % ViewId::ALL.len();
        self.view = ViewId::ALL.get(i).copied().unwrap_or(self.view);
    }

    fn view_key(&mut self, key: KeyEvent) -> bool {
        match self.view {
            ViewId::Sim if key.code == KeyCode::Char('k') => {
                self.sim.toggle_kite(self.kite.design.as_ref().ok());
                true
            }
            ViewId::Sphere => self.sphere.on_key(key),
            ViewId::Kite => self.kite.on_key(key),
            ViewId::Sim => self.sim.on_key(key),
            ViewId::Telemetry => self.telemetry.on_key(key),
        }
    }
}
