//! The steady response of the linear gust model `ẋ = A x + B w` to each
//! sinusoid of `kite fly`'s gusts ([`crate::wind::Wind::spectrum`]): the
//! one loop the gust statistics ([`crate::gusts`]) and the equivalent
//! linearisation's covariance ([`crate::equivalent`]) are summed from.

use crate::linearise::{CVector, InputMatrix, StateMatrix, STATES};
use nalgebra::{Complex, SMatrix};

/// The steady response of `ẋ = A x + B w` to each sinusoid of
/// `spectrum` ([`crate::wind::Wind::spectrum`]): `f(component, a²/2, ω, X)` with `X =
/// (iω - A)⁻¹ B e_c`, the complex amplitude per unit gust amplitude.
pub(crate) fn each_response(
    a: &StateMatrix,
    b: &InputMatrix,
    spectrum: &[Vec<(f64, f64)>; 3],
    mut f: impl FnMut(usize, f64, f64, &CVector),
) {
    let ac = a.map(|x| Complex::new(x, 0.0));
    for (c, modes) in spectrum.iter().enumerate() {
        let rhs = b.column(c).map(|x| Complex::new(x, 0.0));
        for &(amp, hz) in modes {
            let omega = 2.0 * std::f64::consts::PI * hz;
            let m: SMatrix<Complex<f64>, STATES, STATES> =
                SMatrix::identity() * Complex::new(0.0, omega) - ac;
            if let Some(x) = m.lu().solve(&rhs) {
                f(c, amp * amp / 2.0, omega, &x);
            }
        }
    }
}
