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
pub(crate) struct Tables {
    /// `a_lm = sqrt((4l²-1)/(l²-m²))`, at `index(l, m)`, for `l >= m+2`.
    pub(crate) a: [f64; MAX_COEFFS],
    /// `b_lm = sqrt(((l-1)²-m²)/(4(l-1)²-1))`, at `index(l, m)`.
    pub(crate) b: [f64; MAX_COEFFS],
    /// `q_m^m / q_{m-1}^{m-1} = sqrt((2m+1)/(2m))`, at `m`.
    pub(crate) diag: [f64; MAX_DEGREE + 1],
    /// `q_{m+1}^m / (z q_m^m) = sqrt(2m+3)`, at `m`.
    pub(crate) sub: [f64; MAX_DEGREE + 1],
}

// Indexing in a const initialiser cannot panic at run time: an out-of-range
// index would be a compile error.
#[allow(clippy::indexing_slicing)]
pub(crate) const TABLES: Tables = {
    let mut t = Tables {
        a: [0.0; MAX_COEFFS],
        b: [0.0; MAX_COEFFS],
        diag: [0.0; MAX_DEGREE + 1],
        sub: [0.0; MAX_DEGREE + 1],
    };
    let mut m = 0;
    while m <= MAX_DEGREE {
        let mf = m as f64;
        t.diag[m] = if m == 0 {
            0.0
        } else {
            const_sqrt((2.0 * mf + 1.0) / (2.0 * mf))
        };
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
/// `sqrt(3)`: `q_1^0 / (z q_0^0)`.
const SQRT3: f64 = 1.732_050_807_568_877_2;

/// Writes `Y_lm(dir)` for `l = 0..=degree` into `out[index(l, m)]`.
///
/// `dir` must be a unit vector (not checked: the caller normalises once).
/// Writes `min(coeff_count(degree), out.len())` values and returns that
/// count; `degree` above [`MAX_DEGREE`] is clamped to it.
pub fn evaluate<T: ShScalar>(degree: usize, dir: &Vector3<T>, out: &mut [T]) -> usize {
    let degree = degree.min(MAX_DEGREE);
    // The walk visits (l, m) as: m = 0 for l = 0..=N, then for each m >= 1
    // and l = m..=N the pair (l, +m), (l, -m); track it to scatter each
    // value to its standard index.
    let (mut l, mut m, mut negative) = (0usize, 0isize, false);
    walk(degree, dir, |y| {
        if let Some(o) = out.get_mut(index(l, if negative { -m } else { m })) {
            *o = y;
        }
        if m == 0 {
            l += 1;
            if l > degree {
                (l, m) = (1, 1);
            }
        } else if !negative {
            negative = true;
        } else {
            negative = false;
            l += 1;
            if l > degree {
                m += 1;
                l = m as usize;
            }
        }
    });
    coeff_count(degree).min(out.len())
}

/// Position of `Y_lm` in the *walk order* of degree `degree`: the order in
/// which the recurrence produces values (m = 0 for l = 0..=N, then for each
/// m >= 1 and l = m..=N the pair `Y_lm`, `Y_l,-m`). Coefficient storage
/// uses this order so that evaluation streams through it (see
/// [`accumulate`]). `None` when `|m| > l` or `l > degree`.
pub const fn walk_position(l: usize, m: isize, degree: usize) -> Option<usize> {
    let am = m.unsigned_abs();
    if am > l || l > degree || degree > MAX_DEGREE {
        return None;
    }
    if am == 0 {
        return Some(l);
    }
    let n1 = degree + 1;
    let base = n1 + 2 * (am - 1) * n1 - (am - 1) * am;
    Some(base + 2 * (l - am) + if m < 0 { 1 } else { 0 })
}

/// `(l, m)` of the standard index `k = l*l + l + m`.
pub const fn degree_order(k: usize) -> (usize, isize) {
    let mut l = 0;
    while (l + 1) * (l + 1) <= k {
        l += 1;
    }
    (l, k as isize - (l * l + l) as isize)
}

/// Start of each order m's run of `(a_lm, b_lm)`, `l = m+2..=MAX_DEGREE`,
/// in [`WALK_AB`].
#[allow(clippy::indexing_slicing)]
const WALK_START: [usize; MAX_DEGREE + 2] = {
    let mut s = [0usize; MAX_DEGREE + 2];
    let mut m = 0;
    while m <= MAX_DEGREE {
        let run = if MAX_DEGREE >= m + 2 {
            MAX_DEGREE - m - 1
        } else {
            0
        };
        s[m + 1] = s[m] + run;
        m += 1;
    }
    s
};

/// `(a_lm, b_lm)` in walk order (m-major, then l ascending from m+2).
#[allow(clippy::indexing_slicing)]
const WALK_AB: [(f64, f64); MAX_COEFFS] = {
    let mut t = [(0.0, 0.0); MAX_COEFFS];
    let mut m = 0;
    while m <= MAX_DEGREE {
        let mut l = m + 2;
        while l <= MAX_DEGREE {
            let i = index(l, m as isize);
            t[WALK_START[m] + l - m - 2] = (TABLES.a[i], TABLES.b[i]);
            l += 1;
        }
        m += 1;
    }
    t
};

/// The walk's constants in the scalar type itself, so that evaluation does
/// no f64 -> f32 conversions (on a single-precision FPU such as the
/// Cortex-M4F those are software calls).
#[derive(Debug)]
pub struct WalkTables<T> {
    /// `(a_lm, b_lm)` in walk order ([`WALK_AB`] layout).
    ab: [(T, T); MAX_COEFFS],
    /// `q_m^m / q_{m-1}^{m-1}`.
    pub(crate) diag: [T; MAX_DEGREE + 1],
    /// `q_{m+1}^m / (z q_m^m)`.
    pub(crate) sub: [T; MAX_DEGREE + 1],
    /// `Y_00`, `sqrt(3)`, `sqrt(2)`.
    pub(crate) y00_sqrt3_sqrt2: [T; 3],
}

impl<T> WalkTables<T> {
    /// Order `m`'s run of `(a_lm, b_lm)` for `l = m+2..=degree`.
    #[inline(always)]
    pub(crate) fn ab_run(&self, m: usize, degree: usize) -> &[(T, T)] {
        let start = WALK_START.get(m).copied().unwrap_or(0);
        let len = degree.saturating_sub(m + 1);
        self.ab.get(start..start + len).unwrap_or(&[])
    }
}

/// The walk's constants in f64.
pub static WALK_F64: WalkTables<f64> = WalkTables {
    ab: WALK_AB,
    diag: TABLES.diag,
    sub: TABLES.sub,
    y00_sqrt3_sqrt2: [Y00, SQRT3, SQRT2],
};

/// The walk's constants rounded once, at compile time, to f32.
#[allow(clippy::indexing_slicing)]
pub static WALK_F32: WalkTables<f32> = {
    let mut t = WalkTables {
        ab: [(0.0f32, 0.0f32); MAX_COEFFS],
        diag: [0.0f32; MAX_DEGREE + 1],
        sub: [0.0f32; MAX_DEGREE + 1],
        y00_sqrt3_sqrt2: [Y00 as f32, SQRT3 as f32, SQRT2 as f32],
    };
    let mut i = 0;
    while i < MAX_COEFFS {
        t.ab[i] = (WALK_AB[i].0 as f32, WALK_AB[i].1 as f32);
        i += 1;
    }
    let mut m = 0;
    while m <= MAX_DEGREE {
        t.diag[m] = TABLES.diag[m] as f32;
        t.sub[m] = TABLES.sub[m] as f32;
        m += 1;
    }
    t
};

/// A scalar the SH recurrence runs in: [`Real`] plus the recurrence's
/// constants already rounded to it (f32 and f64).
pub trait ShScalar: Real + WalkValue<Self> {
    /// The walk's constants in this type.
    fn walk_tables() -> &'static WalkTables<Self>;
}

impl ShScalar for f32 {
    #[inline(always)]
    fn walk_tables() -> &'static WalkTables<Self> {
        &WALK_F32
    }
}

impl ShScalar for f64 {
    #[inline(always)]
    fn walk_tables() -> &'static WalkTables<Self> {
        &WALK_F64
    }
}

/// Σ_k rows[k] · Y_k(dir), with `rows` in the walk order of `degree`
/// ([`walk_position`]): the weighted sums of eqs. (7)-(8), fused with the
/// SH recurrence so that no intermediate buffer is written. `dir` must be
/// unit length; rows beyond `rows.len()` count as zero.
#[inline]
pub fn accumulate<T: ShScalar, const W: usize>(
    degree: usize,
    dir: &Vector3<T>,
    rows: &[[T; W]],
) -> [T; W] {
    let mut acc = [T::zero(); W];
    let mut rows = rows.iter();
    walk(degree, dir, |y| {
        if let Some(row) = rows.next() {
            for (a, &w) in acc.iter_mut().zip(row) {
                *a += w * y;
            }
        }
    });
    acc
}

/// Writes `Y_lm(dir)` in walk order into `out`; returns the count written.
pub fn evaluate_walk<T: ShScalar>(degree: usize, dir: &Vector3<T>, out: &mut [T]) -> usize {
    let mut slots = out.iter_mut();
    let mut written = 0;
    walk(degree, dir, |y| {
        if let Some(o) = slots.next() {
            *o = y;
            written += 1;
        }
    });
    written
}

/// What the recurrence runs on: the scalar itself, or eight of them side
/// by side (one body per lane, [`crate::batch`]). Every operation is the
/// scalar one applied lane by lane, so a lane rounds exactly as the scalar
/// walk does.
pub trait WalkValue<T>:
    Copy + core::ops::Add<Output = Self> + core::ops::Sub<Output = Self> + core::ops::Mul<Output = Self>
{
    /// `x` in every lane.
    fn splat(x: T) -> Self;
}

impl WalkValue<f32> for f32 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
}

impl WalkValue<f64> for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
}

/// Calls `emit` with every `Y_lm(dir)`, `l <= degree`, in walk order.
#[inline(always)]
fn walk<T: ShScalar>(degree: usize, dir: &Vector3<T>, emit: impl FnMut(T)) {
    walk_values(degree, [dir.x, dir.y, dir.z], emit);
}

/// [`walk`] over [`WalkValue`]s: `[x, y, z]` of the unit direction (one
/// direction per lane for lanes).
#[inline(always)]
pub(crate) fn walk_values<T: ShScalar, S: WalkValue<T>>(
    degree: usize,
    [x, y, z]: [S; 3],
    mut emit: impl FnMut(S),
) {
    let degree = degree.min(MAX_DEGREE);
    let t = T::walk_tables();
    let ab = |m: usize| t.ab_run(m, degree);
    let k = S::splat;
    let [y00, sqrt3, sqrt2] = t.y00_sqrt3_sqrt2;
    // m = 0: zonal harmonics.
    let mut q_mm = k(y00);
    emit(q_mm);
    if degree >= 1 {
        let (mut q2, mut q1) = (q_mm, k(sqrt3) * z * q_mm);
        emit(q1);
        for &(a, b) in ab(0) {
            let q = k(a) * (z * q1 - k(b) * q2);
            emit(q);
            q2 = q1;
            q1 = q;
        }
    }
    // m >= 1: (C_m, S_m) = (x + iy)^m carry the longitude.
    let (mut c, mut s) = (k(T::one()), k(T::zero()));
    for m in 1..=degree {
        let (c_prev, s_prev) = (c, s);
        c = x * c_prev - y * s_prev;
        s = x * s_prev + y * c_prev;
        q_mm = q_mm * k(t.diag.get(m).copied().unwrap_or_else(T::zero));
        let (cm, sm) = (k(sqrt2) * c, k(sqrt2) * s);
        emit(q_mm * cm);
        emit(q_mm * sm);
        if m == degree {
            break;
        }
        let mut q2 = q_mm;
        let mut q1 = k(t.sub.get(m).copied().unwrap_or_else(T::zero)) * z * q_mm;
        emit(q1 * cm);
        emit(q1 * sm);
        for &(a, b) in ab(m) {
            let q = k(a) * (z * q1 - k(b) * q2);
            emit(q * cm);
            emit(q * sm);
            q2 = q1;
            q1 = q;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(
        clippy::indexing_slicing,
        clippy::unwrap_used,
        clippy::needless_range_loop
    )]
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
    fn walk_positions_are_a_permutation() {
        for n in 0..=MAX_DEGREE {
            let mut seen = [false; MAX_COEFFS];
            for k in 0..coeff_count(n) {
                let (l, m) = degree_order(k);
                assert_eq!(index(l, m), k);
                let p = walk_position(l, m, n).unwrap();
                assert!(p < coeff_count(n) && !seen[p]);
                seen[p] = true;
            }
        }
    }

    #[test]
    fn accumulate_equals_evaluate_then_sum() {
        let e = Vector3::new(0.36, -0.48, 0.8);
        for n in 0..=MAX_DEGREE {
            let mut y = [0.0f64; MAX_COEFFS];
            evaluate(n, &e, &mut y);
            let mut rows = [[0.0f64; 2]; MAX_COEFFS];
            let mut want = [0.0f64; 2];
            for k in 0..coeff_count(n) {
                let (l, m) = degree_order(k);
                let w = [k as f64 + 1.0, (k * k) as f64 * 0.01 - 1.0];
                rows[walk_position(l, m, n).unwrap()] = w;
                want[0] += w[0] * y[k];
                want[1] += w[1] * y[k];
            }
            let got = accumulate(n, &e, &rows[..coeff_count(n)]);
            assert!(
                (got[0] - want[0]).abs() < 1e-10 && (got[1] - want[1]).abs() < 1e-10,
                "n = {n}"
            );
        }
    }

    #[test]
    fn short_output_is_not_overrun() {
        let mut out = [0.0f64; 5];
        let n = evaluate(12, &Vector3::new(0.0, 0.6, 0.8), &mut out);
        assert_eq!(n, 5);
    }
}
