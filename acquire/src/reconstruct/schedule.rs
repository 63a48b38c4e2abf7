//! The unexplained wrench's correlation time chosen by the markers'
//! innovation likelihood (the final reconstruction's bias time).

use crate::error::Result;
use crate::input::recording::RecordingSet;
use crate::reconstruct::filter::FilterConfig;
use crate::reconstruct::noise::ProcessNoise;
use crate::reconstruct::run::{filter, take_start};
use omniad_core::Coefficients;

/// The forward filter's innovation log-likelihood of every take's
/// markers with `model` and `noise` (`Filter::log_likelihood`), summed.
pub fn log_likelihood(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<f64> {
    let filter = filter(set, model, noise, cfg)?;
    let per: Vec<Result<f64>> = crate::parallel::map(&set.takes, |_, take| {
        Ok(filter.log_likelihood(&take.epochs, take_start(take)?))
    });
    // Summed in take order, so the total does not depend on the threads.
    per.into_iter().sum()
}

/// Correlation times tried by [`most_likely_bias_time`], as fractions of
/// the default `BIAS_TIME_SCALES·τ`, in steps of 4 down to a quarter of a
/// frame at 60 fps for a 0.58 m object (the unexplained wrench is then
/// white).
pub const BIAS_TIME_FRACTIONS: [f64; 5] = [1.0, 0.25, 0.0625, 0.015625, 0.00390625];

/// `noise` with the correlation time of its unexplained wrench chosen by
/// maximum innovation likelihood of the markers ([`log_likelihood`]) over
/// [`BIAS_TIME_FRACTIONS`], the wrench's stationary RMS kept. `noise` itself
/// when it has no finite correlation time (no model yet).
pub fn most_likely_bias_time(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<ProcessNoise> {
    Ok(most_likely_bias_time_scored(set, model, noise, cfg)?.0)
}

/// [`most_likely_bias_time`] with the log-likelihood of the noise it chose
/// (`None` when it chose none of the candidates: `noise` kept), so that a
/// caller scoring the model at that noise need not run the filter again.
pub fn most_likely_bias_time_scored(
    set: &RecordingSet,
    model: &Coefficients<f64>,
    noise: ProcessNoise,
    cfg: &FilterConfig,
) -> Result<(ProcessNoise, Option<f64>)> {
    if !noise.bias_time.is_finite() || noise.bias_time <= 0.0 {
        return Ok((noise, None));
    }
    let mut best = (None, noise);
    for fraction in BIAS_TIME_FRACTIONS {
        let candidate = noise.with_bias_time(noise.bias_time * fraction);
        let ll = log_likelihood(set, model, candidate, cfg)?;
        if ll > best.0.unwrap_or(f64::NEG_INFINITY) {
            best = (Some(ll), candidate);
        }
    }
    Ok((best.1, best.0))
}
