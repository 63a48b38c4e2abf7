//! View 2: kite design (KiteShop, paper §7). The view edits the kite
//! crate's own kite file model ([`KiteSpec`]) with keys; after every edit
//! the kite is assembled and checked by `omniad_kite::check::check`, the
//! function `omniad kite check` runs, so the numbers shown are its numbers.
//! Only view state (selection, tool, axis, message) lives here.

pub mod bar;
pub mod drawing;
pub mod dynamics;
pub mod edit;
pub mod files;
pub mod optimiser;
pub mod view;

use omniad_kite::check::CheckReport;
use omniad_kite::{Design, KiteSpec, Library};
use ratatui::crossterm::event::{KeyCode, KeyEvent};
use std::path::PathBuf;

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
    /// The kite file being edited (the kite crate's model).
    pub spec: KiteSpec,
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
    /// Why the kite file at `path` did not load. Then the view shows this
    /// instead of a kite, ignores edits, and never saves over the file.
    pub load_error: Option<String>,
    /// The assembled kite (coefficients, mass, panels), or why not.
    pub design: Result<Design, String>,
    /// `kite check`'s report on [`Self::design`], or why there is none.
    pub analysis: Result<CheckReport, String>,
    /// The optimiser's report on the design it loaded, as lines (empty
    /// until `o` has run).
    pub optimised: Vec<String>,
    /// The design before the last optimisation (`u` restores it).
    pub previous: Option<KiteSpec>,
    job: Option<optimiser::Job>,
    library: Result<Library, String>,
    base: PathBuf,
}

impl KiteView {
    /// A view of `spec` (object files relative to `base`), assembled with
    /// `library`, saving to `path`.
    pub fn new(
        spec: KiteSpec,
        library: Result<Library, String>,
        base: PathBuf,
        path: String,
    ) -> Self {
        let mut v = Self {
            spec,
            selected: 0,
            tool: Tool::Move,
            axis: 0,
            path,
            message: String::new(),
            load_error: None,
            design: Err(String::new()),
            analysis: Err(String::new()),
            optimised: Vec::new(),
            previous: None,
            job: None,
            library,
            base,
        };
        v.reanalyse();
        v
    }

    /// The view of a kite file at `path` that did not load (`error`): it
    /// shows the error and is not a save target.
    pub fn unloadable(placeholder: KiteSpec, path: String, error: String) -> Self {
        let mut v = Self::new(placeholder, Err(error.clone()), PathBuf::from("."), path);
        v.design = Err(error.clone());
        v.analysis = Err(error.clone());
        v.load_error = Some(error);
        v
    }

    /// Assembles and checks the spec again (as `omniad kite check` would
    /// the saved file).
    pub fn reanalyse(&mut self) {
        if self.load_error.is_some() {
            return;
        }
        self.design = match &self.library {
            Ok(lib) => self
                .spec
                .validate()
                .and_then(|()| Design::assemble(self.spec.clone(), &self.base, lib))
                .map_err(|e| format!("{e:#}")),
            Err(e) => Err(e.clone()),
        };
        self.analysis = match &self.design {
            Ok(d) => omniad_kite::check::check(d, None).map_err(|e| format!("{e:#}")),
            Err(e) => Err(e.clone()),
        };
    }

    /// Handles a key; returns whether it was used.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        if self.load_error.is_some() {
            return key.code == KeyCode::Char('w') && self.save();
        }
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

    /// Writes the spec to `path` (atomically); refuses when the file
    /// there did not load, so a user's file is never replaced by a kite
    /// they were not shown.
    fn save(&mut self) -> bool {
        self.message = match &self.load_error {
            Some(_) => format!(
                "not saved: {} did not load; fix it or open another file",
                self.path
            ),
            None => match self.spec.save(std::path::Path::new(&self.path)) {
                Ok(()) => format!("saved {}", self.path),
                Err(e) => format!("cannot save {}: {e:#}", self.path),
            },
        };
        true
    }
}
