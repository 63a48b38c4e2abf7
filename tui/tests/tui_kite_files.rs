//! The kite view on the kite crate: the bundled kite file loads, is
//! checked by the function `omniad kite check` runs (same numbers for
//! every bundled kite), edits re-check, saving writes a file the kite
//! crate reads back to the same spec, and a file that does not load is an
//! error on screen that `w` never writes over (issue 18).

use omniad_kite::{Design, KiteSpec};
use omniad_tui::app::{App, ViewId};
use omniad_tui::event::Event;
use omniad_tui::kite::files::{demo_spec, kite_view, library, BUNDLED_KITE};
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use std::path::{Path, PathBuf};

fn char_key(c: char) -> KeyEvent {
    KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("omniad-tui-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn screen(app: &App) -> String {
    let mut t = Terminal::new(TestBackend::new(120, 40)).expect("terminal");
    t.draw(|f| f.render_widget(app, f.area())).expect("draw");
    t.backend().to_string()
}

#[test]
fn bundled_kite_loads_and_is_analysed_by_the_kite_crate() {
    let v = kite_view(None);
    assert!(v.message.is_empty(), "{}", v.message);
    assert_eq!(v.spec.name, "box-classic");
    assert_eq!(v.spec.primitives.len(), 2);
    let a = v.analysis.as_ref().expect("analysed");
    assert!(a.mass > 0.0 && a.tension > 0.0);
}

#[test]
fn saved_kite_file_reads_back_with_rods_and_materials() {
    let dir = temp_dir("kitefile");
    let path = dir.join("k.toml");
    std::fs::write(&path, BUNDLED_KITE).expect("write");
    let p = path.to_string_lossy().into_owned();
    let mut v = kite_view(Some(&p));
    let before = v.analysis.clone().expect("analysed");
    v.on_key(char_key('b'));
    v.on_key(char_key('}'));
    let after = v.analysis.clone().expect("still analysed");
    assert!(after.mass > before.mass, "a box was added");
    v.on_key(char_key('w'));
    assert!(v.message.starts_with("saved"), "{}", v.message);
    let text = std::fs::read_to_string(&path).expect("saved file");
    let spec = KiteSpec::parse(&text).expect("the kite crate reads the saved file");
    assert_eq!(spec.primitives.len(), 3);
    assert_eq!(spec.rods.len(), 4, "rods kept:\n{text}");
    assert_eq!(spec.wind.speed, 5.5);
    assert_eq!(spec, v.spec, "the saved file loads back to the same spec");
    let again = kite_view(Some(&p));
    assert_eq!(again.spec, v.spec);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn library_loads() {
    library().expect("primitive library");
}

#[test]
fn the_demo_kite_is_valid() {
    demo_spec().validate().expect("demo kite");
}

/// The TUI's numbers are `omniad kite check`'s for every bundled kite:
/// the view's report equals the one `kite check` computes from the file,
/// and the screen shows its tension, attachment point, γ and eigenvalues.
#[test]
fn the_tui_shows_kite_checks_numbers_for_every_bundled_kite() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/kites");
    let lib = library().expect("primitive library");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("data/kites") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        n += 1;
        let cli = omniad_kite::check::check(&Design::load(&path, &lib).expect("loads"), None)
            .expect("kite check");
        let mut app = App::demo();
        app.kite = kite_view(Some(&path.to_string_lossy()));
        app.view = ViewId::Kite;
        let tui = app.kite.analysis.as_ref().expect("the TUI checks it");
        let json = |r| serde_json::to_string(r).expect("json");
        assert_eq!(json(tui), json(&cli), "{}", path.display());
        let text = screen(&app);
        let [px, py, pz] = cli.attachment;
        for shown in [
            format!("|T| {:.3} N", cli.tension),
            format!("attach P ({px:+.3} {py:+.3} {pz:+.3}) m"),
            format!("γ {:.4} m/N", cli.gamma),
            format!("λ1 {:+.4}", cli.axes[0].eigenvalue),
            format!("λ3 {:+.4}", cli.axes[2].eigenvalue),
        ] {
            assert!(text.contains(&shown), "{}: {shown}\n{text}", path.display());
        }
        let stable = cli.axes.iter().all(|a| a.stable);
        let title = if stable { ": stable" } else { ": unstable" };
        assert!(text.contains(title), "{}\n{text}", path.display());
    }
    assert!(n >= 10, "{n} kites");
}

/// Issue 18: `--kite k.toml` with a key the kite crate does not know used
/// to open a demo kite that `w` then wrote over the user's file.
#[test]
fn a_kite_file_that_does_not_load_is_an_error_and_never_saved_over() {
    let dir = temp_dir("badkite");
    let path = dir.join("k.toml");
    let original = format!("{BUNDLED_KITE}\nunknown_key = 1\n");
    std::fs::write(&path, &original).expect("write");
    let mut app = App::demo();
    app.kite = kite_view(Some(&path.to_string_lossy()));
    assert!(app.kite.load_error.is_some());
    app.handle(&Event::Key(char_key('2')));
    let text = screen(&app);
    assert!(text.contains("cannot open kite file"), "{text}");
    assert!(text.contains("unknown_key"), "{text}");
    for c in ['b', '}', 'w'] {
        app.handle(&Event::Key(char_key(c)));
    }
    assert!(
        app.kite.message.starts_with("not saved"),
        "{}",
        app.kite.message
    );
    assert_eq!(std::fs::read_to_string(&path).expect("file"), original);
    app.handle(&Event::Key(char_key('3')));
    app.handle(&Event::Key(char_key('k')));
    assert!(app.sim.kite.is_none(), "nothing to fly");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A kite file that does not exist yet opens the bundled kite, and `w`
/// creates it.
#[test]
fn a_new_kite_file_is_created_by_saving() {
    let dir = temp_dir("newkite");
    let path = dir.join("new.toml");
    let mut app = App::demo();
    app.kite = kite_view(Some(&path.to_string_lossy()));
    app.handle(&Event::Key(char_key('2')));
    app.handle(&Event::Key(char_key('w')));
    assert!(
        app.kite.message.starts_with("saved"),
        "{}",
        app.kite.message
    );
    assert_eq!(
        KiteSpec::load(&path).expect("saved kite loads"),
        app.kite.spec
    );
    let _ = std::fs::remove_dir_all(&dir);
}
