//! The terms of the flight model, each a named block of regressor columns
//! for the body-frame (FRD) aerodynamic force of a sample. The base model
//! is OmniAD's eq. (5) with eq. (7):
//! `F = ½ρ|V|² L² Σ_i Σ_lm α^i_lm Y_lm(E) E^i`; every candidate effect
//! adds columns, so the fit stays linear least squares.

use crate::sample::Sample;
use nalgebra::Vector3;
use omniad_core::basis::vector_basis;
use omniad_core::sh;
use serde::Serialize;

/// A measured channel a coefficient set can vary with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Channel {
    /// Depower (fraction of the range).
    Depower,
    /// Steering (fraction of the range, signed).
    Steering,
    /// Reel-in indicator (1 in the reel-in phase `pp-ri`, `flight_phase_index` 3,
    /// else 0): not a physical effect, the confounder the depower and
    /// steering channels are tested against.
    ReelIn,
}

impl Channel {
    /// The channel's value at a sample.
    pub fn value(self, s: &Sample) -> f64 {
        match self {
            Self::Depower => s.depower,
            Self::Steering => s.steering,
            Self::ReelIn => f64::from(u8::from(s.phase == 3.0)),
        }
    }

    /// The name used in `covariate:<name>`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Depower => "depower",
            Self::Steering => "steering",
            Self::ReelIn => "reel_in_phase",
        }
    }
}

/// One term of the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Term {
    /// C_F(E) of eq. (7), `3 (N+1)²` numbers.
    Base,
    /// `covariate:<channel>`: a second coefficient set blended in linearly
    /// over the channel, `C_F(E, u) = C_F(E) + (u - u₀) C_F'(E)` — the
    /// inverse-distance blend of §7 between two examples of the channel
    /// (with two examples it is exactly linear), `3 (N+1)²` numbers.
    Covariate(Channel, f64),
    /// `tether_drag`: the share of the tether's drag the kite carries,
    /// `-c ½ρ|V|² d l E` (drag of a cylinder of diameter `d` and length
    /// `l` along the apparent wind, lumped at the kite; a uniform line
    /// moving with the kite gives about `c = C_d / 4` ≈ 0.3, Argatov et al.
    /// 2009), one number `c`.
    TetherDrag(f64),
    /// `kite_inertia`: inertia the balance misses (air moving with the
    /// canopy: added mass; a wrong nominal mass), `-Δm a` in the body
    /// frame, one number `Δm` (kg).
    KiteInertia,
    /// `kcu_swing`: the control unit hanging a distance `r` below the
    /// canopy accelerates by `Ω̇ × r + Ω × (Ω × r)` more than the canopy's
    /// IMU; the balance misses `-m_kcu` times that, one number
    /// `m_kcu r` (kg m) with `r` along body +z (FRD, down).
    KcuSwing,
}

impl Term {
    /// The effect's name (`selected` in the report).
    pub fn name(&self) -> String {
        match self {
            Self::Base => "base".into(),
            Self::Covariate(c, _) => format!("covariate:{}", c.name()),
            Self::TetherDrag(_) => "tether_drag".into(),
            Self::KiteInertia => "kite_inertia".into(),
            Self::KcuSwing => "kcu_swing".into(),
        }
    }

    /// Number of columns.
    pub fn width(&self, degree: usize) -> usize {
        match self {
            Self::Base | Self::Covariate(..) => 3 * sh::coeff_count(degree),
            _ => 1,
        }
    }

    /// Whether the smoothness penalty applies (SH blocks) or only a tiny
    /// ridge (physical scalars, whose size the plausibility test judges).
    pub fn is_sh(&self) -> bool {
        matches!(self, Self::Base | Self::Covariate(..))
    }
}

/// What every term needs besides the sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// SH degree N.
    pub degree: usize,
    /// Pole Z of the vector basis (FRD).
    pub pole: Vector3<f64>,
    /// Reference length L, m.
    pub reference_length: f64,
}

/// Writes the columns of `term` for sample `s` into `out` (one force
/// vector per column, FRD, N per unit parameter).
pub fn columns(term: &Term, setup: &Setup, s: &Sample, out: &mut Vec<Vector3<f64>>) {
    let speed = s.air_velocity.norm();
    let e = s.air_velocity / speed;
    let q = 0.5 * s.air_density * speed * speed;
    match term {
        Term::Base => sh_columns(setup, &e, q * setup.reference_length.powi(2), out),
        Term::Covariate(c, centre) => {
            let k = q * setup.reference_length.powi(2) * (c.value(s) - centre);
            sh_columns(setup, &e, k, out);
        }
        Term::TetherDrag(diameter) => out.push(-e * (q * diameter * s.tether_length)),
        Term::KiteInertia => out.push(-s.acceleration),
        Term::KcuSwing => {
            let r = Vector3::z();
            let w = s.rates;
            out.push(-(s.angular_acceleration.cross(&r) + w.cross(&w.cross(&r))));
        }
    }
}

/// `k Y_lm(E) E^i` for i = 1..3 (outer) and the SH index (inner).
fn sh_columns(setup: &Setup, e: &Vector3<f64>, k: f64, out: &mut Vec<Vector3<f64>>) {
    let mut y = [0.0; sh::MAX_COEFFS];
    let n = sh::evaluate(setup.degree, e, &mut y);
    let basis = vector_basis(e, &setup.pole);
    for b in basis {
        out.extend(y.iter().take(n).map(|yk| b * (k * yk)));
    }
}

/// Per-column roughness `l(l+1)` of an SH block in column order (0 for
/// l = 0), for the smoothness penalty.
pub fn roughness(degree: usize) -> Vec<f64> {
    let one: Vec<f64> = (0..sh::coeff_count(degree))
        .map(|k| {
            let (l, _) = sh::degree_order(k);
            (l * (l + 1)) as f64
        })
        .collect();
    [one.clone(), one.clone(), one].concat()
}
