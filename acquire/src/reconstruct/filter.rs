//! Motion reconstruction (§5): an iterated extended Kalman filter with the
//! OmniAD model as process model (`Process`) and a Rauch-Tung-Striebel
//! smoother, in error-state form (`crate::reconstruct::state`).
//!
//! Robustness: frames without observations are predicted only; a marker
//! whose innovation fails a chi-square gate is ignored and counted; when
//! every marker of [`LOST_FRAMES`] frames in a row is gated, the filter
//! assumes it is lost and accepts the next frame's markers ungated.
//!
//! Mirror-image poses: a face's four coplanar markers seen from 7 m fit two
//! poses (the face tilted towards or away from the line of sight) almost
//! equally well, and the filter can follow the wrong branch where the two
//! meet. Every `mirror_window` epochs the other branch is filtered over the
//! next `mirror_window` epochs and taken when it predicts their markers
//! clearly better; the epochs since the previous test are then filtered
//! again with a test at each, so that the switch lands where the branches
//! part, and the smoother does not carry the jump back (see
//! `Filter::mirror_test`; counted in [`FilterStats::mirror_switches`]).

use crate::input::camera::Camera;
use crate::input::recording::Object;
use crate::input::tracks::{Epoch, MarkerSighting, Observation};
use crate::reconstruct::measurement::{marker_pixel, pose_residual};
use crate::reconstruct::process::Process;
use crate::reconstruct::state::{boxminus, boxplus, Cov, Delta, FilterState};
use nalgebra::{Matrix3, Matrix6, SMatrix, Vector3};
use omniad_core::State;

mod iterated;
mod mirror;
mod smoother;

pub use smoother::body_velocity_cov;
use smoother::smooth;
pub use smoother::Posterior;

/// Consecutive fully-gated frames after which gating is suspended once.
pub const LOST_FRAMES: usize = 3;

/// Posterior miss, in pixel sigmas, beyond which a marker is an outlier.
pub const POSTERIOR_GATE: f64 = 6.0;

/// Seen markers count as coplanar (see `Filter::mirror_test`) when the
/// smallest eigenvalue of their scatter is below this fraction of the largest.
pub const MIRROR_PLANARITY: f64 = 0.01;

/// The other mirror-image branch (see `Filter::mirror_test`) is taken
/// only when it is better by this much (negative log-likelihood x2: a
/// likelihood ratio of `exp(9 / 2)`, about 90 to 1), so that nearly-tied
/// branches cannot make the estimate flicker.
pub const MIRROR_MARGIN: f64 = 9.0;

/// Default of [`FilterConfig::mirror_window`].
pub const MIRROR_WINDOW: usize = 12;

/// Filter settings. Defaults are documented per field.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterConfig {
    /// Pixel noise, 1 sigma, px (from the camera).
    pub pixel_noise: f64,
    /// Pose-track position noise, 1 sigma, m (default 2 mm).
    pub pose_position_noise: f64,
    /// Pose-track orientation noise, 1 sigma, rad (default 0.5°).
    pub pose_angle_noise: f64,
    /// Chi-square gate per marker (2 dof) / per pose (6 dof): default 25
    /// and 40 (far beyond noise; catches tracker jumps).
    pub marker_gate: f64,
    /// See `marker_gate`.
    pub pose_gate: f64,
    /// Initial 1-sigma of position (m), orientation (rad), velocity (m/s)
    /// and angular velocity (rad/s) around the take's rough guess.
    pub initial_sigma: [f64; 4],
    /// Initial 1-sigma of the unexplained force (N) and torque (N m).
    pub initial_bias: [f64; 2],
    /// Gauss-Newton iterations of each measurement update.
    pub update_iterations: usize,
    /// Forward-backward passes; each pass after the first starts from the
    /// previous pass's smoothed first state, so that the early frames are
    /// linearised about a good estimate (default 2).
    pub passes: usize,
    /// Epochs between mirror-image branch tests and epochs each test looks
    /// ahead (see `Filter::mirror_test`); 0 turns the tests off
    /// (default [`MIRROR_WINDOW`]).
    pub mirror_window: usize,
    /// Most sweeps linearised about the previous smoothed trajectory after
    /// the passes (see `filter::iterated`; default 3, 0 turns them off).
    pub relinearise: usize,
    /// The recording's steady wind, world frame, m/s: the process model's
    /// air moves with it (`V = Rᵀ(v - w)`, eqs. 5-6). Zero unless the
    /// residual analysis found one (`residual::refit`).
    pub wind: Vector3<f64>,
}

impl Default for FilterConfig {
    fn default() -> Self {
        Self {
            pixel_noise: 1.0,
            pose_position_noise: 0.002,
            pose_angle_noise: 0.5f64.to_radians(),
            marker_gate: 25.0,
            pose_gate: 40.0,
            initial_sigma: [0.3, 0.5, 5.0, 20.0],
            initial_bias: [1.0, 0.1],
            update_iterations: 4,
            passes: 2,
            mirror_window: MIRROR_WINDOW,
            relinearise: 3,
            wind: Vector3::zeros(),
        }
    }
}

/// Counts of what the filter did with the observations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilterStats {
    /// Marker rows (or poses) used.
    pub used: usize,
    /// Marker rows (or poses) rejected by the gate (outliers).
    pub gated: usize,
    /// Frames with no observation at all.
    pub empty_frames: usize,
    /// Marker rows behind the camera in the prediction (unusable).
    pub unprojectable: usize,
    /// Predictions that were not finite (the filter restarted).
    pub restarts: usize,
    /// Times the filter moved to the other mirror-image pose branch.
    pub mirror_switches: usize,
    /// Times every marker of [`LOST_FRAMES`] frames in a row was gated and
    /// the next frame's were taken ungated (the filter had lost the object).
    pub lost: usize,
}

fn finite(x: &FilterState) -> bool {
    x.body.is_finite() && x.force.iter().chain(x.torque.iter()).all(|v| v.is_finite())
}

/// A smoothed take: one state per epoch (default: none, a take left out).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Smoothed {
    /// Epoch times, s.
    pub times: Vec<f64>,
    /// Smoothed states.
    pub states: Vec<State<f64>>,
    /// Per epoch: the filter moved to the other mirror-image branch there,
    /// so the smoother does not link it to the epoch before (empty: none).
    pub cuts: Vec<bool>,
    /// Per epoch k: the smoother's posterior covariance (world frame,
    /// (m/s)²) of the central velocity difference `v_{k+1} - v_{k-1}` that
    /// eqs. (9)-(10) difference (see `smoother::velocity_difference_cov`); zero at
    /// the first and last epoch. Empty: unknown (e.g. true states).
    pub velocity_difference_cov: Vec<Matrix3<f64>>,
    /// Per epoch: the smoothed covariance of the attitude error (rad, body
    /// frame) and the velocity (m/s, world frame), in that order, from
    /// which [`Self::body_velocity_cov`] is made. Empty: unknown.
    pub attitude_velocity_cov: Vec<Matrix6<f64>>,
    /// Counts.
    pub stats: FilterStats,
}

impl Smoothed {
    /// The covariance of the body-frame velocity `V = Rᵀv` at epoch `k`,
    /// (m/s)², from [`Self::attitude_velocity_cov`] about the state there
    /// ([`body_velocity_cov`]); `None` when unknown.
    pub fn body_velocity_cov(&self, k: usize) -> Option<Matrix3<f64>> {
        let block = self.attitude_velocity_cov.get(k)?;
        Some(body_velocity_cov(self.states.get(k)?, block))
    }

    /// Whether the smoother linked epochs `from..=to` into one chain (no
    /// cut after `from` up to `to`): differences of their states are
    /// differences along one smoothed trajectory.
    pub fn linked(&self, from: usize, to: usize) -> bool {
        to < self.states.len() && !(from + 1..=to).any(|k| self.cut_at(k))
    }

    /// Whether the smoother does not link epoch `k` to the one before it.
    fn cut_at(&self, k: usize) -> bool {
        self.cuts.get(k).copied().unwrap_or(false)
    }

    /// Where a re-simulation of the take can start and be scored: the
    /// first epoch of the first chain the smoother linked ([`Self::linked`])
    /// over at least `span` s or to the take's last epoch; failing that, of
    /// the longest chain of two epochs or more. `None` when no two
    /// consecutive epochs are linked.
    ///
    /// Why not simply the first linked epoch: an epoch cut off from the
    /// rest keeps the filter's prior velocity and angular velocity (the
    /// markers see poses only), so after a cut at epoch 1 the first state
    /// is at rest while the object falls at 3 m/s; and a short chain that
    /// ends in a cut is the one the filter left for the other mirror-image
    /// branch (MuJoCo's box in wind, seed 3, `spin-12`: epochs 0-1 linked,
    /// a cut at 2, and their velocity 5.8 m/s off the chain after it). A
    /// recording compared across a cut is compared with a jump.
    pub fn first_linked_over(&self, span: f64) -> Option<usize> {
        let n = self.states.len();
        let mut longest: Option<(usize, usize)> = None;
        let mut start = 0;
        while start + 1 < n {
            let end = (start + 1..n).find(|&k| self.cut_at(k)).unwrap_or(n);
            let (first, last) = (self.times.get(start), self.times.get(end - 1));
            let spans = matches!((first, last), (Some(a), Some(b)) if b - a >= span);
            if end - start >= 2 && (spans || end == n) {
                return Some(start);
            }
            if end - start >= 2 && longest.is_none_or(|(_, len)| end - start > len) {
                longest = Some((start, end - start));
            }
            start = end;
        }
        longest.map(|(k, _)| k)
    }
}

/// Everything the filter needs besides the observations.
pub struct Filter<'a> {
    /// Process model.
    pub process: Process<'a>,
    /// Object (markers).
    pub object: &'a Object,
    /// Camera (marker takes).
    pub camera: Option<&'a Camera>,
    /// Settings.
    pub config: FilterConfig,
}

struct Step {
    predicted: FilterState,
    predicted_cov: Cov,
    filtered: FilterState,
    filtered_cov: Cov,
    /// Jacobian from the previous epoch to this one.
    jacobian: Cov,
    /// The filter moved to the other mirror-image branch at this epoch: the
    /// states before it were on the wrong one, and the smoother must not
    /// carry this jump back through the linearised dynamics.
    switched: bool,
    /// Counts and lost-frame run after this epoch (to filter again from it).
    stats: FilterStats,
    lost: usize,
}

impl Filter<'_> {
    /// Filters and smooths one take starting from `initial` (a rough guess);
    /// the counts are those of the last pass.
    pub fn run(&self, epochs: &[Epoch], initial: State<f64>) -> Smoothed {
        let mut start = FilterState::new(initial);
        let mut result = (
            Vec::new(),
            Posterior::default(),
            FilterStats::default(),
            Vec::new(),
        );
        for _ in 0..self.config.passes.max(1) {
            let mut stats = FilterStats::default();
            let steps = self.forward(epochs, start, &mut stats);
            let (smoothed, dv) = smooth(&steps);
            start = smoothed.first().copied().unwrap_or(start);
            let switched: Vec<bool> = steps.iter().map(|s| s.switched).collect();
            result = (smoothed, dv, stats, switched);
        }
        let (smoothed, dv, stats, switched) = result;
        let ((smoothed, dv), stats) = self.relinearise(
            epochs,
            FilterState::new(initial),
            (smoothed, dv),
            &switched,
            stats,
            self.config.relinearise,
        );
        Smoothed {
            times: epochs.iter().map(|e| e.t).collect(),
            states: smoothed.into_iter().map(|s| s.body).collect(),
            cuts: switched,
            velocity_difference_cov: dv.velocity_difference,
            attitude_velocity_cov: dv.attitude_velocity,
            stats,
        }
    }

    /// Smooths one take again with this filter's model, starting the
    /// relinearised sweeps (at least one) from `previous`, a smoothed
    /// trajectory of the same take made by [`Self::run`] with an earlier
    /// model, keeping its mirror-image branch and its cuts; the prior of the
    /// first epoch is still `initial`. No branch tests are made: they
    /// predict with the model, and with some fitted models they were seen to
    /// pick wrong branches that the earlier run had right. The unexplained
    /// wrench of the reference is zero (the new model's prediction); the
    /// dynamics are linear in it.
    pub fn refine(&self, epochs: &[Epoch], initial: State<f64>, previous: &Smoothed) -> Smoothed {
        if previous.states.len() != epochs.len() {
            return self.run(epochs, initial);
        }
        let reference: Vec<FilterState> = previous
            .states
            .iter()
            .map(|s| FilterState::new(*s))
            .collect();
        let ((smoothed, dv), stats) = self.relinearise(
            epochs,
            FilterState::new(initial),
            (
                reference,
                Posterior {
                    velocity_difference: previous.velocity_difference_cov.clone(),
                    attitude_velocity: previous.attitude_velocity_cov.clone(),
                },
            ),
            &previous.cuts,
            previous.stats,
            self.config.relinearise.max(1),
        );
        Smoothed {
            times: epochs.iter().map(|e| e.t).collect(),
            states: smoothed.into_iter().map(|s| s.body).collect(),
            cuts: previous.cuts.clone(),
            velocity_difference_cov: dv.velocity_difference,
            attitude_velocity_cov: dv.attitude_velocity,
            stats,
        }
    }

    fn initial_cov(&self) -> Cov {
        let mut p = Cov::zeros();
        let c = &self.config.initial_sigma;
        let sigmas = [
            c[0],
            c[1],
            c[2],
            c[3],
            self.config.initial_bias[0],
            self.config.initial_bias[1],
        ];
        for (i, s) in sigmas.iter().enumerate() {
            for j in 0..3 {
                p[(3 * i + j, 3 * i + j)] = s * s;
            }
        }
        p
    }

    fn forward(
        &self,
        epochs: &[Epoch],
        initial: FilterState,
        stats: &mut FilterStats,
    ) -> Vec<Step> {
        let mut out: Vec<Step> = Vec::with_capacity(epochs.len());
        let mut lost = 0;
        let mut prev_t = epochs.first().map(|e| e.t).unwrap_or(0.0);
        let window = self.config.mirror_window;
        // After a branch switch is found at a periodic test, the epochs since
        // the previous test are filtered again, testing at every epoch up to
        // this index, so that the switch happens where the branches part.
        let mut scan_until: Option<usize> = None;
        // Never filter the same epochs again twice, nor again before a switch.
        let (mut scanned, mut floor) = (0, 1);
        let mut i = 0;
        while let Some(e) = epochs.get(i) {
            let (predicted, predicted_cov, jacobian) = match out.last() {
                None => (initial, self.initial_cov(), Cov::identity()),
                Some(p) => {
                    let dt = e.t - prev_t;
                    let (x, f) = self.process.step_with_jacobian(&p.filtered, dt);
                    let cov =
                        f * p.filtered_cov * f.transpose() + self.process.noise(&p.filtered, dt);
                    if finite(&x) && cov.iter().all(|v| v.is_finite()) {
                        (x, cov, f)
                    } else {
                        // The model blew up: restart from the last estimate.
                        stats.restarts += 1;
                        (
                            p.filtered,
                            p.filtered_cov + self.initial_cov(),
                            Cov::identity(),
                        )
                    }
                }
            };
            prev_t = e.t;
            let (mut filtered, mut filtered_cov) = self.update(
                &e.observation,
                &predicted,
                &predicted,
                &predicted_cov,
                &mut lost,
                stats,
            );
            let mut switched = false;
            let scanning = scan_until.is_some_and(|k| i <= k);
            if !finite(&filtered) || filtered_cov.iter().any(|v| !v.is_finite()) {
                stats.restarts += 1;
                (filtered, filtered_cov) = (predicted, predicted_cov);
            } else if window > 0 && (scanning || i.is_multiple_of(window)) {
                let later = epochs.get(i + 1..).unwrap_or(&[]);
                if let Some(alt) = self.mirror_test(
                    e,
                    later,
                    &predicted,
                    &predicted_cov,
                    &filtered,
                    &filtered_cov,
                ) {
                    let back = i.saturating_sub(window - 1).max(floor);
                    if !scanning && back < i && i > scanned {
                        if let Some((b_stats, b_lost)) =
                            out.get(back - 1).map(|b| (b.stats, b.lost))
                        {
                            out.truncate(back);
                            *stats = b_stats;
                            lost = b_lost;
                            prev_t = epochs.get(back - 1).map_or(prev_t, |e| e.t);
                            scan_until = Some(i);
                            scanned = i;
                            i = back;
                            continue;
                        }
                    }
                    (filtered, filtered_cov) = alt;
                    stats.mirror_switches += 1;
                    switched = true;
                    scan_until = None;
                    floor = i + 1;
                }
            }
            out.push(Step {
                predicted,
                predicted_cov,
                filtered,
                filtered_cov,
                jacobian,
                switched,
                stats: *stats,
                lost,
            });
            i += 1;
        }
        out
    }

    /// The measurement update of prior `x`, `p`; the Gauss-Newton iterations
    /// of a marker update start from `start` (the prior itself, or the
    /// previous sweep's smoothed state when relinearising).
    fn update(
        &self,
        obs: &Observation,
        start: &FilterState,
        x: &FilterState,
        p: &Cov,
        lost: &mut usize,
        stats: &mut FilterStats,
    ) -> (FilterState, Cov) {
        match obs {
            Observation::Markers(list) if list.is_empty() => {
                stats.empty_frames += 1;
                (*x, *p)
            }
            Observation::Markers(list) => {
                let ungated = *lost >= LOST_FRAMES;
                let accepted = self.gate_markers(list, x, p, ungated, stats);
                if accepted.is_empty() {
                    *lost += 1;
                    return (*x, *p);
                }
                stats.lost += usize::from(ungated);
                *lost = 0;
                let (_, post, cov) = self.update_markers_robust(accepted, start, x, p, stats);
                (post, cov)
            }
            Observation::Pose(y, q) => self.update_pose(y, q, x, p, stats),
        }
    }

    /// The forward filter's innovation log-likelihood of one take's markers,
    /// `Σ_k -½(ν_kᵀ S_k⁻¹ ν_k + ln det S_k)` over epochs with markers (ν the
    /// stacked pixel innovations of the prediction, S their covariance);
    /// each marker's squared Mahalanobis distance is capped at the gate so
    /// that outliers count as gated. Scores process-noise settings: the
    /// better the prediction, the higher.
    pub fn log_likelihood(&self, epochs: &[Epoch], initial: State<f64>) -> f64 {
        let Some(camera) = self.camera else {
            return 0.0;
        };
        let mut stats = FilterStats::default();
        let steps = self.forward(epochs, FilterState::new(initial), &mut stats);
        let r = self.config.pixel_noise.powi(2);
        let mut total = 0.0;
        for (step, e) in steps.iter().zip(epochs) {
            let Observation::Markers(list) = &e.observation else {
                continue;
            };
            let rows: Vec<_> = list
                .iter()
                .filter_map(|m| {
                    let (_, body) = self.object.markers.get(m.marker)?;
                    let (pixel, h) = marker_pixel(camera, &step.predicted.body, body)?;
                    Some((m.pixel - pixel, h))
                })
                .collect();
            if rows.is_empty() {
                continue;
            }
            let n = 2 * rows.len();
            let mut h = nalgebra::DMatrix::<f64>::zeros(n, crate::reconstruct::state::N);
            let mut nu = nalgebra::DVector::<f64>::zeros(n);
            for (i, (d, hi)) in rows.iter().enumerate() {
                h.view_mut((2 * i, 0), (2, crate::reconstruct::state::N))
                    .copy_from(hi);
                nu.rows_mut(2 * i, 2).copy_from(d);
            }
            let p = nalgebra::DMatrix::from_column_slice(
                crate::reconstruct::state::N,
                crate::reconstruct::state::N,
                step.predicted_cov.as_slice(),
            );
            let cov = &h * p * h.transpose() + nalgebra::DMatrix::identity(n, n) * r;
            let Some(chol) = cov.cholesky() else {
                continue;
            };
            let d2 = nu
                .dot(&chol.solve(&nu))
                .min(self.config.marker_gate * rows.len() as f64);
            let log_det: f64 = 2.0 * chol.l().diagonal().iter().map(|v| v.ln()).sum::<f64>();
            total -= 0.5 * (d2 + log_det);
        }
        total
    }

    /// Markers whose innovation passes the chi-square gate (all when `force`).
    fn gate_markers(
        &self,
        list: &[MarkerSighting],
        x: &FilterState,
        p: &Cov,
        force: bool,
        stats: &mut FilterStats,
    ) -> Vec<MarkerSighting> {
        let Some(camera) = self.camera else {
            return Vec::new();
        };
        let r = self.config.pixel_noise.powi(2);
        let mut out = Vec::with_capacity(list.len());
        for m in list {
            let Some((_, body)) = self.object.markers.get(m.marker) else {
                continue;
            };
            let Some((pixel, h)) = marker_pixel(camera, &x.body, body) else {
                stats.unprojectable += 1;
                continue;
            };
            let s = h * p * h.transpose() + nalgebra::Matrix2::identity() * r;
            let nu = m.pixel - pixel;
            let d2 = s
                .try_inverse()
                .map(|si| (nu.transpose() * si * nu)[0])
                .unwrap_or(f64::INFINITY);
            if force || d2 <= self.config.marker_gate {
                out.push(*m);
            } else {
                stats.gated += 1;
            }
        }
        out
    }

    /// The update, then a posterior check: while more than three markers
    /// remain and one misses its posterior prediction by more than
    /// [`POSTERIOR_GATE`] sigmas, the worst is dropped (counted as gated) and
    /// the update redone. This catches outliers that the prior gate lets
    /// through while the prediction is still uncertain.
    fn update_markers_robust(
        &self,
        mut list: Vec<MarkerSighting>,
        start: &FilterState,
        x: &FilterState,
        p: &Cov,
        stats: &mut FilterStats,
    ) -> (Vec<MarkerSighting>, FilterState, Cov) {
        loop {
            let (post, cov) = self.update_markers(&list, start, x, p);
            let worst = self.worst_marker(&list, &post);
            match worst {
                Some((i, r)) if list.len() > 3 && r > POSTERIOR_GATE * self.config.pixel_noise => {
                    list.remove(i);
                    stats.gated += 1;
                }
                _ => {
                    stats.used += list.len();
                    return (list, post, cov);
                }
            }
        }
    }

    /// Index and pixel miss of the marker worst predicted by `x`.
    fn worst_marker(&self, list: &[MarkerSighting], x: &FilterState) -> Option<(usize, f64)> {
        let camera = self.camera?;
        list.iter()
            .enumerate()
            .filter_map(|(i, m)| {
                let (_, body) = self.object.markers.get(m.marker)?;
                let (pixel, _) = marker_pixel(camera, &x.body, body)?;
                Some((i, (m.pixel - pixel).norm()))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Iterated (Gauss-Newton) EKF update with marker pixels, information form.
    fn update_markers(
        &self,
        list: &[MarkerSighting],
        start: &FilterState,
        prior: &FilterState,
        p: &Cov,
    ) -> (FilterState, Cov) {
        let Some(camera) = self.camera else {
            return (*prior, *p);
        };
        let Some(p_inv) = p.cholesky().map(|c| c.inverse()) else {
            return (*prior, *p);
        };
        let w = 1.0 / self.config.pixel_noise.powi(2);
        let mut x = *start;
        let mut info = p_inv;
        for _ in 0..self.config.update_iterations.max(1) {
            let delta = boxminus(&x, prior);
            info = p_inv;
            let mut g = -(p_inv * delta);
            for m in list {
                let Some((_, body)) = self.object.markers.get(m.marker) else {
                    continue;
                };
                let Some((pixel, h)) = marker_pixel(camera, &x.body, body) else {
                    continue;
                };
                info += h.transpose() * h * w;
                g += h.transpose() * (m.pixel - pixel) * w;
            }
            let Some(chol) = info.cholesky() else { break };
            let step = chol.solve(&g);
            x = boxplus(&x, &step);
            if step.norm() < 1e-10 {
                break;
            }
        }
        let cov = info.cholesky().map(|c| c.inverse()).unwrap_or(*p);
        (x, cov)
    }

    fn update_pose(
        &self,
        y: &Vector3<f64>,
        q: &nalgebra::UnitQuaternion<f64>,
        x: &FilterState,
        p: &Cov,
        stats: &mut FilterStats,
    ) -> (FilterState, Cov) {
        let c = &self.config;
        let r = SMatrix::<f64, 6, 6>::from_diagonal(&SMatrix::<f64, 6, 1>::from_fn(|i, _| {
            if i < 3 {
                c.pose_position_noise.powi(2)
            } else {
                c.pose_angle_noise.powi(2)
            }
        }));
        let mut h = SMatrix::<f64, 6, { crate::reconstruct::state::N }>::zeros();
        h.fixed_view_mut::<6, 6>(0, 0).fill_with_identity();
        let nu = pose_residual(&x.body, y, q);
        let s = h * p * h.transpose() + r;
        let Some(si) = s.try_inverse() else {
            return (*x, *p);
        };
        if (nu.transpose() * si * nu)[0] > c.pose_gate {
            stats.gated += 1;
            return (*x, *p);
        }
        stats.used += 1;
        let k = p * h.transpose() * si;
        let delta: Delta = k * nu;
        let cov = (Cov::identity() - k * h) * p;
        (boxplus(x, &delta), 0.5 * (cov + cov.transpose()))
    }
}

#[cfg(test)]
mod tests;
