//! The camera: OpenCV pinhole with radial (k1, k2, k3) and tangential
//! (p1, p2) distortion, exactly as `cv::projectPoints`, and the analytic
//! Jacobian of the projection (the observation function h of §5).

use crate::error::{Error, Result};
use crate::input::validate::{finite, positive, rotation_from_rows};
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Vector2, Vector3};
use serde::Deserialize;
use std::path::Path;

/// Points closer to the image plane than this (m, camera z) are not projected.
pub const MIN_DEPTH: f64 = 1e-3;

/// A calibrated camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Image width, px.
    pub width: u32,
    /// Image height, px.
    pub height: u32,
    /// Frames per second, 1/s.
    pub fps: f64,
    /// Focal lengths fx, fy, px.
    pub focal: Vector2<f64>,
    /// Principal point cx, cy, px.
    pub centre: Vector2<f64>,
    /// k1, k2, p1, p2, k3 (OpenCV order).
    pub distortion: [f64; 5],
    /// World -> camera rotation: `x_cam = rotation * x_world + translation`.
    pub rotation: Matrix3<f64>,
    /// m.
    pub translation: Vector3<f64>,
    /// Tracker 1-sigma error, px.
    pub pixel_noise: f64,
}

/// The slowest camera accepted, frames per second.
pub const MIN_FPS: f64 = 1.0;

/// The fastest camera accepted, frames per second (high-speed cameras).
pub const MAX_FPS: f64 = 1e6;

/// Pixel noise assumed when `pixel_noise` is absent, px.
pub const DEFAULT_PIXEL_NOISE: f64 = 1.0;

impl Camera {
    pub(crate) fn from_raw(path: &Path, c: &RawCamera) -> Result<Self> {
        for (name, v) in [("width", c.width), ("height", c.height)] {
            if v == 0 {
                return Err(Error::at_field(
                    path,
                    format!("camera.{name}"),
                    "must be a positive number of pixels, found 0",
                ));
            }
        }
        for (name, v) in [("fps", c.fps), ("fx", c.fx), ("fy", c.fy)] {
            positive(path, &format!("camera.{name}"), v)?;
        }
        if !(MIN_FPS..=MAX_FPS).contains(&c.fps) {
            return Err(Error::at_field(
                path,
                "camera.fps",
                format!(
                    "must be from {MIN_FPS} to {MAX_FPS} frames per second, found {}",
                    c.fps
                ),
            ));
        }
        finite(path, "camera.cx", &[c.cx, c.cy])?;
        finite(path, "camera.distortion", &c.distortion)?;
        finite(path, "camera.translation", &c.translation)?;
        let q = rotation_from_rows(&c.rotation).ok_or_else(|| {
            Error::at_field(
                path,
                "camera.rotation",
                "must be a rotation matrix (orthonormal, det +1)",
            )
        })?;
        let pixel_noise = c.pixel_noise.unwrap_or(DEFAULT_PIXEL_NOISE);
        positive(path, "camera.pixel_noise", pixel_noise)?;
        let camera = Self {
            width: c.width,
            height: c.height,
            fps: c.fps,
            focal: Vector2::new(c.fx, c.fy),
            centre: Vector2::new(c.cx, c.cy),
            distortion: c.distortion,
            rotation: q.to_rotation_matrix().into_inner(),
            translation: Vector3::from(c.translation),
            pixel_noise,
        };
        camera.check_distortion().map_err(|why| {
            Error::at_field(path, "camera.distortion", format!("impossible lens: {why}"))
        })?;
        Ok(camera)
    }

    /// Checks that the distortion is a lens's over the image: one-to-one
    /// (the Jacobian determinant of the distortion stays positive) and
    /// moving no point by more than half the image diagonal. Checked on a
    /// 17 x 17 grid of the undistorted image rectangle.
    fn check_distortion(&self) -> std::result::Result<(), String> {
        const STEPS: u32 = 16;
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let limit = 0.5 * w.hypot(h);
        for i in 0..=STEPS {
            for j in 0..=STEPS {
                let px = Vector2::new(
                    w * f64::from(i) / f64::from(STEPS),
                    h * f64::from(j) / f64::from(STEPS),
                );
                let n = (px - self.centre).component_div(&self.focal);
                let (d, jd) = self.distort(&n);
                let shift = (d - n).component_mul(&self.focal).norm();
                let det = jd.determinant();
                if det.is_nan() || det <= 0.0 {
                    return Err(format!(
                        "it folds the image over near pixel ({:.0}, {:.0})",
                        px.x, px.y
                    ));
                }
                if shift.is_nan() || shift > limit {
                    return Err(format!(
                        "it moves pixel ({:.0}, {:.0}) by {shift:.3e} px, more than half the image diagonal",
                        px.x, px.y
                    ));
                }
            }
        }
        Ok(())
    }

    /// World point (m) -> camera frame (m).
    pub fn to_camera(&self, world: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * world + self.translation
    }

    /// Pixel of a world point, or `None` behind (or on) the image plane.
    pub fn project(&self, world: &Vector3<f64>) -> Option<Vector2<f64>> {
        self.project_camera(&self.to_camera(world)).map(|(p, _)| p)
    }

    /// Pixel of a camera-frame point and the Jacobian d(u,v)/d(point), px/m.
    pub fn project_camera(&self, p: &Vector3<f64>) -> Option<(Vector2<f64>, Matrix2x3<f64>)> {
        if p.z.is_nan() || p.z <= MIN_DEPTH {
            return None;
        }
        let iz = 1.0 / p.z;
        let n = Vector2::new(p.x * iz, p.y * iz);
        let dn = Matrix2x3::new(iz, 0.0, -p.x * iz * iz, 0.0, iz, -p.y * iz * iz);
        let (d, jd) = self.distort(&n);
        let f = Matrix2::from_diagonal(&self.focal);
        let pixel = f * d + self.centre;
        Some((pixel, f * jd * dn))
    }

    /// Pixel of a world point and the Jacobian d(u,v)/d(world point), px/m.
    pub fn project_world(&self, world: &Vector3<f64>) -> Option<(Vector2<f64>, Matrix2x3<f64>)> {
        self.project_camera(&self.to_camera(world))
            .map(|(p, j)| (p, j * self.rotation))
    }

    /// OpenCV distortion of normalised coordinates and its 2x2 Jacobian.
    fn distort(&self, n: &Vector2<f64>) -> (Vector2<f64>, Matrix2<f64>) {
        let [k1, k2, p1, p2, k3] = self.distortion;
        let (x, y) = (n.x, n.y);
        let r2 = x * x + y * y;
        let radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
        // d radial / d r2
        let dradial = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);
        let xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
        let yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
        let dxd_dx = radial + x * dradial * 2.0 * x + 2.0 * p1 * y + p2 * 6.0 * x;
        let dxd_dy = x * dradial * 2.0 * y + 2.0 * p1 * x + p2 * 2.0 * y;
        let dyd_dx = y * dradial * 2.0 * x + p1 * 2.0 * x + 2.0 * p2 * y;
        let dyd_dy = radial + y * dradial * 2.0 * y + p1 * 6.0 * y + 2.0 * p2 * x;
        (
            Vector2::new(xd, yd),
            Matrix2::new(dxd_dx, dxd_dy, dyd_dx, dyd_dy),
        )
    }
}

/// The `[camera]` table of `recording.toml` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCamera {
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
    pub distortion: [f64; 5],
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
    pub pixel_noise: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            width: 720,
            height: 1280,
            fps: 60.0,
            focal: Vector2::new(1100.0, 1050.0),
            centre: Vector2::new(359.5, 639.5),
            distortion: [-0.25, 0.12, 0.003, -0.002, 0.05],
            rotation: nalgebra::Rotation3::from_euler_angles(1.4, 0.1, -0.2).into_inner(),
            translation: Vector3::new(0.1, 3.5, 7.0),
            pixel_noise: 0.7,
        }
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let cam = camera();
        for p in [
            Vector3::new(0.3, -0.2, 6.0),
            Vector3::new(-1.5, 0.4, 2.0),
            Vector3::new(2.0, 2.5, 3.0),
        ] {
            let (_, j) = cam.project_camera(&p).expect("in front");
            let h = 1e-6;
            for c in 0..3 {
                let mut a = p;
                let mut b = p;
                a[c] += h;
                b[c] -= h;
                let fd = (cam.project_camera(&a).expect("a").0
                    - cam.project_camera(&b).expect("b").0)
                    / (2.0 * h);
                let col = j.column(c);
                assert!(
                    (fd - col).norm() < 1e-5 * (1.0 + col.norm()),
                    "column {c}: fd {fd} vs {col}"
                );
            }
        }
    }

    #[test]
    fn world_jacobian_matches_finite_differences() {
        let cam = camera();
        let w = Vector3::new(0.2, 0.1, 5.0);
        let (_, j) = cam.project_world(&w).expect("visible");
        for c in 0..3 {
            let mut a = w;
            let mut b = w;
            a[c] += 1e-6;
            b[c] -= 1e-6;
            let fd = (cam.project(&a).expect("a") - cam.project(&b).expect("b")) / 2e-6;
            assert!((fd - j.column(c)).norm() < 1e-4, "column {c}");
        }
    }

    #[test]
    fn matches_opencv_reference_values() {
        // Reference computed by hand from the cv::projectPoints formulas:
        // x' = 0.1, y' = -0.05, r2 = 0.0125.
        let mut cam = camera();
        cam.rotation = Matrix3::identity();
        cam.translation = Vector3::zeros();
        cam.focal = Vector2::new(1000.0, 1000.0);
        cam.centre = Vector2::new(500.0, 400.0);
        cam.distortion = [0.1, 0.01, 0.001, 0.002, 0.0];
        let p = cam.project(&Vector3::new(0.2, -0.1, 2.0)).expect("visible");
        let r2: f64 = 0.0125;
        let radial = 1.0 + 0.1 * r2 + 0.01 * r2 * r2;
        let xd = 0.1 * radial + 2.0 * 0.001 * 0.1 * -0.05 + 0.002 * (r2 + 0.02);
        let yd = -0.05 * radial + 0.001 * (r2 + 2.0 * 0.0025) + 2.0 * 0.002 * 0.1 * -0.05;
        assert!((p.x - (1000.0 * xd + 500.0)).abs() < 1e-9);
        assert!((p.y - (1000.0 * yd + 400.0)).abs() < 1e-9);
    }

    #[test]
    fn behind_camera_is_none() {
        let mut cam = camera();
        cam.rotation = Matrix3::identity();
        cam.translation = Vector3::zeros();
        assert!(cam.project(&Vector3::new(0.0, 0.0, -1.0)).is_none());
    }
}
