//! Issue 17, item 5 (a real frame): the check refuses a frame that is not
//! one piece and names the unjoined part; cut lengths subtract the socket's
//! core; moving a primitive carries its rods; `kite fly` statistics are
//! right when a kite crashes early.

mod common;

use nalgebra::Vector3;
use omniad_kite::check::{check, Verdict};
use omniad_kite::connect::{move_primitive, pieces};
use omniad_kite::flight::{fly, FlightOptions, Outcome};
use omniad_kite::geometry::rod_ends;
use omniad_kite::sockets::inset_mm;
use omniad_kite::{export, Design, KiteSpec};

fn assemble(spec: KiteSpec) -> Design {
    Design::assemble(spec, &common::repo().join("data/kites"), &common::library())
        .expect("assembles")
}

#[test]
fn a_cell_without_rods_to_the_rest_is_refused_by_name() {
    let mut spec = common::kite("box-three-cell").spec;
    // Keep the rods with both ends in front (x < 0): the rear cell loses its.
    let front: Vec<bool> = (spec.rods.iter().enumerate())
        .map(|(i, r)| {
            rod_ends(&spec, i, r).expect("resolves")[..]
                .iter()
                .all(|e| e.x < 0.0)
        })
        .collect();
    let mut keep = front.into_iter();
    spec.rods.retain(|_| keep.next().unwrap_or(true));
    let c = check(&assemble(spec), None).expect("check");
    assert_eq!(
        c.verdict,
        Verdict::Disconnected,
        "{}",
        omniad_kite::check::render(&c)
    );
    assert!(
        c.unjoined.iter().any(|u| u.contains("rear")),
        "{:?}",
        c.unjoined
    );
    assert!(c
        .reasons
        .iter()
        .any(|r| r.contains("not one piece") && r.contains("rear")));
    // The bundled kite, with its rods, is one piece.
    let whole = check(&common::kite("box-three-cell"), None).expect("check");
    assert!(whole.unjoined.is_empty());
}

#[test]
fn every_bundled_kite_is_one_piece() {
    for e in std::fs::read_dir(common::repo().join("data/kites")).expect("dir") {
        let p = e.expect("entry").path();
        if p.extension().is_some_and(|x| x == "toml") {
            let d = Design::load(&p, &common::library()).expect("loads");
            assert_eq!(pieces(&d.spec), 1, "{}", p.display());
        }
    }
}

#[test]
fn cut_lengths_subtract_the_socket_core_at_both_ends() {
    // box-single: a 0.4 x 0.4 x 0.3 m cell; its 0.3 m edges are cut
    // 2 x inset shorter.
    let d = common::kite("box-single");
    let inset = inset_mm(d.spec.materials.rod_diameter * 1e3);
    let expect = format!("{:>5} mm", (300.0 - 2.0 * inset).round() as i64);
    let list = export::cut_list(&d);
    let rods = list.split("Coverings").next().unwrap_or_default();
    assert!(rods.contains(&expect), "{expect} not in\n{list}");
    assert!(!rods.contains("  300 mm"), "{list}");
}

#[test]
fn moving_a_primitive_carries_its_rods() {
    let mut spec = common::kite("fig15-b").spec;
    use omniad_kite::geometry::rotation_from_degrees;
    let turn = rotation_from_degrees(&[15.0, 0.0, 10.0]);
    let q0 = rotation_from_degrees(&spec.primitives[1].rotation);
    move_primitive(&mut spec, 1, &turn, &Vector3::new(0.0, -0.08, 0.0));
    assert_eq!(pieces(&spec), 1);
    let before = common::kite("fig15-b").spec;
    let ends = |s: &KiteSpec| -> Vec<_> {
        (s.rods.iter().enumerate())
            .map(|(i, r)| rod_ends(s, i, r).expect("resolves"))
            .collect()
    };
    assert!(ends(&spec).iter().zip(ends(&before)).any(|(a, b)| *a != b));
    let q1 = rotation_from_degrees(&spec.primitives[1].rotation);
    assert!(
        (q1 - turn * q0).norm() < 1e-9,
        "{:?}",
        spec.primitives[1].rotation
    );
}

#[test]
fn statistics_of_an_early_crash_cover_the_time_flown() {
    // A two-cell kite with no equilibrium (the old fig15-a) falls within
    // seconds: the statistics are over the second half of the time it
    // flew, finite and consistent.
    let spec = KiteSpec::parse(
        r#"name = "falls"
orientation = [0.0, 40, 0.0]
[string]
offset = 0.05
[[primitive]]
name = "big"
kind = "box"
size = [0.36, 0.32, 0.26]
position = [-0.35, -0.12, 0.0]
rotation = [0.0, 0.0, -80]
[[primitive]]
name = "small"
kind = "box"
size = [0.26, 0.28, 0.2]
position = [0.42, 0.14, 0.03]
rotation = [0.0, 0.0, -100]
[[rod]]
from = [-0.2237, 0.085, 0.13]
to = [0.2596, 0.0363, 0.13]
[[rod]]
from = [-0.2237, 0.085, -0.13]
to = [0.2596, 0.0363, -0.07]
[[rod]]
from = [-0.1612, -0.2695, 0.13]
to = [0.3047, 0.2923, 0.13]
[[rod]]
from = [-0.1612, -0.2695, -0.13]
to = [0.3047, 0.2923, -0.07]
"#,
    )
    .expect("parses");
    let f = fly(&assemble(spec), &FlightOptions::default()).expect("flies or crashes");
    assert_eq!(f.outcome, Outcome::Crashes);
    let t = f.crash_time.expect("crash time");
    assert!(
        t < 30.0 && (f.seconds - t).abs() < 1e-9,
        "{t} {}",
        f.seconds
    );
    for x in [
        f.mean_elevation_deg,
        f.min_elevation_deg,
        f.max_spin,
        f.rms_spin,
        f.mean_tension,
        f.max_tension,
    ] {
        assert!(x.is_finite(), "{f:?}");
    }
    assert!(f.min_elevation_deg <= f.mean_elevation_deg && f.rms_spin <= f.max_spin + 1e-12);
    assert!(f.mean_tension > 0.0 && f.max_tension >= f.mean_tension);
}

/// Issue 17: the designs after Fig. 15 are asymmetric, use box sizes not
/// in the primitive library (so §7's blending gives their coefficients),
/// and one carries a captured object fitted by `omniad fit`.
#[test]
fn fig15_designs_are_asymmetric_blended_and_one_carries_an_object() {
    use omniad_kite::spec::Kind;
    let lib_sizes: Vec<[f64; 3]> = std::fs::read_dir(common::repo().join("data/primitives"))
        .expect("dir")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|n| {
            let dims = n.strip_suffix("mm.omni")?.split('-').nth(1)?.to_string();
            let v: Vec<f64> = dims.split('x').filter_map(|x| x.parse().ok()).collect();
            (v.len() == 3).then(|| [v[0] / 1e3, v[1] / 1e3, v[2] / 1e3])
        })
        .collect();
    assert!(lib_sizes.len() > 10);
    let mut objects = 0;
    for name in ["fig15-a", "fig15-b", "fig15-c", "fig15-d"] {
        let d = common::kite(name);
        let boxes: Vec<_> = d
            .spec
            .primitives
            .iter()
            .filter(|p| p.kind == Kind::Box)
            .collect();
        assert!(!boxes.is_empty(), "{name}");
        for b in &boxes {
            let same = |l: &[f64; 3]| (0..3).all(|k| (l[k] - b.size[k]).abs() < 1e-6);
            assert!(
                !lib_sizes.iter().any(same),
                "{name}: {:?} is a library size",
                b.size
            );
        }
        // Asymmetric: mirroring y does not map the primitives onto themselves.
        let mirrored = d.spec.primitives.iter().all(|p| {
            d.spec
                .primitives
                .iter()
                .any(|q| q.size == p.size && (q.position[1] + p.position[1]).abs() < 1e-6)
        });
        assert!(!mirrored, "{name} is symmetric");
        objects += d
            .spec
            .primitives
            .iter()
            .filter(|p| p.kind == Kind::Object)
            .count();
    }
    assert!(objects >= 1);
}
