//! The batch's SH sums for f32 on AVX registers ([`crate::batch`]): eight
//! bodies, one per lane, `Σ_k rows[k] Y_k(e)` for the six sets.
//!
//! Why its own code: the batch's generic lanes ([`crate::sh::walk_values`]
//! over `Lanes<f32>`, arrays of eight scalars) compile to scalar
//! accumulators that are taken apart and put back together around every
//! term (profiled: about 100 shuffles per coefficient row), which cost
//! more than the arithmetic. Here every value is one `__m256` register.
//!
//! Two passes: the recurrence writes the harmonics of all eight lanes to
//! a buffer, then the weighting streams through them. Fused (weighting
//! each harmonic as it is made, as the portable walk does) the weighting
//! of one order waits on that order's serial recurrence chain and fills
//! the processor's window, so the next order's chain starts late; split,
//! the short recurrence code of many orders overlaps and the weighting is
//! bound by multiplier throughput only.
//!
//! Every step is the portable walk's scalar operation, in the same order,
//! as one separate vector multiply, add or subtract (never a fused
//! multiply-add), so each lane is *bit for bit* what
//! [`crate::sh::accumulate`] gives for that lane's direction
//! (`core/tests/batch.rs` compares them).

use super::load;
use crate::lanes::{Lanes, SETS};
use crate::sh::{coeff_count, MAX_COEFFS, MAX_DEGREE, WALK_F32};
use core::arch::x86_64::{
    __m256, _mm256_add_ps, _mm256_mul_ps, _mm256_set1_ps, _mm256_setzero_ps, _mm256_store_ps,
    _mm256_sub_ps,
};
use core::mem::MaybeUninit;

/// The harmonics of one walk, in walk order: written by the recurrence,
/// then read by the weighting (two passes, see [`batch_sums`]).
struct Harmonics {
    y: [MaybeUninit<__m256>; MAX_COEFFS],
    len: usize,
}

impl Harmonics {
    /// Appends `y` (ignored past [`MAX_COEFFS`]).
    #[target_feature(enable = "avx")]
    #[inline]
    fn emit(&mut self, y: __m256) {
        if let Some(slot) = self.y.get_mut(self.len) {
            slot.write(y);
            self.len += 1;
        }
    }
}

/// `a (z q1 - b q2)`: one step of the three-term recurrence in `l`.
#[target_feature(enable = "avx")]
#[inline]
fn step(a: f32, b: f32, z: __m256, q1: __m256, q2: __m256) -> __m256 {
    let zq = _mm256_mul_ps(z, q1);
    let bq = _mm256_mul_ps(_mm256_set1_ps(b), q2);
    _mm256_mul_ps(_mm256_set1_ps(a), _mm256_sub_ps(zq, bq))
}

/// [`crate::sh::walk_values`] with `emit` weighting `rows` (walk order),
/// for unit directions `[x, y, z]` one per lane. `None` when `rows` is
/// shorter than the degree's count (the generic lanes then handle it).
#[target_feature(enable = "avx")]
#[inline]
pub(crate) fn batch_sums(
    degree: usize,
    rows: &[[f32; SETS]],
    [x, y, z]: &[Lanes<f32>; 3],
) -> Option<[Lanes<f32>; SETS]> {
    let degree = degree.min(MAX_DEGREE);
    if rows.len() < coeff_count(degree) {
        return None;
    }
    let (x, y, z) = (load(x), load(y), load(z));
    let t = &WALK_F32;
    let k = _mm256_set1_ps;
    let mut ys = Harmonics {
        y: [MaybeUninit::uninit(); MAX_COEFFS],
        len: 0,
    };
    let [y00, sqrt3, sqrt2] = t.y00_sqrt3_sqrt2;
    // m = 0: zonal harmonics.
    let mut q_mm = k(y00);
    ys.emit(q_mm);
    if degree >= 1 {
        let (mut q2, mut q1) = (q_mm, _mm256_mul_ps(_mm256_mul_ps(k(sqrt3), z), q_mm));
        ys.emit(q1);
        for &(a, b) in t.ab_run(0, degree) {
            let q = step(a, b, z, q1, q2);
            ys.emit(q);
            (q2, q1) = (q1, q);
        }
    }
    // m >= 1: (C_m, S_m) = (x + iy)^m carry the longitude.
    let (mut c, mut s) = (k(1.0), k(0.0));
    for m in 1..=degree {
        let (c_prev, s_prev) = (c, s);
        c = _mm256_sub_ps(_mm256_mul_ps(x, c_prev), _mm256_mul_ps(y, s_prev));
        s = _mm256_add_ps(_mm256_mul_ps(x, s_prev), _mm256_mul_ps(y, c_prev));
        q_mm = _mm256_mul_ps(q_mm, k(t.diag.get(m).copied().unwrap_or(0.0)));
        let (cm, sm) = (_mm256_mul_ps(k(sqrt2), c), _mm256_mul_ps(k(sqrt2), s));
        ys.emit(_mm256_mul_ps(q_mm, cm));
        ys.emit(_mm256_mul_ps(q_mm, sm));
        if m == degree {
            break;
        }
        let sub = k(t.sub.get(m).copied().unwrap_or(0.0));
        let mut q2 = q_mm;
        let mut q1 = _mm256_mul_ps(_mm256_mul_ps(sub, z), q_mm);
        ys.emit(_mm256_mul_ps(q1, cm));
        ys.emit(_mm256_mul_ps(q1, sm));
        for &(a, b) in t.ab_run(m, degree) {
            let q = step(a, b, z, q1, q2);
            ys.emit(_mm256_mul_ps(q, cm));
            ys.emit(_mm256_mul_ps(q, sm));
            (q2, q1) = (q1, q);
        }
    }
    // Second pass: `acc[s] += row[s] y` row by row, the portable
    // `*a += w * y` in walk order.
    let mut acc = [_mm256_setzero_ps(); SETS];
    let written = ys.y.get(..ys.len).unwrap_or(&[]);
    for (row, y) in rows.iter().zip(written) {
        // SAFETY: the first `len` harmonics were written by `emit`.
        let y = unsafe { y.assume_init() };
        for (a, &w) in acc.iter_mut().zip(row) {
            *a = _mm256_add_ps(*a, _mm256_mul_ps(_mm256_set1_ps(w), y));
        }
    }
    let mut out = [Lanes([0.0f32; 8]); SETS];
    for (o, a) in out.iter_mut().zip(acc) {
        // SAFETY: `Lanes<f32>` is 32-byte aligned and holds eight f32.
        unsafe { _mm256_store_ps(o.0.as_mut_ptr(), a) };
    }
    Some(out)
}
