//! Opening the kite view: the user's kite file, the bundled box kite when
//! there is none yet, or the built-in demo (tests, snapshots). The
//! primitive library is the kite crate's (`$OMNIAD_PRIMITIVES` or the
//! repository's `data/primitives`).

use super::KiteView;
use omniad_kite::spec::{Kind, Materials, PrimitiveSpec, StringSpec, WindSpec};
use omniad_kite::{KiteSpec, Library};
use std::path::{Path, PathBuf};

/// The bundled kite file (the kite crate's classic box kite).
pub const BUNDLED_KITE: &str = include_str!("../../../data/kites/box-classic.toml");

/// The demo kite of [`crate::App::demo`] (tests and snapshots; users get
/// the bundled box kite): a plate sail with a box cell behind and below it
/// as a fin, built in code so it needs no file and cannot fail. It is not a
/// flying design, and the view says so: the two parts are not joined
/// (`disconnected`), and joined by a rod it is still dynamically unstable
/// (roll-yaw mode +7.7/s) and crashes in `kite fly` — a fixture that shows
/// the warnings, not an example to copy.
pub fn demo_spec() -> KiteSpec {
    let primitive = |name: &str, kind, size, position, rotation| PrimitiveSpec {
        name: name.into(),
        kind,
        size,
        position,
        rotation,
        file: None,
        mass: None,
        frame: true,
    };
    KiteSpec {
        name: "demo".into(),
        description: "plate sail with a box cell as a fin".into(),
        wind: WindSpec::default(),
        string: StringSpec {
            offset: Some(-0.1),
            ..StringSpec::default()
        },
        materials: Materials::default(),
        orientation: [0.0, 30.0, 0.0],
        primitives: vec![
            primitive("sail", Kind::Plate, [0.6, 0.6, 0.0], [0.0; 3], [0.0; 3]),
            primitive(
                "cell",
                Kind::Box,
                [0.2, 0.2, 0.1],
                [0.5, 0.0, -0.05],
                [0.0, 0.0, 90.0],
            ),
        ],
        rods: Vec::new(),
    }
}

/// The kite crate's primitive library at its default place.
pub fn library() -> Result<Library, String> {
    let dir = omniad_kite::library::default_dir();
    Library::load(&dir).map_err(|e| format!("primitive library: {e:#}"))
}

/// A view of the bundled kite file, saving to `save`.
fn bundled(save: String) -> KiteView {
    match KiteSpec::parse(BUNDLED_KITE) {
        Ok(spec) => KiteView::new(spec, library(), PathBuf::from("."), save),
        Err(e) => {
            let mut v = KiteView::new(demo_spec(), library(), PathBuf::from("."), save);
            v.message = format!("bundled kite: {e:#}");
            v
        }
    }
}

/// The demo kite view (saves to `kite.toml`).
pub fn demo_view() -> KiteView {
    KiteView::new(
        demo_spec(),
        library(),
        PathBuf::from("."),
        "kite.toml".into(),
    )
}

/// The kite view for a real run: the kite file at `path` if it exists,
/// else the bundled box kite (saved to `path`, default `kite.toml`). A
/// file that exists but does not load is shown as the error, and `w`
/// will not write over it.
pub fn kite_view(path: Option<&str>) -> KiteView {
    let save = path.unwrap_or("kite.toml").to_string();
    let Some(file) = path.map(Path::new).filter(|p| p.exists()) else {
        return bundled(save);
    };
    match KiteSpec::load(file) {
        Ok(spec) => {
            let base = file.parent().unwrap_or(Path::new(".")).to_path_buf();
            KiteView::new(spec, library(), base, save)
        }
        Err(e) => KiteView::unloadable(demo_spec(), save, format!("{e:#}")),
    }
}
