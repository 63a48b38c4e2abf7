//! Issue 17 in the kite view: the kite's full orientation and the
//! primitives' turns (carrying their rods), the overlap warning, the
//! modes panel, and the optimiser key.

use omniad_kite::connect::pieces;
use omniad_kite::geometry::rod_ends;
use omniad_kite::KiteSpec;
use omniad_tui::app::{App, ViewId};
use omniad_tui::event::Event;
use omniad_tui::kite::files::{library, BUNDLED_KITE};
use omniad_tui::kite::KiteView;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use std::path::PathBuf;

fn key(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

fn keys(app: &mut App, s: &str) {
    for c in s.chars() {
        app.on_key(key(KeyCode::Char(c)));
    }
}

fn kite_app() -> App {
    let mut app = App::demo();
    app.view = ViewId::Kite;
    app
}

/// The app showing a bundled design from `data/kites` (tests run in `tui/`).
fn bundled_app(name: &str) -> App {
    let dir = PathBuf::from("../data/kites");
    let spec = KiteSpec::load(&dir.join(format!("{name}.toml"))).expect("bundled design");
    let mut app = kite_app();
    app.kite = KiteView::new(spec, library(), dir, "k.toml".into());
    app
}

fn screen(app: &App, w: u16, h: u16) -> String {
    let mut t = Terminal::new(TestBackend::new(w, h)).expect("test terminal");
    t.draw(|f| f.render_widget(app, f.area())).expect("draw");
    format!("{}", t.backend())
}

#[test]
fn roll_and_yaw_keys_turn_the_kite_and_the_check_follows() {
    let mut app = kite_app();
    let before = app.kite.analysis.clone().expect("demo analyses");
    let o = app.kite.spec.orientation;
    keys(&mut app, "))>");
    let now = app.kite.spec.orientation;
    assert_eq!(now, [o[0] + 4.0, o[1], o[2] + 2.0]);
    let after = app.kite.analysis.clone().expect("still analyses");
    assert_ne!(
        before.orientation, after.orientation,
        "the check sees the turned kite"
    );
    keys(&mut app, "((<");
    assert_eq!(app.kite.spec.orientation, o);
}

#[test]
fn turning_a_primitive_carries_its_rods_and_keeps_the_frame_whole() {
    let spec = KiteSpec::parse(BUNDLED_KITE).expect("bundled kite");
    assert!(!spec.rods.is_empty(), "the bundled kite has rods");
    let mut v = KiteView::new(spec, library(), PathBuf::from("."), "k.toml".into());
    let ends = |s: &KiteSpec| -> Vec<_> {
        (s.rods.iter().enumerate())
            .map(|(i, r)| rod_ends(s, i, r).expect("resolves"))
            .collect()
    };
    let (rods, parts) = (ends(&v.spec), pieces(&v.spec));
    let yaw = v.spec.primitives[0].rotation[2];
    v.on_key(key(KeyCode::Char('r')));
    v.on_key(key(KeyCode::Char('z')));
    v.on_key(key(KeyCode::Right));
    assert_eq!(v.spec.primitives[0].rotation[2], yaw + 5.0);
    let moved = ends(&v.spec)
        .iter()
        .zip(&rods)
        .filter(|(a, b)| a != b)
        .count();
    assert!(moved > 0, "a rod end on the turned cell follows it");
    assert_eq!(pieces(&v.spec), parts, "the frame stays in one piece");
}

#[test]
fn overlap_along_the_wind_is_warned_and_a_flying_kite_is_not() {
    let flying = bundled_app("fig15-b");
    let clean = screen(&flying, 200, 60);
    assert!(!clean.contains("overlap along the wind"), "{clean}");
    assert!(clean.contains("modes on the line"), "{clean}");
    let mut app = kite_app();
    // A copy of the sail 10 cm above it: it sits in the sail's wake.
    keys(&mut app, "a");
    let a = app.kite.analysis.clone().expect("analyses");
    assert!(!a.overlaps.is_empty(), "the check finds the overlap");
    for (w, h) in [(200, 60), (80, 24)] {
        let s = screen(&app, w, h);
        assert!(s.contains("overlap along the wind"), "{w}x{h}:\n{s}");
    }
}

#[test]
fn the_modes_panel_lists_every_mode_of_the_check() {
    let app = bundled_app("fig15-b");
    let a = app.kite.analysis.clone().expect("fig15-b analyses");
    assert!(!a.modes.modes.is_empty(), "fig15-b has modes");
    let s = screen(&app, 200, 60);
    for m in &a.modes.modes {
        assert!(s.contains(&format!("σ {:+.2}", m.real)), "{m:?}\n{s}");
    }
}

#[test]
fn the_optimise_key_loads_a_design_no_worse_and_u_restores() {
    let mut app = bundled_app("box-classic");
    let before = app.kite.analysis.clone().expect("box-classic analyses");
    assert!(
        before.modes.max_growth_rate.is_finite(),
        "{:?}",
        before.verdict
    );
    let spec = app.kite.spec.clone();
    keys(&mut app, "o");
    assert!(app.kite.optimising(), "{}", app.kite.message);
    assert!(app.animating(), "the loop ticks while it runs");
    assert!(screen(&app, 200, 60).contains("optimising…"));
    let start = std::time::Instant::now();
    while app.kite.optimising() {
        assert!(start.elapsed().as_secs() < 900, "optimiser finishes");
        std::thread::sleep(std::time::Duration::from_millis(50));
        app.handle(&Event::Tick);
    }
    assert!(
        app.kite.message.starts_with("optimised"),
        "{}",
        app.kite.message
    );
    let after = app.kite.analysis.clone().expect("optimised analyses");
    assert!(
        -after.modes.max_growth_rate >= -before.modes.max_growth_rate - 1e-9,
        "margin {} -> {}",
        -before.modes.max_growth_rate,
        -after.modes.max_growth_rate
    );
    assert!(!app.kite.optimised.is_empty());
    keys(&mut app, "u");
    assert_eq!(app.kite.spec, spec, "u restores the design before");
}
