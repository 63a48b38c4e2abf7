//! View 3: live simulation of many falling bodies (paper Fig. 14) with
//! the air density, size and mass/inertia controls, and a switch between
//! OmniAD, a drag-only model and the paper's Fig. 12 comparison models.

pub mod air;
pub mod tethered;
pub mod view;
pub mod world;

use crate::models::Model;
use air::{Air, COMPARISONS};
use ratatui::crossterm::event::{KeyCode, KeyEvent};
use tethered::Tethered;
use world::{Params, World};

/// Seed of the bodies' initial states (fixed: reproducible runs).
pub const SEED: u64 = 14;
/// Default number of bodies.
pub const DEFAULT_COUNT: usize = 400;
/// Most bodies.
pub const MAX_COUNT: usize = 25_600;

/// The simulation view's state.
#[derive(Clone, Debug)]
pub struct SimView {
    /// `[0]` OmniAD, `[1..]` coefficient comparison models; after them
    /// the view offers [`COMPARISONS`].
    pub models: Vec<Model>,
    /// Model in use: an index into `models`, then into [`COMPARISONS`].
    pub model: usize,
    /// The Fig. 14 controls.
    pub params: Params,
    /// The bodies.
    pub world: World,
    /// Advancing on each tick.
    pub running: bool,
    /// Wall time of the last physics frame, ms (set by the run loop).
    pub step_ms: f64,
    /// The tethered-kite scene, when shown instead of the bodies.
    pub kite: Option<Tethered>,
}

impl SimView {
    /// A paused simulation of [`DEFAULT_COUNT`] bodies.
    pub fn new(models: Vec<Model>) -> Self {
        Self {
            models,
            model: 0,
            params: Params::default(),
            world: World::new(DEFAULT_COUNT, SEED),
            running: false,
            step_ms: 0.0,
            kite: None,
        }
    }

    /// The model in use.
    pub fn current(&self) -> Option<Air<'_>> {
        air_at(&self.models, self.model)
    }

    /// The control panel's model line: the model's label and, for a
    /// comparison model, the body shape it moves (or why it has none).
    pub fn model_line(&self) -> String {
        match (self.current(), self.main()) {
            (Some(a @ Air::Comparison(_)), Some(main)) => {
                let shape = air::comparison_shape(main, self.params);
                let sep = if shape.is_some() { " on " } else { ": " };
                format!("{}{sep}{}", a.label(), air::shape_note(shape.as_ref()))
            }
            (Some(a), _) => a.label(),
            (None, _) => "none".into(),
        }
    }

    /// The OmniAD model, whose body every model moves.
    pub fn main(&self) -> Option<&Model> {
        self.models.first()
    }

    /// Switches between the falling bodies and the kite of `design` on
    /// its line in gusts (the kite crate's flight model).
    pub fn toggle_kite(&mut self, design: Option<&omniad_kite::Design>) {
        self.kite = match (self.kite.take(), design) {
            (None, Some(d)) => Tethered::new(d),
            _ => None,
        };
    }

    /// Advances one frame (if a model is loaded).
    pub fn step(&mut self) {
        if let Some(k) = &mut self.kite {
            return k.step_frame();
        }
        let (world, params) = (&mut self.world, self.params);
        match (air_at(&self.models, self.model), self.models.first()) {
            (Some(Air::Coefficients(m)), _) => world.step_frame(m, params),
            (Some(Air::Comparison(kind)), Some(main)) => {
                // No shape: nothing moves (the panel says why).
                if let Some(shape) = air::comparison_shape(main, params) {
                    world.step_comparison((kind, &shape), main, params);
                }
            }
            _ => {}
        }
    }

    /// Handles a key; returns whether it was used.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        let KeyCode::Char(c) = key.code else {
            return false;
        };
        if let Some(k) = &mut self.kite {
            match c {
                'g' => k.gust = (k.gust - 0.1).max(0.0),
                'G' => k.gust = (k.gust + 0.1).min(1.0),
                'u' => k.wind = (k.wind - 0.5).max(0.5),
                'U' => k.wind = (k.wind + 0.5).min(30.0),
                _ => return self.on_common_key(c),
            }
            k.retune();
            return true;
        }
        self.on_common_key(c)
    }

    fn on_common_key(&mut self, c: char) -> bool {
        let p = &mut self.params;
        let up = 1.25;
        match c {
            ' ' => self.running = !self.running,
            '.' => self.step(),
            'd' => p.air_density = (p.air_density / up).max(0.01),
            'D' => p.air_density = (p.air_density * up).min(100.0),
            's' => p.size = (p.size / up).max(0.1),
            'S' => p.size = (p.size * up).min(10.0),
            'w' => p.mass_scale = (p.mass_scale / up).max(0.05),
            'W' => p.mass_scale = (p.mass_scale * up).min(50.0),
            'o' => self.model = (self.model + 1) % (self.models.len() + COMPARISONS.len()),
            '+' | '=' => self.resize(self.world.bodies.len() * 2),
            '-' => self.resize(self.world.bodies.len() / 2),
            '0' => {
                self.params = Params::default();
                self.world = World::new(self.world.bodies.len(), SEED);
            }
            _ => return false,
        }
        true
    }

    fn resize(&mut self, n: usize) {
        self.world.resize(n.clamp(1, MAX_COUNT));
    }
}

/// The air of view model `index`: `models` first, then [`COMPARISONS`].
fn air_at(models: &[Model], index: usize) -> Option<Air<'_>> {
    match models.get(index) {
        Some(m) => Some(Air::Coefficients(m)),
        None => index
            .checked_sub(models.len())
            .and_then(|i| COMPARISONS.get(i))
            .map(|k| Air::Comparison(*k)),
    }
}
