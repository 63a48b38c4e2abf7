//! The tethered kite linearised: the state matrix `A = ∂ẋ/∂x` of the very
//! model `kite fly` integrates ([`Flight::rate`]: eqs. 1-2 with the
//! primitives' eq. 14-15 air wrench and the elastic line), taken by
//! central differences about a state (normally the equilibrium of
//! [`crate::equilibrium`]), as XFLR5 and the Vortex-Step-Method tools do
//! for their stability derivatives.
//!
//! The state is the 12-vector of tangent coordinates
//! `x = [δy (world, m), δθ (body rotation vector, rad: R = R₀ exp[δθ]×),
//! v (world, m/s), Ω (body, rad/s)]`, so the quaternion's unit-norm
//! constraint does not add a spurious zero eigenvalue. About `Ω = 0` the
//! attitude kinematics `δθ̇ = Ω` hold to first order, so the second row
//! block is read from the model's quaternion rate as `2 vec(q̄ q̇)`.

use crate::flight_step::Flight;
use nalgebra::{Complex, Quaternion, SMatrix, SVector, UnitQuaternion, Vector3};
use omniad_core::rigid_body::{State, StateRate};

/// Number of tangent coordinates.
pub const STATES: usize = 12;
/// The state matrix, rows and columns in the order of the module doc.
pub type StateMatrix = SMatrix<f64, STATES, STATES>;
/// A tangent vector.
pub type Tangent = SVector<f64, STATES>;
/// A complex tangent vector (an eigenvector).
pub type CVector = SVector<Complex<f64>, STATES>;

/// Central-difference step for every coordinate (m, rad, m/s, rad/s):
/// about the cube root of machine epsilon times the unit scale, which
/// balances truncation (`O(h²)`) against rounding (`O(ε/h)`); the test
/// `step_is_in_the_flat_part` checks that halving or doubling it changes
/// `A` by far less than the eigenvalue tolerance.
pub const STEP: f64 = 1e-5;

/// `base` moved by `x`.
pub fn perturb(base: &State<f64>, x: &Tangent) -> State<f64> {
    let dtheta = x.fixed_rows::<3>(3).into_owned();
    State {
        position: base.position + x.fixed_rows::<3>(0),
        orientation: base.orientation * UnitQuaternion::from_scaled_axis(dtheta),
        velocity: base.velocity + x.fixed_rows::<3>(6),
        angular_velocity: base.angular_velocity + x.fixed_rows::<3>(9),
    }
}

/// `ẋ` at `base + x` from the flight model's own state derivative.
pub fn tangent_rate(flight: &Flight, base: &State<f64>, x: &Tangent) -> Tangent {
    let s = perturb(base, x);
    as_tangent(&s, &flight.rate(0.0, &s))
}

/// Gust inputs: the three wind components (world x, y, z).
pub const INPUTS: usize = 3;
/// The input matrix `B = ∂ẋ/∂w`, columns per world wind component.
pub type InputMatrix = SMatrix<f64, STATES, INPUTS>;

/// `B = ∂ẋ/∂w` at `base`: how a change `w` (m/s, world frame) of the
/// steady wind drives the tangent state, by central differences of the
/// same model ([`Flight::rate_in_wind`]) about the flight's mean wind,
/// with the step of [`STEP`] scaled to m/s.
pub fn input_matrix(flight: &Flight, base: &State<f64>) -> InputMatrix {
    let mean = flight.wind_model().mean;
    let h = STEP * mean.norm().max(1.0);
    let mut b = InputMatrix::zeros();
    for j in 0..INPUTS {
        let mut e = Vector3::zeros();
        e[j] = h;
        let plus = as_tangent(base, &flight.rate_in_wind(base, &(mean + e)));
        let minus = as_tangent(base, &flight.rate_in_wind(base, &(mean - e)));
        b.set_column(j, &((plus - minus) / (2.0 * h)));
    }
    b
}

/// A state rate as a tangent rate at `s`.
fn as_tangent(s: &State<f64>, r: &StateRate<f64>) -> Tangent {
    let q: Quaternion<f64> = *s.orientation.quaternion();
    let body_rate = (q.conjugate() * r.orientation) * 2.0;
    let mut out = Tangent::zeros();
    out.fixed_rows_mut::<3>(0).copy_from(&r.position);
    out.fixed_rows_mut::<3>(3).copy_from(&body_rate.imag());
    out.fixed_rows_mut::<3>(6).copy_from(&r.velocity);
    out.fixed_rows_mut::<3>(9).copy_from(&r.angular_velocity);
    out
}

/// `A = ∂ẋ/∂x` at `base` by central differences of step `h`.
pub fn state_matrix_with_step(flight: &Flight, base: &State<f64>, h: f64) -> StateMatrix {
    let mut a = StateMatrix::zeros();
    for j in 0..STATES {
        let mut e = Tangent::zeros();
        e[j] = h;
        let col = (tangent_rate(flight, base, &e) - tangent_rate(flight, base, &(-e))) / (2.0 * h);
        a.set_column(j, &col);
    }
    a
}

/// `A` at `base` with the checked step [`STEP`].
pub fn state_matrix(flight: &Flight, base: &State<f64>) -> StateMatrix {
    state_matrix_with_step(flight, base, STEP)
}

/// The eigenvector of `a` for `l` by inverse iteration (complex LU).
pub fn eigenvector(a: &StateMatrix, l: Complex<f64>) -> CVector {
    let shift = l + Complex::new(1e-9, 1e-9) * l.norm().max(1e-6);
    let m: SMatrix<Complex<f64>, STATES, STATES> =
        a.map(|x| Complex::new(x, 0.0)) - SMatrix::identity() * shift;
    let lu = m.lu();
    let mut v = CVector::from_element(Complex::new(1.0, 0.0));
    for _ in 0..3 {
        if let Some(w) = lu.solve(&v) {
            let n = w.norm();
            if n > 0.0 && n.is_finite() {
                v = w / Complex::new(n, 0.0);
            }
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flight::FlightOptions;
    use crate::{Design, Library};
    use nalgebra::Matrix3;

    fn classic() -> (Flight, State<f64>) {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let lib = Library::load(&root.join("data/primitives")).expect("library");
        let d = Design::load(&root.join("data/kites/box-classic.toml"), &lib).expect("kite");
        let opts = FlightOptions {
            gust: 0.0,
            ..FlightOptions::default()
        };
        let flight = Flight::new(d, &opts).expect("flight");
        // The symmetric classic kite starts at rest at its equilibrium.
        let base = *flight.state();
        (flight, base)
    }

    #[test]
    fn step_is_in_the_flat_part() {
        let (flight, base) = classic();
        let a = state_matrix(&flight, &base);
        let scale = a.abs().max();
        for h in [STEP / 2.0, STEP * 2.0] {
            let b = state_matrix_with_step(&flight, &base, h);
            let d = (a - b).abs().max() / scale;
            assert!(d < 1e-7, "h = {h:e}: relative change {d:e}");
        }
        // Much smaller steps are dominated by rounding.
        let tiny = state_matrix_with_step(&flight, &base, 1e-11);
        assert!((a - tiny).abs().max() / scale > 1e-7);
    }

    #[test]
    fn position_block_is_the_line_spring() {
        // Moving the kite does not change its air (uniform wind), so
        // ∂v̇/∂y is the line alone: -(k d dᵀ + T/|d| (1 - d dᵀ)) / M.
        let (flight, base) = classic();
        let a = state_matrix(&flight, &base);
        let line = flight.line();
        let at = base.position + base.orientation.transform_vector(&line.attachment);
        let d: Vector3<f64> = line.anchor - at;
        let dist = d.norm();
        let u = d / dist;
        let t = line.force(&base).norm();
        let uu = u * u.transpose();
        let k =
            (uu * line.stiffness + (Matrix3::identity() - uu) * (t / dist)) / -flight.body().mass;
        let got = a.fixed_view::<3, 3>(6, 0).into_owned();
        assert!((got - k).abs().max() < 1e-6 * k.abs().max(), "{got} vs {k}");
    }
}
