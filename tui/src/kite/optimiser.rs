//! The kite view's `o` key: the kite crate's design optimiser
//! ([`omniad_kite::optimise::optimise`], what `omniad kite optimise`
//! runs) on a background thread, so the view keeps drawing "optimising…"
//! while it searches. The result is loaded into the editor; the design
//! before it is kept, and `u` brings it back.

use super::KiteView;
use omniad_kite::optimise::{optimise, render, OptimiseOptions, OptimiseReport};
use omniad_kite::Design;
use std::sync::mpsc::{channel, Receiver, TryRecvError};

/// The TUI's search budget: a few seconds in a release build (each
/// evaluation is one `kite check`; one stable design is flown on seeds
/// 1-3 instead of `kite optimise`'s eight).
pub const TUI_OPTIONS: OptimiseOptions = OptimiseOptions {
    max_evaluations: 40,
    flown: 1,
};

/// A search under way.
pub type Job = Receiver<Result<OptimiseReport, String>>;

impl KiteView {
    /// Starts the optimiser on the current design (`o`); refuses while
    /// one runs or when the design does not assemble.
    pub(super) fn start_optimise(&mut self) {
        if self.job.is_some() {
            return;
        }
        let (Ok(design), Ok(library)) = (&self.design, &self.library) else {
            self.message = "cannot optimise: the design does not assemble".into();
            return;
        };
        let (design, library, base) = (design.clone(), library.clone(), self.base.clone());
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let assemble = |spec| Design::assemble(spec, &base, &library);
            let report = optimise(&design, &assemble, &TUI_OPTIONS).map_err(|e| format!("{e:#}"));
            // The receiver is gone only when the view was dropped.
            let _ = tx.send(report);
        });
        self.job = Some(rx);
        self.message = "optimising…".into();
    }

    /// Whether a search is under way (the app then ticks to poll it).
    pub fn optimising(&self) -> bool {
        self.job.is_some()
    }

    /// Takes the search's result when it is ready: loads the optimised
    /// design (keeping the one before for `u`) and shows what changed.
    /// Returns whether anything changed on screen.
    pub fn poll_optimise(&mut self) -> bool {
        let Some(rx) = &self.job else {
            return false;
        };
        let result = match rx.try_recv() {
            Ok(r) => r,
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => Err("the optimiser stopped".into()),
        };
        self.job = None;
        match result {
            Ok(report) => {
                self.previous = Some(std::mem::replace(&mut self.spec, report.spec.clone()));
                self.selected = self
                    .selected
                    .min(self.spec.primitives.len().saturating_sub(1));
                self.optimised = render(&report).lines().map(str::to_string).collect();
                self.message = format!(
                    "optimised: {} changes (u restores the design before)",
                    report.changes.len()
                );
                self.reanalyse();
            }
            Err(e) => self.message = format!("optimiser: {e}"),
        }
        true
    }

    /// `u`: back to the design before the last optimisation.
    pub(super) fn restore(&mut self) {
        match self.previous.take() {
            Some(spec) => {
                self.spec = spec;
                self.selected = self
                    .selected
                    .min(self.spec.primitives.len().saturating_sub(1));
                self.optimised.clear();
                self.message = "restored the design before optimising".into();
            }
            None => self.message = "nothing to restore".into(),
        }
    }
}
