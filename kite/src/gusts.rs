//! The gust response of the linearised tethered kite: how far the gusts
//! of `kite fly` ([`crate::wind`]) swing a kite whose modes all decay,
//! sized from the same linearisation as the modes and compared with the
//! flight's own outcome limits ([`MIN_ELEVATION_DEG`], [`MAX_SPIN`],
//! [`GROUND_CLEARANCE`]).
//!
//! Why: a decaying mode says a small disturbance dies out, not how large
//! the motion the gusts keep driving is. A kite damped at 0.2/s whose
//! equilibrium hangs at 25° line elevation is pushed below 15° by a 1 m/s
//! gust (BENCHMARKS, issue 17); the modes alone call it stable.
//!
//! Model: `ẋ = A x + B w`, `A` the state matrix and `B = ∂ẋ/∂w` the gust
//! input ([`crate::linearise`]), `w` the gust of [`crate::wind`] at the
//! default strength `G` of `kite fly` ([`FlightOptions::default`]). `A`
//! and `B` are taken at the gusts' amplitude: the equivalent (statistical)
//! linearisation of [`crate::equivalent`], the expected slopes over the
//! Gaussian spread of state and gust that they drive; the slopes at the
//! equilibrium over-predict the swing at G = 1 m/s by 10-45 % (box-three-
//! cell, the stop-19 fig15-a with the string 10 cm higher: 16.5° and 16.0° linear,
//! 13.3° and 11.3° equivalent, 11.7° and 10.9° flown; BENCHMARKS, issue
//! 17, stop 19). A kite on a limit cycle, or whose equivalent model has a
//! mode that does not decay, keeps the small-gust `A`, `B`. That
//! gust is a sum of sinusoids whose amplitudes `a_k` (at frequencies
//! `f_k`) do not depend on the seed, so in steady state every output `y =
//! C x` (line elevation, the body rates, height) has the exact spectral
//! moments `m_0 = Σ |C G(iω_k) B|² a_k²/2` and `m_2 = Σ ω_k² |…|² a_k²/2`,
//! `G(s) = (sI - A)⁻¹`, summed over the three components. Its extreme
//! over a span `T` is `g σ`, `σ = √m_0`, with the peak factor `g` of a
//! Gaussian process crossing its mean `νT` times in the span, `ν =
//! √(m_2/m_0)/2π` (S. O. Rice, "Mathematical analysis of random noise",
//! 1944-45), from the distribution of the span's largest value
//! `P(max ≤ z) ≈ Φ(z) exp(-νT e^{-z²/2})` (see [`expected_max`]). The
//! gusts are dominated by periods of 30-100 s (Λ/U = 6 s), so within the
//! 30 s the flight judges the slow part is nearly an offset: `g` is then
//! well below Davenport's many-crossing `√(2 ln νT) + 0.5772/√(2 ln νT)`
//! (A. G. Davenport, Proc. ICE 28, 1964). `T` is the span the flight
//! judges: the second half of the run for elevation and spin, the whole
//! run for the ground.
//!
//! Which extreme: the expected extreme of one run, `E[max z]`
//! ([`expected_max`]), on the `σ` at the gusts' amplitude. Two readings of
//! issue 17's "stable exactly when it flies on seeds 1-3" were measured
//! (BENCHMARKS, issue 17, stop 19; 108 variants, seeds 1-12 as four
//! triples). Design-level (stable vs flies on all three) favours the median
//! of the worst of three runs (4 / 8 / 11 / 29 disagreements against 4 /
//! 16 / 19 / 37). Flight by flight, a design whose seeds disagree among
//! themselves fails whatever the verdict, so the only errors a verdict can
//! avoid are refusing a kite that flies on all three and passing one that
//! crashes on all three: the expected extreme makes none on any triple, the
//! worst-of-three median four on seeds 1-3 (kites that fly on 1-3, and on
//! 7-9 of the twelve seeds). The per-flight reading is the acceptance's
//! wording, so the expected extreme is kept. The `σ` at the gusts'
//! amplitude gives the same verdict as the small-gust `σ` on every one of
//! the 108 variants with this statistic; it is kept because its margins are
//! the flown swing's (the small-gust `σ` over-predicts by up to 1.5x).
//!
//! The spin `|Ω|` is taken as the norm of the three body rates: its `σ`
//! is `√(Σ m_0)` and it is given the same peak factor (an approximation:
//! `|Ω|` is not Gaussian).
//!
//! A kite on a limit cycle ([`crate::limit_cycle`]: a growing mode that
//! saturates) has no stable linearisation. Its gust response is taken
//! from the same `A`, `B` (the frequency response `(iω - A)⁻¹` exists
//! while no eigenvalue lies on the imaginary axis, and a mode `σ ± iω₀`
//! contributes `|1/(iω - σ ∓ iω₀)|`, the same magnitude as the damped mode
//! `-σ ± iω₀`: the growing mode is sized as if the saturation damped it at
//! the rate it grows), and the extremes are taken from the cycle's own:
//! lowest elevation and height minus the gust's peak, largest spin plus
//! it (an upper bound: the two need not peak together).

use crate::equivalent::equivalent;
use crate::flight_step::{Flight, FlightOptions, GROUND_CLEARANCE, MAX_SPIN, MIN_ELEVATION_DEG};
use crate::limit_cycle::LimitCycle;
use crate::linearise::{perturb, InputMatrix, StateMatrix, Tangent, STATES, STEP};
use crate::spectral::each_response;
use crate::wind::Wind;
use nalgebra::Complex;
use omniad_core::rigid_body::State;
use serde::Serialize;

/// What the gusts are predicted to do to the kite.
#[derive(Clone, Debug, Serialize)]
pub struct GustReport {
    /// Gust strength G, m/s (`kite fly`'s default).
    pub gust: f64,
    /// Line elevation at the equilibrium, degrees.
    pub elevation_deg: f64,
    /// Standard deviation of the line elevation, degrees, from the model
    /// at the gusts' amplitude ([`crate::equivalent`]; the small-gust one
    /// when that has no stationary response or the kite is on a limit
    /// cycle).
    pub sigma_elevation_deg: f64,
    /// The same from the small-gust linearisation at the equilibrium,
    /// degrees.
    pub sigma_elevation_linear_deg: f64,
    /// Lowest line elevation over the judged half at the verdict's
    /// statistic ([`expected_max`]), degrees.
    pub min_elevation_deg: f64,
    /// Standard deviation of `|Ω|` (norm of the body-rate deviations),
    /// rad/s, from the same model as `sigma_elevation_deg`.
    pub sigma_spin: f64,
    /// The same from the small-gust linearisation, rad/s.
    pub sigma_spin_linear: f64,
    /// Fixed-point iterations of the equivalent linearisation; `None`:
    /// the small-gust model was used.
    pub equivalent_iterations: Option<usize>,
    /// Largest `|Ω|` over the judged half (the verdict's extreme,
    /// [`expected_max`]), rad/s.
    pub max_spin: f64,
    /// Lowest centre-of-mass height over the run (the same statistic), m.
    pub min_height: f64,
    /// The limits the flight judges by: elevation, degrees; spin, rad/s;
    /// height, m.
    pub limits: [f64; 3],
    /// The smallest of the three margins as a fraction of its room at
    /// rest: `(min_elevation - limit)/|elevation - limit|`, `1 -
    /// max_spin/limit`, `(min_height - limit)/|height - limit|`. 1: no
    /// response; 0: at a limit; negative: past one.
    pub margin: f64,
    /// Every predicted extreme is inside the flight's limits (`margin > 0`).
    pub ok: bool,
}

/// Spectral moments `(m_0, m_2)` of one output.
#[derive(Clone, Copy, Default)]
struct Moments(f64, f64);

impl Moments {
    fn add(&mut self, y: Complex<f64>, power: f64, omega: f64) {
        let p = y.norm_sqr() * power;
        self.0 += p;
        self.1 += p * omega * omega;
    }

    /// The largest excursion over `span` seconds at the verdict's
    /// statistic, `σ ẑ` ([`expected_max`]).
    fn peak(self, span: f64) -> f64 {
        let sigma = self.0.sqrt();
        if !(sigma > 0.0) {
            return 0.0;
        }
        let rate = (self.1 / self.0).sqrt() / (2.0 * std::f64::consts::PI);
        sigma * expected_max(rate * span)
    }
}

/// `E[max z]` over a span holding `n = νT` up-crossings of the mean on
/// average, `z` a unit Gaussian process: from `P(max ≤ z) ≈ Φ(z)
/// exp(-n e^{-z²/2})` (below `z` at the start, then no up-crossing of it:
/// Rice's rate, Poisson crossings), `E = ∫₀^∞ (1 - P) dz - ∫_{-∞}^0 P dz`.
/// It is 0 for a process too slow to change within the span and tends to
/// Davenport's `√(2 ln n) + 0.5772/√(2 ln n)` for many crossings.
fn expected_max(n: f64) -> f64 {
    const DZ: f64 = 0.005;
    // Midpoint rule: no sample falls on the jump of the integrand at 0.
    let mut e = 0.0;
    let mut z = -8.0 + DZ / 2.0;
    while z < 10.0 {
        let p = phi(z) * (-n * (-z * z / 2.0).exp()).exp();
        e += if z > 0.0 { 1.0 - p } else { -p } * DZ;
        z += DZ;
    }
    e
}

/// How close a motion comes to the flight's limits, as a fraction of the
/// room at rest ([`GustReport::margin`]): 1 no motion, 0 at a limit.
/// `elevation` and `height` are [extreme, at rest] (degrees, m), `spin`
/// the largest |Ω| (rad/s). Each room is taken as a magnitude, so a kite
/// resting past a limit (a line below 15° at rest) has a negative margin.
pub(crate) fn limits_margin(elevation: [f64; 2], spin: f64, height: [f64; 2]) -> f64 {
    let fraction = |[extreme, rest]: [f64; 2], limit: f64| {
        (extreme - limit) / (rest - limit).abs().max(f64::MIN_POSITIVE)
    };
    fraction(elevation, MIN_ELEVATION_DEG)
        .min(1.0 - spin / MAX_SPIN)
        .min(fraction(height, GROUND_CLEARANCE))
}

/// The unit normal distribution function `Φ(z)` (Abramowitz & Stegun
/// 7.1.26 for erfc, absolute error below 1.5e-7).
fn phi(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let tail = 0.5 * poly * (-x * x).exp();
    if z >= 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The spectral moments of line elevation (deg), height (m) and `|Ω|`
/// (rad/s) of `ẋ = A x + B w` under `spectrum`.
fn moments(
    a: &StateMatrix,
    b: &InputMatrix,
    spectrum: &[Vec<(f64, f64)>; 3],
    elevation_row: &[f64; STATES],
) -> [Moments; 3] {
    let (mut elevation, mut height) = (Moments::default(), Moments::default());
    let mut spin = [Moments::default(); 3];
    each_response(a, b, spectrum, |_, power, omega, x| {
        let e: Complex<f64> = (0..STATES).map(|k| x[k] * elevation_row[k]).sum();
        elevation.add(e, power, omega);
        height.add(x[2], power, omega);
        for (k, s) in spin.iter_mut().enumerate() {
            s.add(x[9 + k], power, omega);
        }
    });
    let spin_total = Moments(
        spin.iter().map(|s| s.0).sum(),
        spin.iter().map(|s| s.1).sum(),
    );
    [elevation, height, spin_total]
}

/// The gust response about the equilibrium `eq` of the steady `flight`,
/// with its state matrix `a` and gust input `b`, at rest there or (with
/// `cycle`) on the limit cycle its growing mode ends in, to `kite fly`'s
/// default gusts.
pub fn response(
    flight: &Flight,
    eq: &State<f64>,
    a: &StateMatrix,
    b: &InputMatrix,
    cycle: Option<&LimitCycle>,
) -> GustReport {
    response_to(flight, eq, a, b, cycle, FlightOptions::default().gust)
}

/// [`response`] to gusts of strength `gust` (m/s): the model at the
/// gusts' amplitude ([`crate::equivalent`]) for a kite at rest, the
/// small-gust `a`, `b` for one on a limit cycle (or when the equivalent
/// model has no stationary response).
pub fn response_to(
    flight: &Flight,
    eq: &State<f64>,
    a: &StateMatrix,
    b: &InputMatrix,
    cycle: Option<&LimitCycle>,
    gust: f64,
) -> GustReport {
    let opts = FlightOptions::default();
    let spectrum = Wind::new(flight.wind_model().mean.norm(), gust, 0).spectrum();
    let elevation_row = elevation_row(flight, eq);
    let linear = moments(a, b, &spectrum, &elevation_row);
    let eqv = cycle
        .is_none()
        .then(|| equivalent(flight, eq, a, b, &spectrum, &elevation_row))
        .flatten();
    let [elevation, height, spin_total] = eqv
        .as_ref()
        .map_or(linear, |e| moments(&e.a, &e.b, &spectrum, &elevation_row));
    let half = opts.seconds / 2.0;
    let at_rest = flight.line().elevation_deg(eq);
    // Without gusts: at rest, or the cycle's extremes.
    let (low, spun, lowest) = cycle.map_or((at_rest, 0.0, eq.position.z), |c| {
        (c.elevation_deg[0], c.max_spin, c.min_height)
    });
    let min_elevation = low - elevation.peak(half);
    let max_spin = spun + spin_total.peak(half);
    let min_height = lowest - height.peak(opts.seconds);
    let margin = limits_margin(
        [min_elevation, at_rest],
        max_spin,
        [min_height, eq.position.z],
    );
    GustReport {
        gust,
        elevation_deg: at_rest,
        sigma_elevation_deg: elevation.0.sqrt(),
        sigma_elevation_linear_deg: linear[0].0.sqrt(),
        min_elevation_deg: min_elevation,
        sigma_spin: spin_total.0.sqrt(),
        sigma_spin_linear: linear[2].0.sqrt(),
        equivalent_iterations: eqv.map(|e| e.iterations),
        max_spin,
        min_height,
        limits: [MIN_ELEVATION_DEG, MAX_SPIN, GROUND_CLEARANCE],
        margin,
        ok: margin > 0.0,
    }
}

/// The largest gust (m/s from the mean) of `wind`'s `component` (0
/// along-wind, 1 crosswind, 2 vertical) over `span` seconds at the
/// verdict's statistic ([`expected_max`]), counting only its sinusoids up
/// to `max_hz`: their spectral moments and Rice's peak factor, as for the
/// kite's outputs. The spectrum is symmetric, so the deepest lull is as
/// large.
pub(crate) fn gust_peak(wind: &Wind, component: usize, span: f64, max_hz: f64) -> f64 {
    let mut m = Moments::default();
    let spectrum = wind.spectrum();
    let modes = spectrum.get(component).map_or(&[][..], |v| &v[..]);
    for &(amp, f) in modes.iter().filter(|(_, f)| *f <= max_hz) {
        let omega = 2.0 * std::f64::consts::PI * f;
        m.add(Complex::new(1.0, 0.0), amp * amp / 2.0, omega);
    }
    m.peak(span)
}

/// `∂(line elevation, deg)/∂x` at `eq` by central differences.
fn elevation_row(flight: &Flight, eq: &State<f64>) -> [f64; STATES] {
    let line = flight.line();
    let mut row = [0.0; STATES];
    for (j, r) in row.iter_mut().enumerate() {
        let mut e = Tangent::zeros();
        e[j] = STEP;
        *r = (line.elevation_deg(&perturb(eq, &e)) - line.elevation_deg(&perturb(eq, &(-e))))
            / (2.0 * STEP);
    }
    row
}

/// The gust response as one text line (`kite check`).
pub fn render(g: &GustReport) -> String {
    format!(
        "  gusts (G = {} m/s, linear response): line elevation {:.1} deg ± {:.1} -> lowest {:.1} deg (limit {:.0}), |Omega| ± {:.2} -> largest {:.2} rad/s (limit {:.1}), margin {:+.2}\n",
        g.gust,
        g.elevation_deg,
        g.sigma_elevation_deg,
        g.min_elevation_deg,
        g.limits[0],
        g.sigma_spin,
        g.max_spin,
        g.limits[1],
        g.margin
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_factor_limits() {
        // Too slow to change within the span: the expected value, 0.
        assert!(expected_max(0.0).abs() < 1e-3, "{}", expected_max(0.0));
        // Many crossings: Davenport's asymptote.
        let n: f64 = 1e4;
        let l = (2.0 * n.ln()).sqrt();
        let davenport = l + 0.5772 / l;
        assert!((expected_max(n) - davenport).abs() < 0.05 * davenport);
        // More crossings, larger extremes.
        assert!(expected_max(1.0) < expected_max(10.0));
    }

    #[test]
    fn normal_distribution() {
        assert!((phi(0.0) - 0.5).abs() < 1e-7);
        assert!((phi(1.0) - 0.841_344_7).abs() < 1e-6);
        assert!((phi(-2.0) - 0.022_750_1).abs() < 1e-6);
    }
}
