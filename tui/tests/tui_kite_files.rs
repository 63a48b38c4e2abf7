//! The kite view on the kite crate: the bundled kite file loads, is
//! analysed with the blended primitive library, edits re-analyse, and
//! saving writes a file the kite crate reads back.

use omniad_kite::KiteSpec;
use omniad_tui::kite::files::{kite_view, KiteShopAnalyser, BUNDLED_KITE};
use omniad_tui::models;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

fn plate() -> omniad_core::Coefficients<f64> {
    models::builtin_model().coefficients
}

#[test]
fn bundled_kite_loads_and_is_analysed_by_the_kite_crate() {
    let v = kite_view(None, &plate());
    assert!(v.message.is_empty(), "{}", v.message);
    assert_eq!(v.design.name, "box-classic");
    assert_eq!(v.design.parts.len(), 2);
    let a = v.analysis.as_ref().expect("analysed");
    assert!(a.mass > 0.0 && a.tension.norm() > 0.0);
}

#[test]
fn saved_kite_file_reads_back_with_rods_and_materials() {
    let dir = std::env::temp_dir().join(format!("omniad-tui-kitefile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("k.toml");
    std::fs::write(&path, BUNDLED_KITE).expect("write");
    let p = path.to_string_lossy().into_owned();
    let mut v = kite_view(Some(&p), &plate());
    let before = v.analysis.clone().expect("analysed");
    v.on_key(KeyEvent::new(KeyCode::Char('b'), KeyModifiers::NONE));
    v.on_key(KeyEvent::new(KeyCode::Char('}'), KeyModifiers::NONE));
    let after = v.analysis.clone().expect("still analysed");
    assert!(after.mass > before.mass, "a box was added");
    v.on_key(KeyEvent::new(KeyCode::Char('w'), KeyModifiers::NONE));
    assert!(v.message.starts_with("saved"), "{}", v.message);
    let text = std::fs::read_to_string(&path).expect("saved file");
    let spec = KiteSpec::parse(&text).expect("the kite crate reads the saved file");
    assert_eq!(spec.primitives.len(), 3);
    assert_eq!(spec.rods.len(), 4, "rods kept:\n{text}");
    assert_eq!(spec.wind.speed, 5.5);
    let again = kite_view(Some(&p), &plate());
    assert_eq!(again.design.parts, v.design.parts);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn library_loads() {
    KiteShopAnalyser::load_default(".".into()).expect("primitive library");
}
