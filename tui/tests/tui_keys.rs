//! Key-driven state changes, without a terminal.

use omniad_tui::app::{App, ViewId};
use omniad_tui::event::Event;
use omniad_tui::sphere::Mode;
use ratatui::crossterm::event::{
    KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};

fn key(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

fn keys(app: &mut App, s: &str) {
    for c in s.chars() {
        app.on_key(key(KeyCode::Char(c)));
    }
}

#[test]
fn tab_number_keys_and_quit() {
    let mut app = App::demo();
    assert_eq!(app.view, ViewId::Sphere);
    app.on_key(key(KeyCode::Tab));
    assert_eq!(app.view, ViewId::Kite);
    app.on_key(key(KeyCode::BackTab));
    app.on_key(key(KeyCode::BackTab));
    assert_eq!(app.view, ViewId::Telemetry);
    keys(&mut app, "3");
    assert_eq!(app.view, ViewId::Sim);
    assert!(!app.quit);
    keys(&mut app, "q");
    assert!(app.quit);
    let mut app = App::demo();
    app.on_key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL));
    assert!(app.quit, "Ctrl-C quits");
}

#[test]
fn help_toggles_and_esc_closes_it_before_quitting() {
    let mut app = App::demo();
    keys(&mut app, "?");
    assert!(app.help);
    let yaw = app.sphere.yaw;
    app.on_key(key(KeyCode::Left));
    assert_eq!(app.sphere.yaw, yaw, "view keys are ignored under help");
    app.on_key(key(KeyCode::Esc));
    assert!(!app.help && !app.quit);
    app.on_key(key(KeyCode::Esc));
    assert!(app.quit);
}

#[test]
fn sphere_rotates_probes_and_switches_mode() {
    let mut app = App::demo();
    let (yaw, pitch) = (app.sphere.yaw, app.sphere.pitch);
    app.on_key(key(KeyCode::Right));
    app.on_key(key(KeyCode::Up));
    assert_eq!(
        (app.sphere.yaw, app.sphere.pitch),
        (yaw + 10.0, pitch + 10.0)
    );
    for _ in 0..20 {
        app.on_key(key(KeyCode::Up));
    }
    assert_eq!(app.sphere.pitch, 90.0, "pitch is clamped");
    let lon = app.sphere.probe_lon;
    keys(&mut app, "lkL");
    assert_eq!(app.sphere.probe_lon, lon + 20.0);
    assert_eq!(app.sphere.probe_lat, 5.0);
    assert_eq!(app.sphere.mode, Mode::Force);
    keys(&mut app, "m");
    assert_eq!(app.sphere.mode, Mode::Torque);
    keys(&mut app, "m");
    assert_eq!(app.sphere.mode, Mode::Coverage);
    keys(&mut app, "f");
    assert_eq!(app.sphere.mode, Mode::Force);
    keys(&mut app, "ac");
    assert!(!app.sphere.arrows && app.sphere.compare);
    keys(&mut app, "0");
    assert!(app.sphere.arrows && !app.sphere.compare);
    assert_eq!(app.sphere.yaw, yaw);
}

#[test]
fn the_sphere_compares_with_the_paper_comparison_models() {
    let mut app = App::demo();
    let compared = |app: &App| {
        app.sphere
            .models
            .get(app.sphere.compare_with)
            .map(|m| m.label.clone())
    };
    let mut seen = Vec::new();
    for _ in 0..3 {
        seen.extend(compared(&app));
        keys(&mut app, "n");
    }
    assert_eq!(
        compared(&app).as_deref(),
        Some("simplified (Fig. 12, steady)")
    );
    keys(&mut app, "n");
    assert_eq!(
        seen,
        [
            "isotropic drag",
            "kirchhoff (Fig. 12, steady)",
            "drag-traction (Fig. 12, steady)",
        ]
    );
    assert_eq!(compared(&app).as_deref(), Some("isotropic drag"));
}

#[test]
fn probe_facing_points_at_the_viewer() {
    let mut app = App::demo();
    keys(&mut app, "p");
    let c = app.sphere.camera() * app.sphere.probe();
    assert!(c.z > 0.999, "{c:?}");
}

#[test]
fn mouse_drag_rotates_the_sphere() {
    let mut app = App::demo();
    let yaw = app.sphere.yaw;
    let ev = |kind, column| {
        Event::Mouse(MouseEvent {
            kind,
            column,
            row: 5,
            modifiers: KeyModifiers::NONE,
        })
    };
    app.handle(&ev(MouseEventKind::Down(MouseButton::Left), 10));
    assert!(app.handle(&ev(MouseEventKind::Drag(MouseButton::Left), 15)));
    assert_eq!(app.sphere.yaw, yaw + 20.0);
    app.handle(&ev(MouseEventKind::Up(MouseButton::Left), 15));
}

#[test]
fn kite_primitives_are_added_edited_and_removed() {
    let mut app = App::demo();
    keys(&mut app, "2");
    let n = app.kite.spec.primitives.len();
    keys(&mut app, "ab");
    assert_eq!(app.kite.spec.primitives.len(), n + 2);
    let names: Vec<_> = app
        .kite
        .spec
        .primitives
        .iter()
        .map(|p| p.name.clone())
        .collect();
    assert!(
        names.contains(&"plate-1".to_string()) && names.contains(&"box-1".to_string()),
        "{names:?}"
    );
    let sel = app.kite.selected;
    let x = app.kite.spec.primitives[sel].position[0];
    keys(&mut app, "mxll");
    assert!((app.kite.spec.primitives[sel].position[0] - (x + 0.02)).abs() < 1e-12);
    keys(&mut app, "rz");
    app.on_key(key(KeyCode::Left));
    assert_eq!(app.kite.spec.primitives[sel].rotation[2], -5.0);
    let sy = app.kite.spec.primitives[sel].size[1];
    keys(&mut app, "sy");
    app.on_key(key(KeyCode::Right));
    assert!((app.kite.spec.primitives[sel].size[1] - sy * 1.1).abs() < 1e-12);
    app.on_key(key(KeyCode::Delete));
    app.on_key(key(KeyCode::Delete));
    assert_eq!(app.kite.spec.primitives.len(), n);
    for _ in 0..5 {
        app.on_key(key(KeyCode::Backspace));
    }
    assert_eq!(
        app.kite.spec.primitives.len(),
        1,
        "a kite keeps one primitive"
    );
}

#[test]
fn kite_numbers_follow_the_wind_and_the_demo_is_stable() {
    let mut app = App::demo();
    keys(&mut app, "2");
    let a = app.kite.analysis.clone().expect("demo analyses");
    assert!(a.pulls_down);
    assert!(
        a.axes.iter().all(|x| x.eigenvalue < 0.0),
        "demo kite is stable: {:?}",
        a.axes
    );
    keys(&mut app, "}}}}");
    let b = app.kite.analysis.clone().expect("still analyses");
    assert!(b.tension > a.tension);
    keys(&mut app, ".");
    let offset = app.kite.spec.string.offset.expect("offset");
    assert!((offset - (-0.08)).abs() < 1e-12);
}

#[test]
fn kite_is_saved_as_a_kite_file() {
    let mut app = App::demo();
    let path = std::env::temp_dir().join(format!("omniad-tui-kite-{}.toml", std::process::id()));
    app.kite.path = path.to_string_lossy().into_owned();
    keys(&mut app, "2w");
    let text = std::fs::read_to_string(&path).expect("saved");
    let _ = std::fs::remove_file(&path);
    assert!(
        app.kite.message.starts_with("saved"),
        "{}",
        app.kite.message
    );
    assert!(
        text.contains("[[primitive]]") && text.contains("kind = \"box\""),
        "{text}"
    );
    assert!(text.contains("[wind]\nspeed = 5"), "{text}");
}

#[test]
fn simulation_runs_on_ticks_only_when_started() {
    let mut app = App::demo();
    keys(&mut app, "3");
    assert!(!app.animating());
    assert!(!app.handle(&Event::Tick), "paused: a tick changes nothing");
    keys(&mut app, " ");
    assert!(app.animating());
    assert!(app.handle(&Event::Tick));
    assert!(app.sim.world.time > 0.0);
    let rho = app.sim.params.air_density;
    keys(&mut app, "DsW");
    assert!(app.sim.params.air_density > rho);
    assert!(app.sim.params.size < 1.0 && app.sim.params.mass_scale > 1.0);
    let label = |app: &App| app.sim.current().map(|a| a.label());
    let first = label(&app);
    for want in [
        "isotropic drag",
        "vacuum (Fig. 12)",
        "kirchhoff (Fig. 12)",
        "drag-traction (Fig. 12)",
        "simplified (Fig. 12)",
    ] {
        keys(&mut app, "o");
        assert_eq!(label(&app).as_deref(), Some(want));
        let t = app.sim.world.time;
        keys(&mut app, ".");
        assert!(app.sim.world.time > t, "{want} steps");
        assert!(app.sim.world.bodies.iter().all(|s| s.is_finite()));
    }
    keys(&mut app, "o");
    assert_eq!(label(&app), first, "o cycles back to the OmniAD model");
    let n = app.sim.world.bodies.len();
    keys(&mut app, "+");
    assert_eq!(app.sim.world.bodies.len(), 2 * n);
    keys(&mut app, "0");
    assert_eq!(app.sim.world.time, 0.0);
    assert_eq!(app.sim.params.air_density, 1.2);
}

#[test]
fn bodies_fall() {
    let mut app = App::demo();
    let z0: f64 = app.sim.world.bodies.iter().map(|s| s.position.z).sum();
    for _ in 0..10 {
        app.sim.step();
    }
    let z1: f64 = app.sim.world.bodies.iter().map(|s| s.position.z).sum();
    assert!(z1 < z0);
    assert!(app.sim.world.bodies.iter().all(|s| s.is_finite()));
}

#[test]
fn telemetry_replays_and_seeks() {
    let mut app = App::demo();
    keys(&mut app, "4");
    let i = app.telemetry.index();
    keys(&mut app, " ");
    assert!(app.animating());
    for _ in 0..30 {
        app.handle(&Event::Tick);
    }
    assert_eq!(
        app.telemetry.index(),
        i + 10,
        "30 frames at 30 Hz = 1 s = 10 samples"
    );
    app.on_key(key(KeyCode::Home));
    assert_eq!(app.telemetry.index(), 0);
    app.on_key(key(KeyCode::Right));
    assert_eq!(app.telemetry.index(), 100);
    keys(&mut app, "++");
    assert_eq!(app.telemetry.speed, 4.0);
}

#[test]
fn resize_redraws() {
    let mut app = App::demo();
    assert!(app.handle(&Event::Resize(100, 30)));
}

#[test]
fn arguments_are_parsed() {
    let a =
        |v: &[&str]| omniad_tui::parse_args(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    let o = a(&["--no-mouse", "x.omni", "--kite", "k.toml"]).expect("valid");
    assert_eq!(o.files, vec!["x.omni".to_string()]);
    assert!(!o.mouse);
    assert_eq!(o.kite.as_deref(), Some("k.toml"));
    assert!(a(&["--bogus"]).is_err());
    assert!(a(&["--kite"]).is_err());
}

#[test]
fn tethered_kite_flies_in_gusts() {
    let mut app = App::demo();
    keys(&mut app, "3k");
    let k = app.sim.kite.as_ref().expect("kite scene");
    assert!(k.position().z > 0.0);
    keys(&mut app, "G");
    for _ in 0..150 {
        app.sim.step();
    }
    let k = app.sim.kite.as_ref().expect("kite scene");
    println!("after 5 s: {:?} crashes {}", k.position(), k.crashes);
    assert!(k.time > 4.9);
    let line = k.flight.line();
    assert!(
        (k.position() - line.anchor).norm() < 2.0 * line.length,
        "held by the line"
    );
    assert!((k.gust - 0.4).abs() < 1e-12);
    keys(&mut app, "k");
    assert!(app.sim.kite.is_none());
}

#[test]
fn firmware_telemetry_csv_is_replayed_with_eigenvalues() {
    use omniad_tui::telemetry::{FlightLog, TelemetryView};
    let mut csv = String::from("seq,time_ms,force_x,force_y,force_z,torque_x,torque_y,torque_z,");
    csv.push_str("tether_predicted,tether_residual,eig_0,eig_1,eig_2,rejected,instructions\n");
    for i in 0..200 {
        let t = i * 10;
        let e = -0.5 + 0.01 * f64::from(i);
        csv.push_str(&format!(
            "{i},{t},3,4,0,0,0,0,{},0.1,{e},-0.2,-0.1,0,9000\n",
            100 + i
        ));
    }
    let mut v = TelemetryView::new("fw".into(), FlightLog::parse(&csv));
    let labels: Vec<&str> = v.series.iter().map(|s| s.label).collect();
    assert_eq!(
        labels,
        [
            "|force|",
            "tether measured",
            "tether predicted",
            "tether residual",
            "λ1",
            "λ2",
            "λ3"
        ]
    );
    assert!((v.rate_hz - 100.0).abs() < 1e-9, "{}", v.rate_hz);
    let row = v.log.rows.first().cloned().unwrap_or_default();
    assert_eq!(v.series[0].value(&row), 5.0);
    assert!((v.duration() - 1.99).abs() < 1e-9);
    v.on_key(key(KeyCode::Home));
    assert_eq!(v.index(), 0);
    let mut app = App::demo();
    app.telemetry = v;
    app.view = ViewId::Telemetry;
    let mut t =
        ratatui::Terminal::new(ratatui::backend::TestBackend::new(80, 24)).expect("terminal");
    t.draw(|f| f.render_widget(&app, f.area())).expect("draw");
    let screen = t.backend().to_string();
    assert!(screen.contains("λ1 -0.5 N·m/rad ✓"), "{screen}");
}
