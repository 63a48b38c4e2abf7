//! Issue 17, item 5: rods join *named* primitives. A `[[rod]]` end names
//! a primitive and a corner or edge point of it; bad names are errors
//! naming the file, rod and field; a named corner resolves to the right
//! point of a rotated box; moving a primitive moves its rods; old files
//! with coordinate ends still load and are reported as such.

mod common;

use nalgebra::Vector3;
use omniad_kite::check::check;
use omniad_kite::connect::{move_primitive, pieces, remove_primitive};
use omniad_kite::geometry::{rod_ends, rotation_from_degrees};
use omniad_kite::{Design, KiteSpec};

/// Two boxes and one rod whose ends are `FROM` and `TO`.
fn kite(from: &str, to: &str) -> String {
    format!(
        r#"name = "t"
[[primitive]]
name = "lead"
kind = "box"
size = [0.4, 0.3, 0.2]
position = [0.1, -0.2, 0.05]
rotation = [30.0, 0.0, 90.0]
[[primitive]]
name = "wing"
kind = "plate"
size = [0.3, 0.2, 0.0]
position = [0.6, 0.0, 0.0]
[[rod]]
from = {from}
to = {to}
"#
    )
}

fn err(text: &str) -> String {
    format!("{:#}", KiteSpec::parse(text).expect_err("must be refused"))
}

#[test]
fn bad_rod_ends_are_errors_naming_the_rod_and_field() {
    let corner = r#"{ primitive = "lead", corner = "+x+y+z" }"#;
    let cases = [
        (
            r#"{ primitive = "leed", corner = "+x+y+z" }"#,
            "rod[0].to.primitive",
        ),
        (
            r#"{ primitive = "lead", corner = "+x+y" }"#,
            "rod[0].to.corner",
        ),
        (
            r#"{ primitive = "lead", corner = "+x+q+z" }"#,
            "rod[0].to.corner",
        ),
        (
            r#"{ primitive = "lead", corner = "+x+x+z" }"#,
            "rod[0].to.corner",
        ),
        (r#"{ primitive = "lead", edge = "+x" }"#, "rod[0].to.edge"),
        (
            r#"{ primitive = "lead", edge = "+x+y+z" }"#,
            "rod[0].to.edge",
        ),
        (
            r#"{ primitive = "lead", edge = "+x+y", at = 1.5 }"#,
            "rod[0].to.at",
        ),
        (
            r#"{ primitive = "lead", edge = "+x+y", at = -0.1 }"#,
            "rod[0].to.at",
        ),
        (
            r#"{ primitive = "lead", corner = "+x+y+z", at = 0.5 }"#,
            "rod[0].to.at",
        ),
        (r#"{ primitive = "lead" }"#, "rod[0].to"),
        (r#"{ primitive = "lead", corner = "+x+y+z" }"#, "rod[0]"),
    ];
    for (to, field) in cases {
        let e = err(&kite(corner, to));
        assert!(
            e.contains(field),
            "{to}: error {e:?} does not name {field:?}"
        );
    }
    // An unknown key in the end's table is a TOML error with its line.
    let e = err(&kite(
        corner,
        r#"{ primitive = "lead", corners = "+x+y+z" }"#,
    ));
    assert!(e.contains("corners") && e.contains("line"), "{e}");
    // Through the file loader the error names the file too.
    let dir = std::env::temp_dir().join(format!("omniad-rod-ends-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        kite(corner, r#"{ primitive = "nope", corner = "+x+y+z" }"#),
    )
    .expect("write");
    let e = format!("{:#}", KiteSpec::load(&path).expect_err("refused"));
    assert!(
        e.contains("bad.toml") && e.contains("rod[0].to.primitive") && e.contains("nope"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_named_corner_of_a_rotated_box_resolves_by_hand() {
    let spec = KiteSpec::parse(&kite(
        r#"{ primitive = "lead", corner = "+x-y+z" }"#,
        r#"{ primitive = "wing", edge = "-x", at = 0.25 }"#,
    ))
    .expect("parses");
    let [a, b] = rod_ends(&spec, 0, &spec.rods[0]).expect("resolves");
    // lead: half-size (0.2, 0.15, 0.1), turned 30° about x then 90°
    // about z. Local (+0.2, -0.15, +0.1); about x by 30°:
    // (0.2, -0.15 cos30 - 0.1 sin30, -0.15 sin30 + 0.1 cos30);
    // about z by 90°: (x, y) -> (-y, x).
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let (y1, z1) = (-0.15 * c - 0.1 * s, -0.15 * s + 0.1 * c);
    let hand_a = Vector3::new(0.1 - y1, -0.2 + 0.2, 0.05 + z1);
    assert!((a - hand_a).norm() < 1e-12, "{a} vs {hand_a}");
    // wing: a plate (no z extent) at (0.6, 0, 0), unrotated, 0.3 x 0.2:
    // the -x edge runs along y from -0.1 to +0.1; a quarter along it.
    let hand_b = Vector3::new(0.6 - 0.15, -0.1 + 0.25 * 0.2, 0.0);
    assert!((b - hand_b).norm() < 1e-12, "{b} vs {hand_b}");
}

#[test]
fn moving_or_scaling_a_primitive_moves_its_named_rods() {
    let mut spec = KiteSpec::parse(&kite(
        r#"{ primitive = "lead", corner = "+x+y+z" }"#,
        r#"{ primitive = "wing", corner = "-x-y" }"#,
    ))
    .expect("parses");
    let turn = rotation_from_degrees(&[0.0, 20.0, 10.0]);
    move_primitive(&mut spec, 0, &turn, &Vector3::new(0.0, 0.1, 0.0));
    let [a, b] = rod_ends(&spec, 0, &spec.rods[0]).expect("resolves");
    // The end is the same corner of the moved box, whatever Euler angles
    // the move wrote back.
    let p = &spec.primitives[0];
    let q = rotation_from_degrees(&p.rotation);
    let corner = Vector3::from(p.position) + q * Vector3::new(0.2, 0.15, 0.1);
    assert!((a - corner).norm() < 1e-12, "{a} vs {corner}");
    assert!((b - Vector3::new(0.45, -0.1, 0.0)).norm() < 1e-12, "{b}");
    // Scaling the plate (as the TUI's scale tool does) moves its corner.
    spec.primitives[1].size[0] = 0.5;
    let [_, b2] = rod_ends(&spec, 0, &spec.rods[0]).expect("resolves");
    assert!((b2 - Vector3::new(0.35, -0.1, 0.0)).norm() < 1e-12, "{b2}");
    // Removing a primitive freezes the ends naming it where they were.
    remove_primitive(&mut spec, 1);
    let [_, b3] = rod_ends(&spec, 0, &spec.rods[0]).expect("still resolves");
    assert!((b3 - b2).norm() < 1e-12);
}

#[test]
fn a_named_end_joins_its_primitive_and_coordinate_ends_are_reported() {
    // The rod joins lead to wing by name: one piece, though the two
    // primitives do not touch.
    let named = KiteSpec::parse(&kite(
        r#"{ primitive = "lead", corner = "+x+y+z" }"#,
        r#"{ primitive = "wing", corner = "-x-y" }"#,
    ))
    .expect("parses");
    assert_eq!(pieces(&named), 1);
    // Without the rod they are two pieces.
    let mut apart = named.clone();
    apart.rods.clear();
    assert_eq!(pieces(&apart), 2);
    // An old file: the bundled box-classic with its rods by coordinates
    // loads, checks to the same verdict, and says the rods are joined by
    // coordinates.
    let design = common::kite("box-classic");
    let mut old = design.spec.clone();
    for (i, r) in design.spec.rods.iter().enumerate() {
        let [a, b] = rod_ends(&design.spec, i, r).expect("resolves");
        old.rods[i].from = omniad_kite::rod_end::RodEnd::Point(a.into());
        old.rods[i].to = omniad_kite::rod_end::RodEnd::Point(b.into());
    }
    let text = old.to_toml().expect("toml");
    let old = KiteSpec::parse(&text).expect("old form parses");
    let old = Design::assemble(old, &common::repo().join("data/kites"), &common::library())
        .expect("assembles");
    let (c_new, c_old) = (
        check(&design, None).expect("check"),
        check(&old, None).expect("check"),
    );
    assert_eq!(c_new.verdict, c_old.verdict);
    assert!(c_new.joined_by_coordinates.is_empty());
    assert_eq!(c_old.joined_by_coordinates.len(), design.spec.rods.len());
    assert!(c_old
        .reasons
        .iter()
        .any(|r| r.contains("joined by coordinates")));
}

#[test]
fn named_ends_survive_a_save_and_load() {
    let spec = common::kite("fig15-c").spec;
    let text = spec.to_toml().expect("toml");
    assert!(text.contains("corner"), "{text}");
    assert_eq!(KiteSpec::parse(&text).expect("reads back"), spec);
}
