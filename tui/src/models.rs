//! Bundled models: the default plate, an isotropic-drag comparison model,
//! and loading `.omni` files.

use nalgebra::Vector3;
use omniad_core::coefficients::MassProperties;
use omniad_core::model::{Model as AirModel, ModelKind};
use omniad_core::projection::project_steady;
use omniad_core::reference::shape::Shape;
use omniad_core::{Coefficients, Environment};
use std::f64::consts::PI;

/// A named model shown by the views.
#[derive(Clone, Debug)]
pub struct Model {
    /// Label (file name or built-in name).
    pub label: String,
    /// The coefficients.
    pub coefficients: Coefficients<f64>,
}

/// Degree of the built-in plate projection.
const PLATE_DEGREE: u8 = 6;
/// Default body of the built-in plate: a 7 cm square card of 2 g.
pub const PLATE_BODY: MassProperties = MassProperties {
    mass: 0.002,
    inertia: [8.2e-7, 8.2e-7, 1.63e-6, 0.0, 0.0, 0.0],
};

/// The bundled default coefficient file: the paper's foam plate.
pub const BUNDLED_PLATE: &[u8] = include_bytes!("../../data/plate.omni");

/// The default model: the bundled `data/plate.omni`, or the built-in
/// projected plate should that ever fail to decode.
pub fn default_model() -> Model {
    match omniad_core::file::decode::<f64>(BUNDLED_PLATE) {
        Ok(coefficients) => Model {
            label: "plate.omni (bundled)".into(),
            coefficients,
        },
        Err(_) => builtin_model(),
    }
}

/// The built-in analytic plate projected onto SH (independent of any
/// data file: used by tests and snapshots).
pub fn builtin_model() -> Model {
    Model {
        label: "plate (built-in)".into(),
        coefficients: demo_plate(),
    }
}

/// Reads a `.omni` file.
pub fn load(path: &str) -> Result<Model, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {path}: {e}"))?;
    let coefficients =
        omniad_core::file::decode::<f64>(&bytes).map_err(|e| format!("{path}: {e}"))?;
    let label = std::path::Path::new(path)
        .file_name()
        .map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned());
    Ok(Model {
        label,
        coefficients,
    })
}

/// The drag-only comparison model: `C_F = -c E`, no torque, same L and
/// body as `like`.
pub fn isotropic_drag(like: &Coefficients<f64>, c: f64) -> Model {
    let mut m = Coefficients::zeros(0, like.pole(), like.reference_length())
        .unwrap_or_else(|_| unit_zeros(0));
    let _ = m.set_alpha(0, 0, -c * (4.0 * PI).sqrt());
    let _ = m.set_name("isotropic drag");
    m.body = like.body;
    m.set_damping(&like.damping()).ok();
    Model {
        label: "isotropic drag".into(),
        coefficients: m,
    }
}

/// The equivalent box of a model's body ([`Shape::of_body`]: the uniform
/// box of its mass and moments of inertia), [`PLATE_BODY`]'s when the file
/// records no body (as the simulation view moves it). `None` when the
/// moments are no box's.
pub fn equivalent_box(model: &Coefficients<f64>) -> Option<Shape> {
    let body = model.body.unwrap_or(PLATE_BODY);
    let inertia = omniad_core::math::symmetric_from_six(body.inertia);
    Shape::of_body(body.mass, &inertia.diagonal())
}

/// The steady coefficient functions of the paper's Fig. 12 comparison
/// models (Kirchhoff's Munk moment, drag and traction, simplified lift and
/// drag) on the equivalent box of `like`'s body ([`equivalent_box`]) in
/// standard air, projected onto SH of `like`'s degree and `L`
/// (`omniad_core::projection::project_steady`), so the sphere view can set
/// them beside the OmniAD model. Vacuum has no wrench and is not listed.
/// Empty when `like` records no body (its scale would be a guess) or its
/// moments are no box's.
pub fn comparison_spheres(like: &Coefficients<f64>) -> Vec<Model> {
    let Some(shape) = like.body.and(equivalent_box(like)) else {
        return Vec::new();
    };
    let environment = Environment::standard();
    [
        ModelKind::Kirchhoff,
        ModelKind::DragTraction,
        ModelKind::Simplified,
    ]
    .into_iter()
    .filter_map(|kind| {
        let air = AirModel::new(kind, Some(&shape), None, environment).ok()?;
        let mut m = project_steady(
            &air,
            like.degree(),
            like.pole(),
            like.reference_length(),
            &environment,
        )
        .ok()?;
        let label = format!("{} (Fig. 12, steady)", kind.name());
        let _ = m.set_name(&label);
        m.body = like.body;
        Some(Model {
            label,
            coefficients: m,
        })
    })
    .collect()
}

fn unit_zeros(degree: u8) -> Coefficients<f64> {
    // Degree <= 6 with a unit pole and a positive L is always valid.
    Coefficients::zeros(degree, Vector3::z(), 0.1).expect("valid constant model")
}

/// The analytic flat plate (normal +z, reference length = diagonal) the
/// built-in model is projected from: normal force `-0.6 (E·n) n`, skin
/// friction `-0.03 E`, centre of pressure moving towards the leading edge.
pub fn plate_analytic(e: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let n = Vector3::z();
    let cn = e.dot(&n);
    let force = n * (-0.6 * cn) - e * 0.03;
    let lead = e - n * cn;
    let torque = (lead * 0.15).cross(&force);
    (force, torque)
}

/// The built-in plate: [`plate_analytic`] projected onto spherical
/// harmonics of degree 6 (the core's projection, eqs. 11, 13).
pub fn demo_plate() -> Coefficients<f64> {
    let mut m = unit_zeros(PLATE_DEGREE);
    // Finite analytic values at degree 6 always project.
    let _ = omniad_core::projection::project_into(&mut m, plate_analytic);
    let _ = m.set_name("plate");
    let _ = m.set_damping(&(nalgebra::Matrix3::identity() * 0.02));
    m.body = Some(PLATE_BODY);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plate_projection_is_close_to_the_analytic_plate() {
        let m = demo_plate();
        let e = Vector3::new(0.3, 0.2, 0.9).normalize();
        let got = m.at_direction(&e).map(|c| c.force).unwrap_or_default();
        let (want, _) = plate_analytic(&e);
        assert!((got - want).norm() < 0.05, "{got:?} vs {want:?}");
    }

    #[test]
    fn bundled_plate_decodes() {
        let m = omniad_core::file::decode::<f64>(BUNDLED_PLATE).expect("data/plate.omni decodes");
        assert!(m.at_direction(&Vector3::z()).is_some());
        assert_eq!(default_model().label, "plate.omni (bundled)");
    }

    /// The projected comparison models of the bundled plate: face-on,
    /// drag and traction shares the panel model's broadside coefficient,
    /// so it agrees with the bundled file; the simplified model's force is
    /// its own curve's drag (Wang et al. 2004) over the plate's area, face-on
    /// and edge-on; obliquely, the per-element models have no torque (no
    /// centre of pressure), the simplified model's lift is on the panel
    /// plate's side, and Kirchhoff has the Munk moment and no force (a
    /// wrong shape, scale, sign or direction would not pass).
    #[test]
    fn comparison_spheres_of_the_bundled_plate() {
        use omniad_core::reference::simplified::drag_coefficient;
        let plate = default_model().coefficients;
        let spheres = comparison_spheres(&plate);
        let labels: Vec<&str> = spheres.iter().map(|m| m.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "kirchhoff (Fig. 12, steady)",
                "drag-traction (Fig. 12, steady)",
                "simplified (Fig. 12, steady)"
            ]
        );
        let at = |m: &Coefficients<f64>, e: &Vector3<f64>| m.at_direction(e).expect("a direction");
        let [kirchhoff, traction, simplified] =
            [&spheres[0], &spheres[1], &spheres[2]].map(|m| &m.coefficients);
        let (face_on, edge_on) = (Vector3::z(), Vector3::x());
        let near = |got: f64, want: f64| (got / want - 1.0).abs() < 0.03;
        let (got, want) = (at(traction, &face_on).force.z, at(&plate, &face_on).force.z);
        assert!(near(got, want), "{got} vs {want}");
        let area_over_l2 = 0.3 * 0.5 / plate.reference_length().powi(2);
        for (e, sin_a) in [(face_on, 1.0), (edge_on, 0.0)] {
            let got = at(simplified, &e).force.dot(&e);
            let want = -drag_coefficient(sin_a) * area_over_l2;
            assert!(near(got, want), "{e:?}: {got} vs {want}");
        }
        let oblique = Vector3::new(1.0, 0.0, 1.0).normalize();
        let across = |f: Vector3<f64>| f - oblique * f.dot(&oblique);
        for m in [traction, simplified] {
            assert!(at(m, &oblique).torque.norm() < 1e-9);
        }
        let lift = across(at(simplified, &oblique).force);
        assert!(
            lift.dot(&across(at(&plate, &oblique).force)) > 0.0,
            "{lift:?}"
        );
        let munk = at(kirchhoff, &oblique);
        assert!(
            munk.force.norm() < 1e-9 && munk.torque.y.abs() > 1e-3,
            "{munk:?}"
        );
    }

    #[test]
    fn a_file_without_a_body_gets_no_comparison_spheres() {
        let mut plate = default_model().coefficients;
        plate.body = None;
        assert!(comparison_spheres(&plate).is_empty());
    }

    #[test]
    fn isotropic_drag_opposes_motion() {
        let m = isotropic_drag(&demo_plate(), 0.5).coefficients;
        let e = Vector3::new(1.0, 0.0, 0.0);
        let f = m.at_direction(&e).map(|c| c.force).unwrap_or_default();
        assert!((f - Vector3::new(-0.5, 0.0, 0.0)).norm() < 1e-9);
    }
}
