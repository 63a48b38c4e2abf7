//! What moves the falling bodies: a coefficient model (the OmniAD file or
//! the drag-only comparison, stepped by the batch RK4 of `omniad-sim`) or
//! one of the paper's Fig. 12 comparison models, the core's one model
//! selector ([`omniad_core::model`]: vacuum, Kirchhoff added mass, drag and
//! traction, simplified lift and drag), which need a body shape: here the
//! equivalent box of the OmniAD model's body ([`Shape::of_body`]), so
//! that every model moves the same rigid body.

use super::world::{scaled, Params};
use crate::models::Model;
use omniad_core::model::ModelKind;
use omniad_core::reference::shape::Shape;

/// The paper's comparison models the view offers after the coefficient
/// models, in Fig. 12's order.
pub const COMPARISONS: [ModelKind; 4] = [
    ModelKind::Vacuum,
    ModelKind::Kirchhoff,
    ModelKind::DragTraction,
    ModelKind::Simplified,
];

/// The air of one of the view's models.
#[derive(Clone, Copy, Debug)]
pub enum Air<'a> {
    /// A coefficient model (eqs. 5-6), stepped in batches.
    Coefficients(&'a Model),
    /// A comparison model of Fig. 12 on the main model's body.
    Comparison(ModelKind),
}

impl Air<'_> {
    /// The name shown in the control panel.
    pub fn label(&self) -> String {
        match self {
            Self::Coefficients(m) => m.label.clone(),
            Self::Comparison(k) => format!("{} (Fig. 12)", k.name()),
        }
    }
}

/// The comparison models' shape: the equivalent box of `main`'s body
/// (mass and inertia as scaled by `params`), its extents times the size
/// factor (as `L` is). `None` when the body's moments are no box's.
pub fn comparison_shape(main: &Model, params: Params) -> Option<Shape> {
    let (_, body) = scaled(main, params);
    let mut shape = Shape::of_body(body.mass, &body.inertia.diagonal())?;
    shape.size *= params.size;
    Some(shape)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::builtin_model;
    use omniad_core::reference::shape::ShapeKind;

    /// Vacuum is free fall to rounding (RK4 is exact for a constant
    /// acceleration); every air model makes the same bodies fall less far.
    #[test]
    fn comparison_models_move_the_omniad_body() {
        use crate::sim::world::{World, DT, STEPS_PER_FRAME};
        let (main, params) = (builtin_model(), Params::default());
        let start = World::new(50, 3);
        let frames = 15;
        let t = (frames * STEPS_PER_FRAME) as f64 * DT;
        let descent = |kind| {
            let mut w = start.clone();
            let shape = comparison_shape(&main, params).expect("a shape");
            for _ in 0..frames {
                assert!(w.step_comparison((kind, &shape), &main, params));
            }
            assert_eq!(w.landed, 0, "no body reaches the ground in {t} s");
            let drops: Vec<f64> = start
                .bodies
                .iter()
                .zip(&w.bodies)
                .map(|(a, b)| a.position.z - b.position.z)
                .collect();
            assert!(drops.iter().all(|d| d.is_finite()));
            drops.iter().sum::<f64>() / drops.len() as f64
        };
        let free = 0.5 * 9.81 * t * t;
        let vacuum = descent(ModelKind::Vacuum);
        assert!((vacuum - free).abs() < 1e-9, "{vacuum} vs {free}");
        for kind in [
            ModelKind::Kirchhoff,
            ModelKind::DragTraction,
            ModelKind::Simplified,
        ] {
            let d = descent(kind);
            assert!(
                d > 0.0 && d < 0.99 * vacuum,
                "{}: {d} vs {vacuum}",
                kind.name()
            );
        }
    }

    #[test]
    fn the_built_in_card_is_a_seven_centimetre_plate() {
        let main = builtin_model();
        let shape = comparison_shape(&main, Params::default()).expect("a shape");
        assert_eq!(shape.kind, ShapeKind::Plate);
        assert!((shape.size.x - 0.07).abs() < 1e-3 && (shape.size.y - 0.07).abs() < 1e-3);
        let bigger = Params {
            size: 2.0,
            ..Params::default()
        };
        let twice = comparison_shape(&main, bigger).expect("a shape");
        assert!((twice.size - shape.size * 2.0).norm() < 1e-12);
    }
}
