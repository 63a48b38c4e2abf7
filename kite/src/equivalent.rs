//! The equivalent (statistical) linearisation of the tethered kite at the
//! gusts' amplitude: the state and input matrices `A_eq = E[∂f/∂x]`,
//! `B_eq = E[∂f/∂w]` of `ẋ = f(x, w)` (the flight model's tangent rate,
//! [`crate::linearise`]) averaged over the Gaussian distribution of the
//! state and the gust that the gusts themselves drive, instead of taken at
//! the equilibrium.
//!
//! Why: the linear gust response ([`crate::gusts`]) is right at small
//! gusts and too large at `kite fly`'s 1 m/s: box-three-cell with its
//! string 10 cm higher swings its line by 3.54° rms at G = 0.25 m/s (the
//! linearisation: 3.7°) but by 10.6° at G = 1 (linear: 14.8°; BENCHMARKS,
//! issue 17, kv2). The slopes at the equilibrium are not the slopes the
//! kite sees over its swing: the line's tension (tension-only, it slackens
//! in a lull), the primitives' air wrench (quadratic in the air speed,
//! saturating in the angle of attack) and the line geometry all change
//! along it. A statistic of the extremes needs the `σ` the flight has, not
//! the small-gust one.
//!
//! Method: Gaussian equivalent linearisation (J. B. Roberts & P. D. Spanos,
//! "Random Vibration and Statistical Linearization", Wiley 1990, ch. 5-6;
//! I. E. Kazakov 1956): for a Gaussian response the linear model that
//! minimises the mean-square error of `f` has the expected Jacobian as its
//! matrix, and by Stein's lemma `E[J] L = E[f(Lξ) ξᵀ]` for `z = (x, w) =
//! Lξ`, `ξ` unit Gaussian. The covariance of `z` comes from the linear
//! model itself (the spectral sums of [`crate::gusts`] over `kite fly`'s
//! sinusoids), so `A_eq`, `B_eq` and the covariance are iterated to a
//! fixed point, starting from the small-gust `A`, `B`. The expectation is
//! taken along each principal axis of the covariance in turn (a cut
//! approximation: 7-point Gauss–Hermite quadrature of `f` along that axis,
//! the others at their mean), in coordinates scaled to comparable sizes
//! (positions and velocities per line length, gusts per mean wind, angles
//! and rates as they are); the axes hold the correlated motions the gusts
//! drive (the pendulum swing with its along-wind gust, ...). Directions
//! with no spread keep the equilibrium's slope. The mean offset the
//! nonlinearity adds (`E[f] ≠ 0`) is not modelled: the extremes are taken
//! about the equilibrium, as before.
//!
//! Units: `x` in the tangent coordinates of [`crate::linearise`] (m, rad,
//! m/s, rad/s; world position and velocity, body rotation and rates), `w`
//! world m/s.

use crate::flight_step::Flight;
use crate::linearise::{InputMatrix, StateMatrix, Tangent, INPUTS, STATES};
use crate::spectral::each_response;
use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};
use omniad_core::rigid_body::State;

/// Coordinates averaged over: the state and the gust.
const Z: usize = STATES + INPUTS;
type Joint = SMatrix<f64, Z, Z>;
type JointVector = SVector<f64, Z>;
type Jacobian = SMatrix<f64, STATES, Z>;

/// Probabilists' Gauss–Hermite nodes and weights (the positive half of
/// the 7-point rule, exact for polynomials up to degree 13 under the unit
/// Gaussian; the centre node has weight 0.457 and drops out of the odd
/// moment `E[f(ξ) ξ]`).
const NODES: [f64; 3] = [
    1.154_405_394_739_968,
    2.366_759_410_734_541,
    3.750_439_717_725_742,
];
const WEIGHTS: [f64; 3] = [
    0.240_123_178_605_013,
    0.030_757_123_967_586,
    0.000_548_268_855_972,
];

/// Fixed-point iterations allowed, and the relative change of the
/// standard deviations the verdict uses counted as converged (the cut
/// approximation can end in a small cycle as principal axes swap).
const ITERATIONS: usize = 40;
const TOLERANCE: f64 = 5e-3;
/// Iterates averaged when the iteration ends in a cycle, and the largest
/// change of the spreads between them for the cycle to count (a few
/// per cent: the model's own error is larger).
const CYCLE: usize = 4;
const CYCLE_SPREAD: f64 = 0.05;
/// The fraction of each fixed-point update taken.
const RELAXATION: f64 = 0.5;
/// Principal axes with a spread below this (scaled units) keep the
/// equilibrium's slope.
const NO_SPREAD: f64 = 1e-9;

/// The linearisation at the gusts' amplitude.
#[derive(Clone, Debug)]
pub(crate) struct Equivalent {
    /// `A_eq`.
    pub a: StateMatrix,
    /// `B_eq`.
    pub b: InputMatrix,
    /// Fixed-point iterations run.
    pub iterations: usize,
}

/// The equivalent linearisation of the steady `flight` about `eq` (state
/// matrix `a`, gust input `b` there) under the gusts of `spectrum`
/// ([`crate::wind::Wind::spectrum`]). `None` when the fixed point is not
/// reached or its `A_eq` has a mode that does not decay (no stationary
/// response): the caller keeps the small-gust model.
pub(crate) fn equivalent(
    flight: &Flight,
    eq: &State<f64>,
    a: &StateMatrix,
    b: &InputMatrix,
    spectrum: &[Vec<(f64, f64)>; 3],
    elevation_row: &[f64; STATES],
) -> Option<Equivalent> {
    let scale = scales(flight);
    let j0 = joined(a, b);
    let mut j = j0;
    let mut p = covariance(a, b, spectrum);
    let mut before = spreads(&p, elevation_row);
    // The last iterates and their changes: a cycle is averaged.
    let mut last: Vec<(Jacobian, f64)> = Vec::new();
    for iteration in 1..=ITERATIONS {
        let next = expected_jacobian(flight, eq, &j0, &p, &scale);
        // Under-relaxed: the plain update overshoots (a wider spread
        // softens the slopes, which widen the spread less) and settles in
        // a two-cycle.
        j += (next - j) * RELAXATION;
        let (an, bn) = split(&j);
        if !decays(&an) {
            return None;
        }
        p = covariance(&an, &bn, spectrum);
        let after = spreads(&p, elevation_row);
        let change = before
            .iter()
            .zip(&after)
            .map(|(x, y)| (x - y).abs() / x.max(*y).max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        before = after;
        if change < TOLERANCE {
            return Some(Equivalent {
                a: an,
                b: bn,
                iterations: iteration,
            });
        }
        last.push((j, change));
        if last.len() > CYCLE {
            last.remove(0);
        }
    }
    // No fixed point: a small cycle (its spreads within CYCLE_SPREAD)
    // stands for its mean, a larger one for nothing.
    if last.iter().any(|(_, c)| !(*c < CYCLE_SPREAD)) {
        return None;
    }
    let mean = last.iter().fold(Jacobian::zeros(), |m, (j, _)| m + j) / last.len() as f64;
    let (a, b) = split(&mean);
    decays(&a).then_some(Equivalent {
        a,
        b,
        iterations: ITERATIONS,
    })
}

/// The standard deviations the verdict uses, from the covariance `p`:
/// line elevation (row `elevation_row`), height, `|Ω|`.
fn spreads(p: &Joint, elevation_row: &[f64; STATES]) -> [f64; 3] {
    let r = SVector::<f64, STATES>::from_column_slice(elevation_row);
    let pxx = p.fixed_view::<STATES, STATES>(0, 0);
    let elevation = (r.transpose() * pxx * r)[(0, 0)];
    let spin = p[(9, 9)] + p[(10, 10)] + p[(11, 11)];
    [elevation, p[(2, 2)], spin].map(|v| v.max(0.0).sqrt())
}

/// Every eigenvalue of `a` has a negative real part.
fn decays(a: &StateMatrix) -> bool {
    a.complex_eigenvalues().iter().all(|l| l.re < 0.0)
}

/// `[A B]`.
fn joined(a: &StateMatrix, b: &InputMatrix) -> Jacobian {
    let mut j = Jacobian::zeros();
    j.fixed_view_mut::<STATES, STATES>(0, 0).copy_from(a);
    j.fixed_view_mut::<STATES, INPUTS>(0, STATES).copy_from(b);
    j
}

fn split(j: &Jacobian) -> (StateMatrix, InputMatrix) {
    (
        j.fixed_view::<STATES, STATES>(0, 0).into_owned(),
        j.fixed_view::<STATES, INPUTS>(0, STATES).into_owned(),
    )
}

/// The size of one unit of each coordinate of `z`, so that the principal
/// axes do not depend on the choice of units: positions and velocities
/// per line length (an angle of the line, and its rate), gusts per mean
/// wind, angles and body rates as they are.
fn scales(flight: &Flight) -> JointVector {
    let line = flight.line().length.max(1.0);
    let wind = flight.wind_model().mean.norm().max(1.0);
    JointVector::from_fn(|i, _| match i {
        0..=2 | 6..=8 => line,
        12.. => wind,
        _ => 1.0,
    })
}

/// The joint covariance of `z = (x, w)` in the steady response of `ẋ = A
/// x + B w` to the sinusoids of `spectrum`: a sinusoid of amplitude `a`
/// in component `c` drives `x = Re(X a e^{iωt})`, `X = (iω - A)⁻¹ B e_c`,
/// so it adds `a²/2 Re(X Xᴴ)` to `Cov(x)`, `a²/2 Re X` to `Cov(x, w_c)`
/// and `a²/2` to `Var(w_c)`.
fn covariance(a: &StateMatrix, b: &InputMatrix, spectrum: &[Vec<(f64, f64)>; 3]) -> Joint {
    let mut p = Joint::zeros();
    each_response(a, b, spectrum, |c, power, _, x| {
        for i in 0..STATES {
            for k in 0..STATES {
                p[(i, k)] += power * (x[i] * x[k].conj()).re;
            }
            p[(i, STATES + c)] += power * x[i].re;
            p[(STATES + c, i)] += power * x[i].re;
        }
        p[(STATES + c, STATES + c)] += power;
    });
    p
}

/// `E[∂f/∂z]` for `z` Gaussian about the equilibrium with covariance `p`
/// (module doc): along each principal axis `d` (a one-σ displacement, real
/// units) `E[J] d = E[f(ξ d) ξ]`, the rest of `J` from `j0`.
fn expected_jacobian(
    flight: &Flight,
    eq: &State<f64>,
    j0: &Jacobian,
    p: &Joint,
    scale: &JointVector,
) -> Jacobian {
    let scaled = Joint::from_fn(|i, k| p[(i, k)] / (scale[i] * scale[k]));
    let eig = scaled.symmetric_eigen();
    let mut j = *j0;
    for (i, &lambda) in eig.eigenvalues.iter().enumerate() {
        if !(lambda > NO_SPREAD * NO_SPREAD) {
            continue;
        }
        let s = lambda.sqrt();
        let v: JointVector = eig.eigenvectors.column(i).into_owned();
        let d = v.component_mul(scale) * s;
        let mut odd = Tangent::zeros();
        for (xi, w) in NODES.iter().zip(WEIGHTS) {
            let at = |sign: f64| rate(flight, eq, &(d * (sign * xi)));
            odd += (at(1.0) - at(-1.0)) * (w * xi);
        }
        // Replace the slope along d: E[J] d = odd, keep J across it. The
        // row that reads the d-component of a displacement is vᵀ/(s S).
        let row = v.component_div(scale).transpose() / s;
        j += (odd - j0 * d) * row;
    }
    j
}

/// `f(z)`: the flight model's rate at the equilibrium moved by `z`'s
/// state part, in the mean wind plus `z`'s gust part, in coordinates that
/// follow the line: the attachment point's displacement `δp = δy +
/// R₀(δθ × P)` is taken as a turn `φ = d × δp/|d|²` about the anchor
/// plus a stretch `ρ = δp·d/|d|²` of the line `d` (anchor to attachment),
/// and the velocity turns with it. To first order these are the tangent
/// coordinates of [`crate::linearise`] (so `A_eq = A` for small gusts),
/// but a swing of tens of degrees stays on the line's sphere instead of
/// stretching the stiff line along the tangent (a 5 m sideways step on a
/// 20 m line would stretch it 0.6 m: 125 N on a 4 N kite). The
/// kinematic rows are kept exact (`ẋ_y = v`, `ẋ_θ = Ω`); the velocity's
/// rate is turned back by `-φ`.
fn rate(flight: &Flight, eq: &State<f64>, z: &JointVector) -> Tangent {
    let x: Tangent = z.fixed_rows::<STATES>(0).into_owned();
    let w = Vector3::new(z[STATES], z[STATES + 1], z[STATES + 2]);
    let line = flight.line();
    let attach = line.attachment;
    let dtheta: Vector3<f64> = x.fixed_rows::<3>(3).into_owned();
    let d = eq.position + eq.orientation.transform_vector(&attach) - line.anchor;
    let dp = x.fixed_rows::<3>(0) + eq.orientation.transform_vector(&dtheta.cross(&attach));
    let n2 = d.norm_squared().max(f64::MIN_POSITIVE);
    let turn = UnitQuaternion::from_scaled_axis(d.cross(&dp) / n2);
    let stretch = dp.dot(&d) / n2;
    let orientation = eq.orientation * UnitQuaternion::from_scaled_axis(dtheta);
    let state = State {
        position: line.anchor + turn.transform_vector(&(d * (1.0 + stretch)))
            - orientation.transform_vector(&attach),
        orientation,
        velocity: turn.transform_vector(&(eq.velocity + x.fixed_rows::<3>(6))),
        angular_velocity: eq.angular_velocity + x.fixed_rows::<3>(9),
    };
    let r = flight.rate_in_wind(&state, &(flight.wind_model().mean + w));
    let mut out = Tangent::zeros();
    out.fixed_rows_mut::<3>(0).copy_from(&x.fixed_rows::<3>(6));
    out.fixed_rows_mut::<3>(3).copy_from(&x.fixed_rows::<3>(9));
    out.fixed_rows_mut::<3>(6)
        .copy_from(&turn.inverse_transform_vector(&r.velocity));
    out.fixed_rows_mut::<3>(9).copy_from(&r.angular_velocity);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quadrature's odd moments under the unit Gaussian (centre node
    /// included): `E[ξ²] = 1`, `E[ξ⁴] = 3`, `E[ξ⁶] = 15`, `E[ξ¹²] = 10395`.
    #[test]
    fn gauss_hermite_moments() {
        let centre = 1.0 - 2.0 * WEIGHTS.iter().sum::<f64>();
        assert!((centre - 0.457_142_857_142_857).abs() < 1e-12, "{centre}");
        for (power, want) in [(2, 1.0), (4, 3.0), (6, 15.0), (12, 10395.0)] {
            let m: f64 = NODES
                .iter()
                .zip(WEIGHTS)
                .map(|(x, w)| 2.0 * w * x.powi(power))
                .sum();
            assert!((m - want).abs() < 1e-9 * want, "E[xi^{power}] = {m}");
        }
    }
}
