//! What moves the falling bodies: a coefficient model (the OmniAD file or
//! the drag-only comparison, stepped by the batch RK4 of `omniad-sim`) or
//! one of the paper's Fig. 12 comparison models, the core's one model
//! selector ([`omniad_core::model`]: vacuum, Kirchhoff added mass, drag and
//! traction, simplified lift and drag), which need a body shape: here the
//! equivalent box of the OmniAD model's body ([`Shape::of_body`]), so
//! that every model moves the same rigid body.

use super::world::Params;
use crate::models::Model;
use omniad_core::model::ModelKind;
use omniad_core::reference::shape::{Shape, ShapeKind};

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
/// ([`crate::models::equivalent_box`]; the mass scale does not change it),
/// its extents times the size factor (as `L` is). `None` when the body's
/// moments are no box's.
pub fn comparison_shape(main: &Model, params: Params) -> Option<Shape> {
    let mut shape = crate::models::equivalent_box(&main.coefficients)?;
    shape.size *= params.size;
    Some(shape)
}

/// What the control panel says of the body a comparison model moves:
/// `plate 30.0×50.0×2.1 cm`, or why there is none.
pub fn shape_note(shape: Option<&Shape>) -> String {
    match shape {
        Some(s) => {
            let kind = match s.kind {
                ShapeKind::Plate => "plate",
                ShapeKind::Box => "box",
            };
            let cm = s.size * 100.0;
            format!("{kind} {:.1}×{:.1}×{:.1} cm", cm.x, cm.y, cm.z)
        }
        None => "no box has this body's inertia".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::builtin_model;

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

    /// A body whose moments are no box's: the comparison models say so and
    /// move nothing (the clock stands), the OmniAD model still runs.
    #[test]
    fn a_body_without_a_box_is_named_and_not_moved() {
        use crate::sim::SimView;
        use omniad_core::coefficients::MassProperties;
        let mut main = builtin_model();
        main.coefficients.body = Some(MassProperties {
            mass: 1.0,
            inertia: [1.0, 1.0, 5.0, 0.0, 0.0, 0.0],
        });
        assert!(comparison_shape(&main, Params::default()).is_none());
        let mut view = SimView::new(vec![main]);
        view.step();
        let t = view.world.time;
        assert!(t > 0.0, "the OmniAD model moves the bodies");
        view.model = 1;
        assert_eq!(
            view.model_line(),
            "vacuum (Fig. 12): no box has this body's inertia"
        );
        view.step();
        assert_eq!(view.world.time, t);
    }

    #[test]
    fn the_built_in_card_is_a_seven_centimetre_plate() {
        let main = builtin_model();
        let shape = comparison_shape(&main, Params::default()).expect("a shape");
        assert_eq!(shape.kind, ShapeKind::Plate);
        assert!((shape.size.x - 0.07).abs() < 1e-3 && (shape.size.y - 0.07).abs() < 1e-3);
        assert_eq!(shape_note(Some(&shape)), "plate 7.0×7.0×0.5 cm");
        let bigger = Params {
            size: 2.0,
            ..Params::default()
        };
        let twice = comparison_shape(&main, bigger).expect("a shape");
        assert!((twice.size - shape.size * 2.0).norm() < 1e-12);
    }
}
