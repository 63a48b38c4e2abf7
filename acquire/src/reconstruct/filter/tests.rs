//! Unit tests of the filter.

use super::*;
use nalgebra::{Matrix3, UnitQuaternion, Vector2};
use omniad_core::{Environment, RigidBody};

fn object() -> Object {
    let markers = [(0.15, 0.18), (0.15, -0.18), (-0.15, -0.18), (-0.15, 0.18)]
        .iter()
        .enumerate()
        .map(|(i, (x, y))| (format!("m{i}"), Vector3::new(*x, *y, 0.1)))
        .collect();
    Object {
        name: "box face".into(),
        mass: 0.04,
        inertia: Matrix3::from_diagonal(&Vector3::new(7e-4, 4e-4, 6e-4)),
        reference_length: 0.54,
        pole: Vector3::z(),
        markers,
    }
}

#[test]
fn mirror_pose_fits_the_markers_and_keeps_the_centroid_motion() {
    let camera = crate::synth::write::standard_camera(0.7);
    let object = object();
    let model = crate::fit::model::zero_model(&object, 2).expect("model");
    let filter = Filter {
        process: Process {
            body: RigidBody::new(object.mass, object.inertia).expect("body"),
            environment: Environment::standard(),
            model: &model,
            accel_noise: 1.0,
            angular_accel_noise: 1.0,
            force_walk: 0.1,
            torque_walk: 0.01,
            bias_time: f64::INFINITY,
            torque_turn: f64::INFINITY,
        },
        object: &object,
        camera: Some(&camera),
        config: FilterConfig::default(),
    };
    // The face (body +z) tilted 20 degrees away from facing the camera.
    let face_camera = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 1.2);
    let x = FilterState::new(State {
        position: Vector3::new(0.3, 0.1, 3.0),
        orientation: face_camera,
        velocity: Vector3::new(0.5, 0.2, -4.0),
        angular_velocity: Vector3::new(2.0, -1.0, 0.5),
    });
    let list: Vec<MarkerSighting> = (0..4)
        .map(|marker| MarkerSighting {
            marker,
            pixel: Vector2::zeros(),
        })
        .collect();
    let m = filter.mirror(&list, &x).expect("coplanar markers");
    let angle = x
        .body
        .orientation
        .angle_to(&m.body.orientation)
        .to_degrees();
    assert!(angle > 5.0, "the mirror pose is another pose ({angle} deg)");
    for (_, body) in &object.markers {
        let a = marker_pixel(&camera, &x.body, body).expect("a").0;
        let b = marker_pixel(&camera, &m.body, body).expect("b").0;
        assert!((a - b).norm() < 1.0, "marker pixels {a} vs {b}");
    }
    // The centroid and its velocity are kept.
    let c = Vector3::new(0.0, 0.0, 0.1);
    let centroid = |s: &FilterState| s.body.position + s.body.orientation * c;
    let centroid_velocity =
        |s: &FilterState| s.body.velocity + s.body.orientation * s.body.angular_velocity.cross(&c);
    assert!((centroid(&x) - centroid(&m)).norm() < 1e-12);
    assert!((centroid_velocity(&x) - centroid_velocity(&m)).norm() < 1e-12);
    // Mirroring twice gives the pose back.
    let back = filter.mirror(&list, &m).expect("coplanar");
    assert!(back.body.orientation.angle_to(&x.body.orientation) < 1e-9);
    assert!((back.body.angular_velocity - x.body.angular_velocity).norm() < 1e-9);
}

/// `epochs` at rest at 60 Hz, with the smoother's chains cut at `cuts`.
fn chains(epochs: usize, cuts: &[usize]) -> Smoothed {
    Smoothed {
        times: (0..epochs).map(|k| k as f64 / 60.0).collect(),
        states: vec![State::at_rest(Vector3::zeros()); epochs],
        cuts: (0..epochs).map(|k| cuts.contains(&k)).collect(),
        ..Smoothed::default()
    }
}

/// The re-simulation starts on the first chain that lasts the span or
/// reaches the last epoch, not on a short one the filter left (MuJoCo's
/// box `spin-12`: epochs 0-1, then a cut); without such a chain, on the
/// longest; never on a lone epoch.
#[test]
fn a_re_simulation_starts_on_a_chain_that_lasts() {
    assert_eq!(chains(40, &[]).first_linked_over(0.5), Some(0));
    assert_eq!(chains(40, &[1]).first_linked_over(0.5), Some(1));
    assert_eq!(chains(40, &[2]).first_linked_over(0.5), Some(2));
    // 0.5 s is 30 intervals: the chain 5..36 lasts, 36..40 reaches the end.
    assert_eq!(chains(40, &[2, 5, 36]).first_linked_over(0.5), Some(5));
    // 5..15 and 15..40 are both short of 1 s; the second reaches the end.
    assert_eq!(chains(40, &[2, 5, 15]).first_linked_over(1.0), Some(15));
    // No chain reaches the end (a lone last epoch) nor lasts 1 s: the longest.
    assert_eq!(chains(40, &[10, 15, 39]).first_linked_over(1.0), Some(15));
    assert_eq!(chains(3, &[1, 2]).first_linked_over(0.5), None);
    assert_eq!(Smoothed::default().first_linked_over(0.5), None);
}
