//! An added mass the first states hide, found by how well a process model
//! predicts the markers (issue 15, item 4).
//!
//! Why: every estimate made from reconstructed states leans toward the
//! model the states were reconstructed with (BENCHMARKS, stop 31). The
//! first round's process model has no acceleration reaction, so its
//! smoothed rates can absorb an added mass whole. On plate
//! `added_mass=0.3` seed 5, M_a fitted on them is (-3.2, -3.8, -0.3) g
//! against the truth (0.0, 0.0, 6.6) g: significant on held-out takes but
//! with no positive part to try, so no refit ever held it. The markers do
//! not lean. The forward filter's innovation log-likelihood
//! (the prediction-error decomposition: F. C. Schweppe, IEEE Trans. Inf.
//! Theory 11, 1965; A. C. Harvey, *Forecasting, structural time series
//! models and the Kalman filter*, 1989, §3.4;
//! [`crate::reconstruct::schedule::log_likelihood`]) scores a process model
//! by how well it predicts each frame's marker pixels before it sees them.
//! Measured on that set, refining with `s` times the true M_a in the
//! process model (C_F refitted on those states, each fit with its own
//! final noise) gives -4512, -4051, -3825, -4416 at s = 0, 0.5, 1, 2: it
//! peaks at the truth. On a clean plate the same M_a gives -3565, -3788,
//! -4063, -4459: it peaks at none.
//!
//! What is searched: the scale `s` of a shape's tensor, `M_a = s M_shape`.
//! `M_shape` is the potential-flow added mass (Lamb §114,
//! [`omniad_core::reference::ellipsoid::added_mass`]) of the ellipsoid
//! inscribed in the uniform box that has the object's mass and inertia,
//! in the inertia's principal axes. That box is the object's own when it
//! is uniform; otherwise `M_shape` is only a direction, and the scales span
//! a factor of 16. Each scale is one refinement of every take (about 7 s
//! for a plate on the project's VM). The best scale starts the refit
//! rounds as a tentative added mass when it beats none (and the rival
//! reading below) by [`MIN_LOG_LIKELIHOOD_GAIN`]. The rounds re-estimate M_a whole and keep
//! it only if their own selection does, as for any tentative added mass.
//! The probe runs only when the first round leaves the reading of M_a in
//! doubt ([`super::proposal::in_doubt`]): added mass significant with
//! nothing positive to try, or the coupling (M_a without the acceleration
//! reaction) as the refits' start. Then the best scale must also beat the
//! coupling's own refinement by the same bar. The first states favour the
//! coupling for the same reason they hide added mass: they absorbed the
//! reaction that tells the two apart. Clean sets never reach the probe:
//! neither reading is significant there.

use super::proposal::Doubt;
use super::state::StateEffects;
use super::{round_config, Round};
use crate::error::Result;
use crate::input::recording::RecordingSet;
use crate::pipeline::{final_noise_scored, fit, FitConfig, FitOutcome};
use crate::reconstruct::run::{Progress, Silent};
use crate::reconstruct::schedule::log_likelihood;
use nalgebra::{Matrix3, SymmetricEigen};
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::reference::ellipsoid::added_mass;
use serde::Serialize;

/// Scales of the shape's tensor tried (a factor of 2 apart).
pub const SCALES: [f64; 5] = [0.125, 0.25, 0.5, 1.0, 2.0];

/// Least gain in innovation log-likelihood over no added mass (and over
/// the first round's reading) for the best scale to start the rounds:
/// half the 99.9 % point of χ² with one degree of freedom (10.83), a
/// likelihood-ratio test of the one scale searched.
pub const MIN_LOG_LIKELIHOOD_GAIN: f64 = 10.83 / 2.0;

/// What the probe tried and found.
#[derive(Clone, Debug, Serialize)]
pub struct AddedMassProbe {
    /// The shape's tensor at scale 1 (xx, yy, zz, xy, xz, yz, kg, body
    /// frame).
    pub shape: [f64; 6],
    /// The scales tried, 0 (the first round) first.
    pub scales: Vec<f64>,
    /// The markers' innovation log-likelihood of each scale's refinement
    /// (`None`: that refinement failed).
    pub log_likelihood: Vec<Option<f64>>,
    /// The first round's reading it was judged against (the refits' start
    /// it would replace: its effects and their refinement's
    /// log-likelihood), if any.
    pub rival: Option<Rival>,
    /// The scale that starts the rounds (`None`: none beat no added mass,
    /// and the rival where there is one, by [`MIN_LOG_LIKELIHOOD_GAIN`]).
    pub chosen: Option<f64>,
}

/// The start the probe's added mass must beat.
#[derive(Clone, Debug, Serialize)]
pub struct Rival {
    /// Its effects' names.
    pub effects: Vec<&'static str>,
    /// Its refinement's log-likelihood (`None`: it failed).
    pub log_likelihood: Option<f64>,
}

impl AddedMassProbe {
    /// The tentative added mass the rounds start from.
    pub(super) fn effect(&self) -> Option<Effect<f64>> {
        let s = self.chosen?;
        let p: Vec<f64> = self.shape.iter().map(|m| s * m).collect();
        Effect::new(EffectKind::AddedMass, &p)
    }
}

/// The potential-flow added mass (kg, xx, yy, zz, xy, xz, yz in the body
/// frame) of the ellipsoid inscribed in the uniform box with mass `mass`
/// (kg) and inertia `inertia` (kg m², body frame, about the centre of mass)
/// in air of density `rho` (kg/m³). A uniform box with edges `a, b, c` has
/// principal moments `m (b² + c²)/12` and cyclically, so `a² = 6 (I_b +
/// I_c - I_a)/m`. An edge that comes out at or below zero (a thin plate's
/// thickness in rounding) is held at 1 % of the largest.
pub fn shape_added_mass(mass: f64, inertia: &Matrix3<f64>, rho: f64) -> Option<[f64; 6]> {
    if !(mass > 0.0 && rho > 0.0) {
        return None;
    }
    let eig = SymmetricEigen::new(inertia.symmetric_part());
    let i = eig.eigenvalues;
    let edge2 = |k: usize| 6.0 * (i[(k + 1) % 3] + i[(k + 2) % 3] - i[k]) / mass;
    let edges = [0, 1, 2].map(|k| edge2(k).max(0.0).sqrt());
    let longest = edges.iter().copied().fold(0.0, f64::max);
    if !(longest > 0.0 && longest.is_finite()) {
        return None;
    }
    let semi = edges.map(|e| 0.5 * e.max(0.01 * longest));
    let m = added_mass(semi, rho);
    let tensor =
        eig.eigenvectors * Matrix3::from_diagonal(&m.into()) * eig.eigenvectors.transpose();
    let t = |r: usize, c: usize| tensor[(r, c)];
    let out = [t(0, 0), t(1, 1), t(2, 2), t(0, 1), t(0, 2), t(1, 2)];
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// The markers' innovation log-likelihood of a refinement, at its own
/// final noise (the noise its reconstruction would use; choosing that
/// noise already scored it, unless it had no correlation time to choose).
fn scored(set: &RecordingSet, cfg: &FitConfig, outcome: &FitOutcome) -> Option<f64> {
    let (noise, chosen) = final_noise_scored(set, outcome, cfg).ok()?;
    let ll = match chosen {
        Some(ll) => ll,
        None => log_likelihood(set, &outcome.model, noise, &cfg.filter).ok()?,
    };
    ll.is_finite().then_some(ll)
}

/// A refit round's refinement with `effects` in the process model (the
/// round's own settings, [`super::round_config`]) and its log-likelihood
/// (`None`: the refinement failed).
fn refined(
    set: &RecordingSet,
    cfg: &FitConfig,
    effects: &StateEffects,
) -> Option<(FitOutcome, Option<f64>)> {
    let round = round_config(cfg, effects);
    let outcome: Result<FitOutcome> = fit(set, &round, &Silent);
    let outcome = outcome.ok()?;
    let ll = scored(set, &round, &outcome);
    Some((outcome, ll))
}

/// The probe's report, and the rival's refinement when the probe chose no
/// added mass: the rounds then start from the rival, and its first round
/// is that refinement (made by the same [`super::round_config`] of the
/// same effects), not fitted again.
pub(super) struct Probed {
    pub report: AddedMassProbe,
    pub rival_outcome: Option<FitOutcome>,
}

/// Runs the probe on `set` from the first round `first` (its refinement is
/// the scale-0 one) and the reading in doubt, with `cfg` the residual
/// analysis's fit settings.
pub(super) fn probe(
    set: &RecordingSet,
    cfg: &FitConfig,
    first: &Round,
    doubt: &Doubt,
    progress: &dyn Progress,
) -> Option<Probed> {
    let shape = shape_added_mass(set.object.mass, &set.object.inertia, set.world.air_density)?;
    let runs = SCALES.len() + 1 + usize::from(doubt.rival.is_some());
    progress.stage("residual: added mass by the markers' likelihood", runs);
    let mut scales = vec![0.0];
    let first_cfg = round_config(cfg, &StateEffects::default());
    let mut ll = vec![scored(set, &first_cfg, &first.outcome)];
    progress.tick();
    let mut rival_outcome = None;
    let rival = doubt.rival.as_ref().map(|r| {
        let run = refined(set, cfg, r);
        progress.tick();
        let log_likelihood = run.as_ref().and_then(|(_, ll)| *ll);
        rival_outcome = run.map(|(o, _)| o);
        Rival {
            effects: r.effects.iter().map(|e| e.kind.name()).collect(),
            log_likelihood,
        }
    });
    for s in SCALES {
        let p: Vec<f64> = shape.iter().map(|m| s * m).collect();
        let am = Effect::new(EffectKind::AddedMass, &p);
        let effects = StateEffects {
            wind: None,
            effects: doubt.others.iter().copied().chain(am).collect(),
        };
        scales.push(s);
        ll.push(refined(set, cfg, &effects).and_then(|(_, ll)| ll));
        progress.tick();
    }
    let beat = rival.as_ref().map(|r| r.log_likelihood);
    let chosen = choose(&scales, &ll, beat);
    Some(Probed {
        report: AddedMassProbe {
            shape,
            scales,
            log_likelihood: ll,
            rival,
            chosen,
        },
        rival_outcome: rival_outcome.filter(|_| chosen.is_none()),
    })
}

/// The scale with the highest log-likelihood when it is not 0 and beats
/// scale 0 and the rival (`Some`: its log-likelihood; a rival whose
/// refinement failed is beaten) by [`MIN_LOG_LIKELIHOOD_GAIN`].
fn choose(scales: &[f64], ll: &[Option<f64>], rival: Option<Option<f64>>) -> Option<f64> {
    let none = (*ll.first()?)?;
    let (s, best) = scales
        .iter()
        .zip(ll)
        .filter_map(|(s, l)| Some((*s, (*l)?)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let bar = none.max(rival.flatten().unwrap_or(f64::NEG_INFINITY));
    (s > 0.0 && best - bar >= MIN_LOG_LIKELIHOOD_GAIN).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The box of a uniform plate's inertia is the plate: its inscribed
    /// ellipsoid's added mass is Lamb's, and turning the body turns the
    /// tensor with it.
    #[test]
    fn a_uniform_box_is_recovered_from_its_inertia() {
        let (m, [a, b, c]) = (0.048, [0.3, 0.5, 0.02]);
        let inertia = Matrix3::from_diagonal(
            &[b * b + c * c, a * a + c * c, a * a + b * b]
                .map(|x| m * x / 12.0)
                .into(),
        );
        let got = shape_added_mass(m, &inertia, 1.2).unwrap_or([f64::NAN; 6]);
        let want = added_mass([0.5 * a, 0.5 * b, 0.5 * c], 1.2);
        for k in 0..3 {
            assert!((got[k] / want[k] - 1.0).abs() < 1e-9, "{got:?} vs {want:?}");
            assert!(got[k + 3].abs() < 1e-12 * want[2]);
        }
        // The same plate turned 90° about z: xx and yy swap.
        let r = nalgebra::Rotation3::from_axis_angle(
            &nalgebra::Vector3::z_axis(),
            0.5 * std::f64::consts::PI,
        );
        let turned = r.matrix() * inertia * r.matrix().transpose();
        let t = shape_added_mass(m, &turned, 1.2).unwrap_or([f64::NAN; 6]);
        assert!((t[0] / want[1] - 1.0).abs() < 1e-9 && (t[1] / want[0] - 1.0).abs() < 1e-9);
        assert!((t[2] / want[2] - 1.0).abs() < 1e-9);
        assert!(shape_added_mass(0.0, &inertia, 1.2).is_none());
        assert!(shape_added_mass(m, &Matrix3::zeros(), 1.2).is_none());
    }

    /// The best scale is chosen only when it is not none and beats none by
    /// the bar; failed refinements are skipped.
    #[test]
    fn a_scale_is_chosen_only_when_it_beats_none_by_the_bar() {
        let s = [0.0, 0.25, 0.5, 1.0];
        let bar = MIN_LOG_LIKELIHOOD_GAIN;
        let ll = [Some(-100.0), Some(-90.0), None, Some(-95.0)];
        assert_eq!(choose(&s, &ll, None), Some(0.25));
        let near = [Some(-100.0), Some(-100.0 + 0.9 * bar), None, None];
        assert_eq!(choose(&s, &near, None), None);
        let worse = [Some(-100.0), Some(-120.0), Some(-130.0), None];
        assert_eq!(choose(&s, &worse, None), None);
        assert_eq!(choose(&s, &[None, Some(-90.0), None, None], None), None);
        // A rival reading must be beaten by the bar too; a failed one is.
        assert_eq!(choose(&s, &ll, Some(Some(-92.0))), None);
        assert_eq!(choose(&s, &ll, Some(Some(-99.0))), Some(0.25));
        assert_eq!(choose(&s, &ll, Some(None)), Some(0.25));
    }
}
