//! The mirror-image pose branches of coplanar markers (see the module
//! documentation of `filter` and `Filter::mirror_test`).

use super::{finite, Filter, FilterStats, MIRROR_MARGIN, MIRROR_PLANARITY};
use crate::input::tracks::{Epoch, MarkerSighting, Observation};
use crate::reconstruct::measurement::marker_pixel;
use crate::reconstruct::state::{Cov, FilterState};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

impl Filter<'_> {
    /// Coplanar markers seen from afar fit two poses almost equally well:
    /// the plane tilted towards or away from the line of sight (the
    /// mirror-image ambiguity of planar pose estimation). The two branches
    /// meet when the plane faces the camera, and the iterated update, a
    /// local search, follows whichever the prediction is on; a single frame
    /// cannot tell them apart, the motion over the next frames can. So the
    /// update is repeated from the prediction mirrored onto the other branch
    /// (same covariance) and, when that explains this
    /// frame's markers about as well, both are filtered over the next
    /// `mirror_window` epochs; the other branch is taken when it predicts
    /// those epochs' markers better by [`MIRROR_MARGIN`] (see
    /// [`Self::window_nll`]).
    pub(super) fn mirror_test(
        &self,
        epoch: &Epoch,
        later: &[Epoch],
        prior: &FilterState,
        p: &Cov,
        post: &FilterState,
        cov: &Cov,
    ) -> Option<(FilterState, Cov)> {
        let Observation::Markers(list) = &epoch.observation else {
            return None;
        };
        let window = later.get(..self.config.mirror_window).unwrap_or(later);
        if window.is_empty() {
            return None;
        }
        // The other hypothesis: the prediction was on the other branch.
        let other = self.mirror(list, prior)?;
        let (alt, alt_cov) = self.update_markers(list, &other, &other, p);
        if !finite(&alt) || alt_cov.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let fit = |x: &FilterState| -> f64 {
            let Some(camera) = self.camera else {
                return f64::INFINITY;
            };
            let w = 1.0 / self.config.pixel_noise.powi(2);
            list.iter()
                .filter_map(|m| {
                    let (_, body) = self.object.markers.get(m.marker)?;
                    Some(match marker_pixel(camera, &x.body, body) {
                        Some((pixel, _)) => (m.pixel - pixel).norm_squared() * w,
                        None => f64::INFINITY,
                    })
                })
                .sum()
        };
        if fit(&alt) > fit(post) + MIRROR_MARGIN {
            return None;
        }
        let here = self.window_nll(post, cov, epoch.t, window);
        let there = self.window_nll(&alt, &alt_cov, epoch.t, window);
        (there + MIRROR_MARGIN < here).then_some((alt, alt_cov))
    }

    /// How badly filtering `epochs` from `start` (at time `t`) predicts
    /// their markers: the sum over markers of the squared Mahalanobis
    /// distance of each innovation, capped at the marker gate (an outlier
    /// costs no more than that). This is the prediction-error negative
    /// log-likelihood (x2) without its `ln det S` terms, which nearly cancel
    /// between two hypotheses started with the same covariance.
    fn window_nll(&self, start: &FilterState, cov: &Cov, t: f64, epochs: &[Epoch]) -> f64 {
        let Some(camera) = self.camera else {
            return f64::INFINITY;
        };
        let r = self.config.pixel_noise.powi(2);
        let (mut x, mut p, mut prev) = (*start, *cov, t);
        let mut stats = FilterStats::default();
        let mut lost = 0;
        let mut nll = 0.0;
        for e in epochs {
            let (xn, f) = self.process.step_with_jacobian(&x, e.t - prev);
            let pn = f * p * f.transpose() + self.process.noise(&x, e.t - prev);
            prev = e.t;
            if !finite(&xn) || pn.iter().any(|v| !v.is_finite()) {
                return f64::INFINITY;
            }
            if let Observation::Markers(list) = &e.observation {
                for m in list {
                    let Some((_, body)) = self.object.markers.get(m.marker) else {
                        continue;
                    };
                    let Some((pixel, h)) = marker_pixel(camera, &xn.body, body) else {
                        nll += self.config.marker_gate;
                        continue;
                    };
                    let s = h * pn * h.transpose() + nalgebra::Matrix2::identity() * r;
                    let nu = m.pixel - pixel;
                    let d2 = s
                        .try_inverse()
                        .map(|si| (nu.transpose() * si * nu)[0])
                        .unwrap_or(f64::INFINITY);
                    nll += d2.min(self.config.marker_gate);
                }
            }
            (x, p) = self.update(&e.observation, &xn, &xn, &pn, &mut lost, &mut stats);
        }
        nll
    }

    /// The mirror-image pose of `x` for the seen markers, when they are
    /// (nearly) coplanar: the markers' offsets from their centroid reflected
    /// through the plane normal to the line of sight (`R' = S R F`, `S` the
    /// world reflection along the line of sight, `F` the body reflection
    /// across the marker plane), keeping the centroid and its velocity; the
    /// angular velocity and unexplained torque are mirrored accordingly
    /// (`Ω' = -F Ω`), the unexplained force keeps its world direction.
    pub(super) fn mirror(&self, list: &[MarkerSighting], x: &FilterState) -> Option<FilterState> {
        let camera = self.camera?;
        let pts: Vec<Vector3<f64>> = list
            .iter()
            .filter_map(|m| self.object.markers.get(m.marker).map(|(_, b)| *b))
            .collect();
        if pts.len() < 3 {
            return None;
        }
        let c = pts.iter().sum::<Vector3<f64>>() / pts.len() as f64;
        let scatter = pts
            .iter()
            .fold(Matrix3::zeros(), |a, q| a + (q - c) * (q - c).transpose());
        let eig = scatter.symmetric_eigen();
        let (imin, smallest) = eig.eigenvalues.argmin();
        let largest = eig.eigenvalues.max();
        if largest <= 0.0 || smallest > MIRROR_PLANARITY * largest {
            return None;
        }
        let m: Vector3<f64> = eig.eigenvectors.column(imin).into_owned();
        let r = x.body.orientation.to_rotation_matrix().into_inner();
        let centroid = x.body.position + r * c;
        let eye = -camera.rotation.transpose() * camera.translation;
        let l = (centroid - eye).try_normalize(1e-9)?;
        let s = Matrix3::identity() - 2.0 * l * l.transpose();
        let f = Matrix3::identity() - 2.0 * m * m.transpose();
        let r2 = s * r * f;
        let q2 = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r2));
        let w = x.body.angular_velocity;
        let w2 = -(f * w);
        // The centroid keeps its velocity; the centre of mass follows it.
        let centroid_velocity = x.body.velocity + r * w.cross(&c);
        let mut out = *x;
        out.body.orientation = q2;
        out.body.position = centroid - r2 * c;
        out.body.velocity = centroid_velocity - r2 * w2.cross(&c);
        out.body.angular_velocity = w2;
        // The unexplained force keeps its world direction (the centre of
        // mass accelerates alike); the torque mirrors like the spin.
        out.force = r2.transpose() * (r * x.force);
        out.torque = -(f * x.torque);
        Some(out)
    }
}
