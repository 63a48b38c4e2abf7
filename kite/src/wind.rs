//! Gusty wind: a seeded, spatially uniform turbulence model.
//!
//! `v_wind(t) = U x̂ + Σ_k a_k cos(2π f_k t + φ_k)` per component, with
//! 48 frequencies log-spaced over 0.01-5 Hz, amplitudes following the
//! Dryden-shaped spectrum `S(f) ∝ 1/(1 + (2π f Λ/U)²)` (length scale
//! `Λ` = 30 m), and random phases φ_k from a SplitMix64 generator seeded
//! by the user. Amplitudes are normalised so that the standard deviations
//! are `σ_u = G`, `σ_v = 0.8 G`, `σ_w = 0.5 G` (along-wind, crosswind,
//! vertical; the usual near-ground ratios), `G` the gust strength, m/s.
//! A pure function of time, so RK4 stages see a consistent wind.
//!
//! Conditioned on its value at the release ([`Wind::conditioned`]): when a
//! kite has no equilibrium in the wind blowing at `t = 0`
//! ([`crate::launch`]), the gust is taken as the same process given that
//! it was `c` at `t = 0`, `u(t) - ρ(t) (u(0) - c)`, `ρ` the gusts'
//! autocorrelation. For a Gaussian process this has exactly the
//! conditional law (the conditional mean `ρ(t) c`, the conditional
//! covariance unchanged by the realisation; Rasmussen & Williams,
//! *Gaussian Processes for Machine Learning*, 2006, eq. A.6): the flyer
//! lets go at a moment when the wind is one the kite can rest in. `ρ`
//! falls to 0.2 at 6 s (Λ/U) and stays within ±0.18 after 10 s, so the
//! judged span's gusts keep at least 97 % of their variance.

use nalgebra::Vector3;

/// Number of sinusoids per component.
pub const MODES: usize = 48;
/// Turbulence length scale Λ, m.
pub const LENGTH_SCALE: f64 = 30.0;
/// Component standard deviations relative to G.
pub const RATIOS: [f64; 3] = [1.0, 0.8, 0.5];

/// SplitMix64: a small, well-mixed 64-bit generator.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// Seeded generator.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The wind field.
#[derive(Clone, Debug)]
pub struct Wind {
    /// Mean wind, world frame, m/s.
    pub mean: Vector3<f64>,
    /// Per component: `(amplitude m/s, frequency Hz, phase rad)`.
    modes: [Vec<(f64, f64, f64)>; 3],
    /// The part of the gust at `t = 0` the wind is conditioned away from
    /// (`u(0) - c`, world frame, m/s; zero: the unconditioned process).
    released: Vector3<f64>,
}

impl Wind {
    /// Mean `speed` (m/s) along +x with gusts of strength `gust` (m/s).
    pub fn new(speed: f64, gust: f64, seed: u64) -> Self {
        let mut rng = SplitMix64::new(seed);
        let (lo, hi) = (0.01f64, 5.0f64);
        let ratio = (hi / lo).powf(1.0 / (MODES - 1) as f64);
        let modes = RATIOS.map(|r| {
            let sigma = gust * r;
            let mut m: Vec<(f64, f64, f64)> = (0..MODES)
                .map(|k| {
                    let f = lo * ratio.powi(k as i32);
                    let df = f * (ratio - 1.0);
                    let s = 1.0
                        / (1.0
                            + (2.0 * std::f64::consts::PI * f * LENGTH_SCALE / speed.max(0.1))
                                .powi(2));
                    (
                        (s * df).sqrt(),
                        f,
                        rng.uniform() * 2.0 * std::f64::consts::PI,
                    )
                })
                .collect();
            // Variance of Σ a cos(...) is Σ a²/2.
            let var: f64 = m.iter().map(|(a, _, _)| a * a / 2.0).sum();
            let scale = if var > 0.0 { sigma / var.sqrt() } else { 0.0 };
            m.iter_mut().for_each(|mode| mode.0 *= scale);
            m
        });
        Self {
            mean: Vector3::new(speed, 0.0, 0.0),
            modes,
            released: Vector3::zeros(),
        }
    }

    /// A steady wind `v` (world frame, m/s) without gusts: the gust
    /// response ([`crate::gusts`]) differentiates the flight model's
    /// wrench with respect to the wind through it.
    pub fn steady(v: Vector3<f64>) -> Self {
        Self {
            mean: v,
            modes: [Vec::new(), Vec::new(), Vec::new()],
            released: Vector3::zeros(),
        }
    }

    /// The gust spectrum as sampled: per component (along-wind,
    /// crosswind, vertical) each sinusoid's `(amplitude m/s, frequency
    /// Hz)`. The amplitudes do not depend on the seed (only the phases
    /// do), so a linear model's response variance is the same on every
    /// seed: `Σ |G(i 2π f)|² a²/2`.
    pub fn spectrum(&self) -> [Vec<(f64, f64)>; 3] {
        self.modes
            .each_ref()
            .map(|m| m.iter().map(|&(a, f, _)| (a, f)).collect())
    }

    /// The same gusts given that the gust at `t = 0` was `gust0` (world
    /// frame, m/s; module doc): `u(t) - ρ(t) (u(0) - gust0)`.
    pub fn conditioned(mut self, gust0: Vector3<f64>) -> Self {
        self.released = Vector3::zeros();
        self.released = self.at(0.0) - self.mean - gust0;
        self
    }

    /// Wind velocity at time `t` (s), world frame, m/s.
    pub fn at(&self, t: f64) -> Vector3<f64> {
        let tau = 2.0 * std::f64::consts::PI * t;
        let g = self.modes.each_ref().map(|m| {
            m.iter()
                .map(|(a, f, p)| a * (tau * f + p).cos())
                .sum::<f64>()
        });
        let gust = Vector3::from(g);
        if self.released == Vector3::zeros() {
            return self.mean + gust;
        }
        self.mean + gust - self.released.component_mul(&self.correlation(t))
    }

    /// The gusts' autocorrelation `ρ(t) = Σ a² cos(2π f t) / Σ a²` per
    /// component (1 for a component without gusts).
    pub fn correlation(&self, t: f64) -> Vector3<f64> {
        let tau = 2.0 * std::f64::consts::PI * t;
        Vector3::from(self.modes.each_ref().map(|m| {
            let var: f64 = m.iter().map(|(a, _, _)| a * a).sum();
            let cov: f64 = m.iter().map(|(a, f, _)| a * a * (tau * f).cos()).sum();
            if var > 0.0 {
                cov / var
            } else {
                1.0
            }
        }))
    }
}
