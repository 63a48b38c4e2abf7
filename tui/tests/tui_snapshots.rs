//! Every view rendered into ratatui's `TestBackend` and compared with the
//! committed insta snapshots at 80x24 (the field laptop over SSH) and
//! 200x60 (a large terminal). Rendering is deterministic: no clocks or
//! random seeds reach these frames.

use omniad_tui::app::{App, ViewId};
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;

const SIZES: [(u16, u16); 2] = [(80, 24), (200, 60)];

fn render(app: &App, w: u16, h: u16) -> TestBackend {
    let mut t = Terminal::new(TestBackend::new(w, h)).expect("test terminal");
    t.draw(|f| f.render_widget(app, f.area())).expect("draw");
    t.backend().clone()
}

fn press(app: &mut App, c: char) {
    app.on_key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE));
}

fn snap_all(name: &str, app: &App) {
    for (w, h) in SIZES {
        insta::assert_snapshot!(format!("{name}_{w}x{h}"), render(app, w, h));
    }
}

fn app_on(view: ViewId) -> App {
    let mut app = App::demo();
    app.view = view;
    app
}

#[test]
fn sphere_view() {
    snap_all("sphere", &app_on(ViewId::Sphere));
}

#[test]
fn sphere_torque_mode() {
    let mut app = app_on(ViewId::Sphere);
    press(&mut app, 't');
    snap_all("sphere_torque", &app);
}

#[test]
fn sphere_compare() {
    let mut app = app_on(ViewId::Sphere);
    press(&mut app, 'c');
    assert!(app.sphere.compare);
    snap_all("sphere_compare", &app);
}

#[test]
fn kite_view() {
    snap_all("kite", &app_on(ViewId::Kite));
}

#[test]
fn sim_view_after_one_second() {
    let mut app = app_on(ViewId::Sim);
    for _ in 0..30 {
        app.sim.step();
    }
    snap_all("sim", &app);
}

#[test]
fn sim_tethered_kite() {
    let mut app = app_on(ViewId::Sim);
    press(&mut app, 'k');
    for _ in 0..30 {
        app.sim.step();
    }
    snap_all("sim_kite", &app);
}

#[test]
fn telemetry_view() {
    snap_all("telemetry", &app_on(ViewId::Telemetry));
}

#[test]
fn help_overlay() {
    let mut app = app_on(ViewId::Kite);
    press(&mut app, '?');
    snap_all("help_kite", &app);
}
