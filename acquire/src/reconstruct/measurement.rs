//! Observation functions h(s) of the filter (§5) and their analytic
//! Jacobians in error-state coordinates: marker pixels through the camera,
//! and 3-D poses.

use crate::input::camera::Camera;
use crate::reconstruct::state::N;
use nalgebra::{Matrix3, SMatrix, UnitQuaternion, Vector2, Vector3};
use omniad_core::State;

/// A 2 x 12 Jacobian of one marker's pixel.
pub type MarkerJacobian = SMatrix<f64, 2, N>;

/// Skew matrix `[a]×` with `[a]× b = a × b`.
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Predicted pixel of the body-frame marker `marker` (m) in state `s`, and
/// `∂(u,v)/∂δ`: `x = y + R X`, `∂x/∂δy = I`, `∂x/∂δθ = -R [X]×`.
/// `None` when the marker is behind the camera.
pub fn marker_pixel(
    camera: &Camera,
    s: &State<f64>,
    marker: &Vector3<f64>,
) -> Option<(Vector2<f64>, MarkerJacobian)> {
    let r = s.orientation.to_rotation_matrix().into_inner();
    let world = s.position + r * marker;
    let (pixel, jw) = camera.project_world(&world)?;
    let mut h = MarkerJacobian::zeros(); // bias columns stay zero
    h.fixed_view_mut::<2, 3>(0, 0).copy_from(&jw);
    h.fixed_view_mut::<2, 3>(0, 3)
        .copy_from(&(jw * (-r * skew(marker))));
    Some((pixel, h))
}

/// Pose residual `(y_m - y, log(q⁻¹ q_m))` (m, rad); its Jacobian with
/// respect to δ is `[I 0 0 0; 0 I 0 0]` to first order.
pub fn pose_residual(
    s: &State<f64>,
    y: &Vector3<f64>,
    q: &UnitQuaternion<f64>,
) -> SMatrix<f64, 6, 1> {
    let dq = (s.orientation.inverse() * q).scaled_axis();
    let dy = y - s.position;
    SMatrix::<f64, 6, 1>::new(dy.x, dy.y, dy.z, dq.x, dq.y, dq.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reconstruct::state::{boxplus, Delta};

    #[test]
    fn marker_jacobian_matches_finite_differences() {
        let camera = crate::synth::write::standard_camera(0.7);
        let s = crate::reconstruct::state::FilterState::new(State {
            position: Vector3::new(0.2, -0.3, 4.0),
            orientation: UnitQuaternion::from_euler_angles(0.4, 1.1, -0.7),
            velocity: Vector3::new(1.0, 0.0, -2.0),
            angular_velocity: Vector3::new(3.0, 1.0, -2.0),
        });
        let marker = Vector3::new(0.15, -0.18, 0.1);
        let (_, h) = marker_pixel(&camera, &s.body, &marker).expect("visible");
        for j in 0..N {
            let mut d = Delta::zeros();
            d[j] = 1e-6;
            let a = marker_pixel(&camera, &boxplus(&s, &d).body, &marker)
                .expect("a")
                .0;
            d[j] = -1e-6;
            let b = marker_pixel(&camera, &boxplus(&s, &d).body, &marker)
                .expect("b")
                .0;
            let fd = (a - b) / 2e-6;
            assert!(
                (fd - h.column(j)).norm() < 1e-4 * (1.0 + fd.norm()),
                "column {j}: {fd} vs {}",
                h.column(j)
            );
        }
    }
}
