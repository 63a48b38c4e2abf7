//! Kite files: bad input names the field; overlap along the wind is
//! rejected; blending; export.

mod common;

use omniad_kite::KiteSpec;

const GOOD: &str = r#"
name = "t"
[[primitive]]
name = "a"
kind = "box"
size = [0.3, 0.3, 0.3]
"#;

fn err(text: &str) -> String {
    format!("{:#}", KiteSpec::parse(text).unwrap_err())
}

#[test]
fn bad_files_name_the_field() {
    if let Err(e) = KiteSpec::parse(GOOD) {
        panic!("{e:#}");
    }
    let cases = [
        (
            GOOD.replace("[0.3, 0.3, 0.3]", "[0.3, -0.3, 0.3]"),
            "primitive[0].size",
        ),
        (
            GOOD.replace("[0.3, 0.3, 0.3]", "[0.2, 0.3, 0.3]\n"),
            "primitive[0].size",
        ),
        (GOOD.replace("kind = \"box\"", "kind = \"balloon\""), "kind"),
        (
            GOOD.replace("name = \"t\"", "name = \"t\"\n[wind]\nspeed = -5"),
            "wind.speed",
        ),
        (
            GOOD.replace(
                "name = \"t\"",
                "name = \"t\"\n[string]\ngamma = 0.1\noffset = 0.1",
            ),
            "string",
        ),
        (
            GOOD.replace(
                "name = \"t\"",
                "name = \"t\"\n[materials]\nrod_diameter = 0",
            ),
            "materials.rod_diameter",
        ),
        (GOOD.replace("size =", "colour = 3\nsize ="), "colour"),
        (
            format!(
                "{GOOD}\n[[primitive]]\nname = \"a\"\nkind = \"plate\"\nsize = [0.3, 0.3, 0.0]\n"
            ),
            "primitive[1].name",
        ),
        (
            format!(
                "{GOOD}\n[[primitive]]\nname = \"b\"\nkind = \"plate\"\nsize = [0.3, 0.3, 0.1]\n"
            ),
            "primitive[1].size",
        ),
        (
            format!(
                "{GOOD}\n[[primitive]]\nname = \"b\"\nkind = \"object\"\nsize = [0.3, 0.3, 0.1]\n"
            ),
            "primitive[1].file",
        ),
        (
            format!("{GOOD}\n[[rod]]\nfrom = [0, 0, 0]\nto = [0, 0, 0]\n"),
            "rod[0]",
        ),
        ("name = \"t\"\n".to_string(), "primitive"),
        (
            "name = \"t\"\norientation = [0, 1]\n".to_string(),
            "orientation",
        ),
    ];
    for (text, field) in cases {
        let e = err(&text);
        assert!(e.contains(field), "error {e:?} does not name {field:?}");
    }
}

#[test]
fn loading_a_missing_file_names_it() {
    let e = format!(
        "{:#}",
        KiteSpec::load(std::path::Path::new("/nonexistent/k.toml")).unwrap_err()
    );
    assert!(e.contains("/nonexistent/k.toml"), "{e}");
}

#[test]
fn overlap_along_the_wind_is_rejected() {
    let mut design = common::kite("box-classic");
    // Flown level (pitch 0) the rear cell hides behind the front one.
    design.spec.orientation = [0.0, 0.0, 0.0];
    let r = design.orientation();
    let e = format!("{:#}", design.reject_overlaps(&r).unwrap_err());
    assert!(e.contains("front") && e.contains("rear"), "{e}");
    let c = omniad_kite::check::check(&design, None).unwrap();
    assert_eq!(c.verdict, omniad_kite::check::Verdict::Unflyable);
    // At its design pitch they do not overlap.
    let ok = common::kite("box-classic");
    assert!(ok.reject_overlaps(&ok.orientation()).is_ok());
}

/// Examples whose torque has its own degree blend at it, beta above the
/// force's degree included; examples of other degrees are refused.
#[test]
fn blending_keeps_the_torque_degree_and_refuses_mixed_ones() {
    use omniad_kite::library::{Example, Library};
    let lib = common::library();
    let example = |nt: u8, scale: f64| {
        let first = lib.examples[0].clone();
        let mut c = first.coefficients.with_torque_degree(nt).unwrap();
        for k in 0..c.torque_coeff_count() {
            c.set_beta(1, k, scale * (k as f64 + 1.0)).unwrap();
        }
        Example {
            coefficients: c,
            ..first
        }
    };
    let n = lib.examples[0].coefficients.degree();
    let nt = n + 2;
    let one = Library::from_examples(vec![example(nt, 0.01)]).unwrap();
    let at = one.examples[0].normalised;
    let blended = one.blend(&[at.x, at.y, at.z], "x").unwrap();
    assert_eq!((blended.degree(), blended.torque_degree()), (n, nt));
    let last = blended.torque_coeff_count() - 1;
    assert!((blended.beta(1, last).unwrap() - 0.01 * (last as f64 + 1.0)).abs() < 1e-12);
    let err = Library::from_examples(vec![example(nt, 0.01), example(n, 0.02)]).unwrap_err();
    assert!(format!("{err:#}").contains("torque degree"), "{err:#}");
}

#[test]
fn blending_is_exact_at_examples_and_zero_at_no_area_shapes() {
    let lib = common::library();
    let first = &lib.examples[0];
    let n = first.normalised;
    let w = lib.weights(&n);
    assert_eq!(w, vec![(Some(0), 1.0)]);
    let blended = lib.blend(&[n.x, n.y, n.z], "x").unwrap();
    for k in 0..blended.coeff_count() {
        assert!(
            (blended.alpha(0, k).unwrap() - first.coefficients.alpha(0, k).unwrap()).abs() < 1e-12
        );
    }
    // Close to the no-area shape (l_y -> 0) the coefficients vanish.
    let thin = lib.blend(&[0.3, 1e-6, 0.3], "thin").unwrap();
    assert!((0..thin.coeff_count()).all(|k| thin.alpha(0, k).unwrap().abs() < 1e-6));
    // Weights are normalised for an arbitrary box.
    let w = lib.weights(&nalgebra::Vector3::new(0.7, 0.5, 0.3).normalize());
    assert!((w.iter().map(|(_, w)| w).sum::<f64>() - 1.0).abs() < 1e-12);
    assert!(w.iter().all(|(_, w)| *w > 0.0));
}

#[test]
fn export_writes_one_socket_per_joint() {
    let design = common::kite("box-classic");
    assert_eq!(design.joints.len(), 16, "two cells, eight corners each");
    for j in &design.joints {
        assert_eq!(
            j.directions.len(),
            if j.position.x.abs() < 0.3 { 4 } else { 3 },
            "{:?}",
            j.position
        );
    }
    let dir = std::env::temp_dir().join(format!("omniad-kite-export-{}", std::process::id()));
    let files = omniad_kite::export::export(&design, &dir).unwrap();
    let scad = std::fs::read_to_string(dir.join("sockets.scad")).unwrap();
    assert_eq!(scad.matches("module joint_").count(), 16);
    assert!(scad.contains("90.0"), "right-angle rods at a box corner");
    let cut = std::fs::read_to_string(dir.join("cutlist.txt")).unwrap();
    assert!(cut.contains("total rod length"));
    let svg = std::fs::read_to_string(dir.join("drawing.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.matches("<line").count() == 3 * design.rods.len());
    assert_eq!(files.len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_fitted_object_can_be_a_primitive() {
    let plate = common::repo().join("data/plate.omni");
    let text = format!(
        "name = \"with-object\"\norientation = [0.0, 40.0, 0.0]\n[[primitive]]\nname = \"cell\"\nkind = \"box\"\nsize = [0.3, 0.3, 0.3]\nrotation = [0.0, 0.0, -90.0]\n[[primitive]]\nname = \"foam\"\nkind = \"object\"\nsize = [0.5, 0.3, 0.02]\nposition = [0.0, 0.0, 0.6]\nfile = {:?}\nmass = 0.048\n",
        plate.display().to_string()
    );
    let spec = KiteSpec::parse(&text).unwrap();
    let d = omniad_kite::Design::assemble(spec, &common::repo(), &common::library()).unwrap();
    assert_eq!(d.coefficients.len(), 2);
    assert!(d.mass.mass > 0.048);
    let c = omniad_kite::check::check(&d, None).unwrap();
    assert!(c.tension > 0.0);
    // A missing object file names the field.
    let bad = text.replace("plate.omni", "no-such.omni");
    let e = format!(
        "{:#}",
        omniad_kite::Design::assemble(
            KiteSpec::parse(&bad).unwrap(),
            &common::repo(),
            &common::library()
        )
        .unwrap_err()
    );
    assert!(e.contains("primitive[1].file"), "{e}");
}
