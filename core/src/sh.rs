//! Real orthonormal spherical harmonics `Y_lm` (the basis of eqs. 7-8).
//!
//! Convention: orthonormal on the unit sphere (`∫ Y_lm Y_l'm' dS = δ δ`),
//! no Condon-Shortley phase, so that `Y_1,-1 ∝ y`, `Y_1,0 ∝ z`, `Y_1,1 ∝ x`
//! (the usual "real spherical harmonics" table). Index `l*l + l + m`.
//!
//! All `(N+1)^2` values are produced in one pass from the Cartesian
//! components of the unit vector, without trigonometric calls: with
//! `C_m + i S_m = (x + i y)^m` and the *reduced* normalised associated
//! Legendre functions `q_l^m(z) = N_lm P_l^m(z) / sin^m θ` (polynomials in
//! `z`), `Y_l0 = q_l^0`, `Y_lm = √2 q_l^m C_m`, `Y_l,-m = √2 q_l^m S_m`.
//! `q` obeys the normalised three-term recurrence whose coefficients are
//! computed at compile time (f64, then rounded to the scalar type).

use crate::math::Real;
use nalgebra::Vector3;

/// Highest supported degree N.
pub const MAX_DEGREE: usize = 12;
/// Number of coefficients at [`MAX_DEGREE`]: `(N+1)^2`.
pub const MAX_COEFFS: usize = (MAX_DEGREE + 1) * (MAX_DEGREE + 1);

/// Number of `Y_lm` for degree `n`: `(n+1)^2`.
pub const fn coeff_count(degree: usize) -> usize {
    (degree + 1) * (degree + 1)
}

/// Flat index of `(l, m)`, `-l <= m <= l`.
pub const fn index(l: usize, m: isize) -> usize {
    ((l * l + l) as isize + m) as usize
}

const fn const_sqrt(x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    // Newton's iteration from a power-of-two start converges quadratically;
    // 64 rounds is far more than enough for every x used here (<= 1e3).
    let mut r = if x > 1.0 { x } else { 1.0 };
    let mut i = 0;
    while i < 64 {
        r = 0.5 * (r + x / r);
        i += 1;
    }
    r
}

/// Compile-time recurrence coefficients.
struct Tables {
    /// `a_lm = sqrt((4l²-1)/(l²-m²))`, at `index(l, m)`, for `l >= m+2`.
    a: [f64; MAX_COEFFS],
    /// `b_lm = sqrt(((l-1)²-m²)/(4(l-1)²-1))`, at `index(l, m)`.
    b: [f64; MAX_COEFFS],
    /// `q_m^m / q_{m-1}^{m-1} = sqrt((2m+1)/(2m))`, at `m`.
    diag: [f64; MAX_DEGREE + 1],
    /// `q_{m+1}^m / (z q_m^m) = sqrt(2m+3)`, at `m`.
    sub: [f64; MAX_DEGREE + 1],
}

// Indexing in a const initialiser cannot panic at run time: an out-of-range
// index would be a compile error.
#[allow(clippy::indexing_slicing)]
const TABLES: Tables = {
    let mut t = Tables {
        a: [0.0; MAX_COEFFS],
        b: [0.0; MAX_COEFFS],
        diag: [0.0; MAX_DEGREE + 1],
        sub: [0.0; MAX_DEGREE + 1],
    };
    let mut m = 0;
    while m <= MAX_DEGREE {
        let mf = m as f64;
        t.diag[m] = if m == 0 { 0.0 } else { const_sqrt((2.0 * mf + 1.0) / (2.0 * mf)) };
        t.sub[m] = const_sqrt(2.0 * mf + 3.0);
        let mut l = m + 2;
        while l <= MAX_DEGREE {
            let lf = l as f64;
            let i = index(l, m as isize);
            t.a[i] = const_sqrt((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf));
            let l1 = lf - 1.0;
            t.b[i] = const_sqrt((l1 * l1 - mf * mf) / (4.0 * l1 * l1 - 1.0));
            l += 1;
        }
        m += 1;
    }
    t
};

/// `1 / sqrt(4π)`: `Y_00`.
const Y00: f64 = 0.282_094_791_773_878_14;
const SQRT2: f64 = core::f64::consts::SQRT_2;

/// Writes `Y_lm(dir)` for `l = 0..=degree` into `out[index(l, m)]`.
///
/// `dir` must be a unit vector (not checked: the caller normalises once).
/// Writes `min(coeff_count(degree), out.len())` values and returns that
/// count; `degree` above [`MAX_DEGREE`] is clamped to it.
pub fn evaluate<T: Real>(degree: usize, dir: &Vector3<T>, out: &mut [T]) -> usize {
    let degree = degree.min(MAX_DEGREE);
    let (x, y, z) = (dir.x, dir.y, dir.z);
    let sqrt2 = T::of_f64(SQRT2);
    // (C_m, S_m) = Re, Im of (x + iy)^m; q_mm is the diagonal q_m^m.
    let (mut c, mut s) = (T::one(), T::zero());
    let mut q_mm = T::of_f64(Y00);
    for m in 0..=degree {
        if m > 0 {
            let (c_prev, s_prev) = (c, s);
            c = x * c_prev - y * s_prev;
            s = x * s_prev + y * c_prev;
            q_mm *= T::of_f64(TABLES.diag.get(m).copied().unwrap_or(0.0));
        }
        let sub = T::of_f64(TABLES.sub.get(m).copied().unwrap_or(0.0));
        let (mut q_prev2, mut q_prev) = (T::zero(), q_mm);
        for l in m..=degree {
            let q = if l == m {
                q_mm
            } else if l == m + 1 {
                sub * z * q_mm
            } else {
                let i = index(l, m as isize);
                let a = T::of_f64(TABLES.a.get(i).copied().unwrap_or(0.0));
                let b = T::of_f64(TABLES.b.get(i).copied().unwrap_or(0.0));
                a * (z * q_prev - b * q_prev2)
            };
            if l > m {
                q_prev2 = q_prev;
                q_prev = q;
            }
            if m == 0 {
                if let Some(o) = out.get_mut(index(l, 0)) {
                    *o = q;
                }
            } else {
                let w = sqrt2 * q;
                if let Some(o) = out.get_mut(index(l, m as isize)) {
                    *o = w * c;
                }
                if let Some(o) = out.get_mut(index(l, -(m as isize))) {
                    *o = w * s;
                }
            }
        }
    }
    coeff_count(degree).min(out.len())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::indexing_slicing, clippy::unwrap_used)]
    use super::*;

    #[test]
    fn tables_are_finite_and_positive_where_used() {
        for m in 0..=MAX_DEGREE {
            for l in m + 2..=MAX_DEGREE {
                let i = index(l, m as isize);
                assert!(TABLES.a[i] > 0.0 && TABLES.a[i].is_finite());
                assert!(TABLES.b[i] > 0.0 && TABLES.b[i].is_finite());
            }
        }
        assert!((const_sqrt(2.0) - core::f64::consts::SQRT_2).abs() < 1e-15);
    }

    #[test]
    fn short_output_is_not_overrun() {
        let mut out = [0.0f64; 5];
        let n = evaluate(12, &Vector3::new(0.0, 0.6, 0.8), &mut out);
        assert_eq!(n, 5);
    }
}
