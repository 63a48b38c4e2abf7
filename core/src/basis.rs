//! The vector basis of §4.2: `E1 = E`, `E2 = (E × Z)/|E × Z|`, `E3 = E × E2`.
//!
//! `E1` is the radial (drag) direction, `E2` the longitudinal and `E3` the
//! latitudinal direction on a sphere whose north pole is the object's axis
//! `Z`. The basis is right-handed and orthonormal: `E1 × E2 = E3`.
//!
//! **Poles.** At `E = ±Z`, `E × Z` vanishes and the paper picks "an
//! arbitrary direction orthogonal to Z". We pick, deterministically, the
//! limit reached when approaching the pole along the meridian through the
//! body axis least aligned with `Z` (call it `A`): `E2 = (A × Z)/|A × Z|`
//! re-orthogonalised against `E`. Near the poles `E2` is re-orthogonalised
//! against `Z` and `E` (Gram-Schmidt), so the basis stays orthonormal, and
//! `E2 ⟂ Z`, to rounding even when `|E × Z|` is as small as 1e-12 (where the plain
//! formula loses most of its digits to cancellation). No input produces NaN
//! unless `E` or `Z` already contains NaN.

use crate::math::{norm, Real};
use nalgebra::Vector3;

/// `|E × Z|` above which the plain formula is used (about 3.6° from the
/// poles); nearer, Gram-Schmidt keeps the basis orthonormal.
const FAST_PATH_MIN: f64 = 1.0 / 16.0;

/// The orthonormal frame `[E1, E2, E3]` at direction `e` for pole `pole`.
///
/// `e` and `pole` must be unit vectors.
#[inline]
pub fn vector_basis<T: Real>(e: &Vector3<T>, pole: &Vector3<T>) -> [Vector3<T>; 3] {
    let cross = e.cross(pole);
    let len = norm(&cross);
    // Away from the poles the paper's formula is accurate to a few ulps
    // (the cross product's relative rounding error is about eps / |E × Z|,
    // at most 16 eps here) and much shorter: one square root and one
    // division instead of two of each, which matters because the basis is
    // on the critical path of every force evaluation.
    if len > T::of_f64(FAST_PATH_MIN) {
        let e2 = cross * (T::one() / len);
        return [*e, e2, e.cross(&e2)];
    }
    // Below this the cross product carries no direction information.
    let tiny = T::default_epsilon() * T::default_epsilon();
    let raw = if len > tiny {
        cross / len
    } else {
        pole_fallback(pole)
    };
    // Gram-Schmidt against Z, then E: removes the rounding error of the
    // cross product (relative 1e-16 / |E × Z|) from E2 · Z and E2 · E. Far
    // from the poles both steps change E2 only at rounding level; near
    // them, E2 · E after the first step is at most |E - Z|, so the second
    // step keeps E2 · Z at rounding level too.
    let raw = raw - pole * pole.dot(&raw);
    let e2 = raw - e * e.dot(&raw);
    let len2 = norm(&e2);
    let e2 = if len2 > tiny {
        e2 / len2
    } else {
        pole_fallback(pole)
    };
    let e3 = e.cross(&e2);
    [*e, e2, e3]
}

/// `(A × Z)/|A × Z|` with `A` the coordinate axis least aligned with `Z`.
fn pole_fallback<T: Real>(pole: &Vector3<T>) -> Vector3<T> {
    let (ax, ay, az) = (pole.x.abs(), pole.y.abs(), pole.z.abs());
    let axis = if ax <= ay && ax <= az {
        Vector3::x()
    } else if ay <= az {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let c = axis.cross(pole);
    let len = norm(&c);
    if len > T::zero() {
        c / len
    } else {
        // Only reachable when `pole` is zero or NaN, which the model rejects.
        Vector3::y()
    }
}
