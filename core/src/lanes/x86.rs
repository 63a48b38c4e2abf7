//! The AVX path for f32: coefficient storage in lane layout
//! ([`LaneBlocks`]), the kernel, and AVX detection without `std` (CPUID
//! and XCR0, as `is_x86_feature_detected!` does).
//!
//! AVX and FMA are not in the x86_64 baseline, so the kernel is compiled
//! with `#[target_feature(enable = "avx,fma")]` and chosen at run time;
//! without them the portable path runs.

mod batch_walk;

use super::{
    first_powers, group_ab, group_start, Lanes, SimdCoefficients, SimdKernel, BLOCKS, LANES,
    LANES_F32, SETS,
};
use crate::sh::MAX_DEGREE;
use core::arch::x86_64::{
    __cpuid, __m128, __m256, _mm256_castps256_ps128, _mm256_extractf128_ps, _mm256_fmadd_ps,
    _mm256_fmsub_ps, _mm256_hadd_ps, _mm256_load_ps, _mm256_mul_ps, _mm256_set1_ps,
    _mm256_set_m128, _mm256_setzero_ps, _mm_add_ps, _mm_mul_ps, _mm_set1_ps, _mm_set_ps,
    _mm_setzero_ps, _mm_storeu_ps, _mm_sub_ps, _xgetbv,
};
use core::sync::atomic::{AtomicU8, Ordering};
use nalgebra::Vector3;

/// One step of one group: `[part][set]`, one lane per order; part 0 holds
/// the coefficients of `Y_{l,m}` (cosine), part 1 those of `Y_{l,-m}` (sine).
pub type Block<T> = [[Lanes<T>; SETS]; 2];

/// Coefficients in lane layout: step `j` of group `g` (orders
/// `8g..8g+7`) is block `group_start(g) + j`. Entries beyond the model's
/// degree stay zero (the kernel relies on it).
#[derive(Clone, Debug, PartialEq)]
pub struct LaneBlocks(pub [Block<f32>; BLOCKS]);

/// Where the coefficient of `Y_lm` lives: `(block, part, lane)`. `None`
/// when `|m| > l` or `l > MAX_DEGREE`.
pub const fn slot(l: usize, m: isize) -> Option<(usize, usize, usize)> {
    let am = m.unsigned_abs();
    if am > l || l > MAX_DEGREE {
        return None;
    }
    let part = if m < 0 { 1 } else { 0 };
    Some((group_start(am / LANES) + (l - am), part, am % LANES))
}

impl SimdCoefficients<f32> for LaneBlocks {
    fn zeroed() -> Self {
        Self([[[Lanes([0.0; LANES]); SETS]; 2]; BLOCKS])
    }
    fn set(&mut self, l: usize, m: isize, set: usize, value: f32) {
        let Some((block, part, lane)) = slot(l, m) else {
            return;
        };
        let entry = self
            .0
            .get_mut(block)
            .and_then(|b| b.get_mut(part))
            .and_then(|p| p.get_mut(set))
            .and_then(|lanes| lanes.0.get_mut(lane));
        if let Some(entry) = entry {
            *entry = value;
        }
    }
    #[inline(always)]
    fn run<K: SimdKernel>(kernel: &K) -> K::Output {
        if has_avx() {
            // SAFETY: AVX and FMA support was just checked.
            unsafe { run_avx(kernel) }
        } else {
            kernel.run()
        }
    }
    #[inline(always)]
    fn lane_sums(
        degree: usize,
        rows: &[[f32; SETS]],
        e: &[Lanes<f32>; 3],
    ) -> Option<[Lanes<f32>; SETS]> {
        if has_avx() {
            // SAFETY: AVX support was just checked.
            unsafe { batch_walk::batch_sums(degree, rows, e) }
        } else {
            None
        }
    }
    #[inline]
    fn accumulate(&self, degree: usize, dir: &Vector3<f32>) -> Option<[f32; SETS]> {
        if has_avx() {
            // SAFETY: AVX support was just checked.
            Some(unsafe { accumulate_avx(degree, dir, &self.0) })
        } else {
            None
        }
    }
}

/// `kernel` compiled with AVX and FMA when the machine has them, for any
/// scalar type (the batch path of [`crate::batch`] runs f32 and f64 this
/// way: eight bodies per lane group become one or two vector instructions).
#[inline(always)]
pub(crate) fn run_wide<K: SimdKernel>(kernel: &K) -> K::Output {
    if has_avx() {
        // SAFETY: AVX and FMA support was just checked.
        unsafe { run_avx(kernel) }
    } else {
        kernel.run()
    }
}

/// `kernel` (e.g. [`crate::Coefficients::wrench`]) compiled with AVX and
/// FMA enabled.
#[target_feature(enable = "avx,fma")]
fn run_avx<K: SimdKernel>(kernel: &K) -> K::Output {
    kernel.run()
}

/// The blocks of group `g`'s steps `0..steps`.
#[inline(always)]
fn group_blocks(blocks: &[Block<f32>; BLOCKS], g: usize, steps: usize) -> &[Block<f32>] {
    let start = group_start(g);
    blocks.get(start..start + steps).unwrap_or(&[])
}

/// 0: not yet detected, 1: no AVX, 2: AVX.
static AVX: AtomicU8 = AtomicU8::new(0);

/// Whether the processor has AVX and FMA and the OS saves the YMM
/// registers (detected once).
#[inline]
pub(super) fn has_avx() -> bool {
    match AVX.load(Ordering::Relaxed) {
        1 => false,
        2 => true,
        _ => {
            let found = detect_avx_fma();
            AVX.store(if found { 2 } else { 1 }, Ordering::Relaxed);
            found
        }
    }
}

#[cold]
fn detect_avx_fma() -> bool {
    // CPUID leaf 1, ECX: bit 12 FMA, bit 27 OSXSAVE (XGETBV usable),
    // bit 28 AVX.
    // SAFETY: CPUID leaf 1 exists on every x86_64 processor.
    #[allow(unused_unsafe)]
    let ecx = unsafe { __cpuid(1) }.ecx;
    let needed = (1 << 12) | (1 << 27) | (1 << 28);
    if ecx & needed != needed {
        return false;
    }
    // SAFETY: OSXSAVE is set, so XGETBV is available.
    let xcr0 = unsafe { xcr0() };
    // XCR0 bits 1 (SSE state) and 2 (AVX state): the OS preserves YMM.
    xcr0 & 0b110 == 0b110
}

#[target_feature(enable = "xsave")]
unsafe fn xcr0() -> u64 {
    _xgetbv(0)
}

#[target_feature(enable = "avx")]
#[inline]
fn load(v: &Lanes<f32>) -> __m256 {
    // SAFETY: `Lanes<f32>` is 32-byte aligned and holds eight f32.
    unsafe { _mm256_load_ps(v.0.as_ptr()) }
}

/// Step 1, four orders per complex product: `(Re, Im)` of `w_m`,
/// `m = 0..16`, as four 4-lane pairs.
#[target_feature(enable = "avx")]
#[inline]
fn powers(degree: usize, dir: &Vector3<f32>) -> [(__m128, __m128); 4] {
    let [w1, w2, w3, u] = first_powers(dir);
    let (ur, ui) = (_mm_set1_ps(u.0), _mm_set1_ps(u.1));
    let times_u = |(re, im): (__m128, __m128)| {
        (
            _mm_sub_ps(_mm_mul_ps(re, ur), _mm_mul_ps(im, ui)),
            _mm_add_ps(_mm_mul_ps(re, ui), _mm_mul_ps(im, ur)),
        )
    };
    let w0_3 = (
        _mm_set_ps(w3.0, w2.0, w1.0, 1.0),
        _mm_set_ps(w3.1, w2.1, w1.1, 0.0),
    );
    let w4_7 = times_u(w0_3);
    let w8_11 = times_u(w4_7);
    // Orders 12.. only exist at the maximum degree.
    let w12_15 = if degree >= 12 {
        times_u(w8_11)
    } else {
        (_mm_setzero_ps(), _mm_setzero_ps())
    };
    [w0_3, w4_7, w8_11, w12_15]
}

/// Steps 2-3 for one group, added into `acc` lane by lane: cosine and
/// sine terms into separate accumulators, so that each accumulator's chain
/// has one fused multiply-add per step (the latency bound of the loop).
#[target_feature(enable = "avx,fma")]
#[inline]
fn add_group(
    sums: &mut [__m256; SETS],
    blocks: &[Block<f32>],
    ab: &[[Lanes<f32>; 2]],
    (cm, sm): (__m256, __m256),
    z: __m256,
) {
    // Σ_j w q_j per lane; the lane's cm, sm (constant in j) multiply once
    // at the end, which keeps them off the loop's critical path.
    let mut acc = [[_mm256_setzero_ps(); SETS]; 2];
    let (mut q2, mut q1) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    for (j, ([cos, sin], [a, ab])) in blocks.iter().zip(ab).enumerate() {
        if j > 0 {
            let az = _mm256_mul_ps(load(a), z);
            let q = _mm256_fmsub_ps(az, q1, _mm256_mul_ps(load(ab), q2));
            (q2, q1) = (q1, q);
        }
        let [acc_cos, acc_sin] = &mut acc;
        for (s, w) in acc_cos.iter_mut().zip(cos) {
            *s = _mm256_fmadd_ps(load(w), q1, *s);
        }
        for (s, w) in acc_sin.iter_mut().zip(sin) {
            *s = _mm256_fmadd_ps(load(w), q1, *s);
        }
    }
    let [acc_cos, acc_sin] = acc;
    for ((s, c), si) in sums.iter_mut().zip(acc_cos).zip(acc_sin) {
        *s = _mm256_fmadd_ps(c, cm, _mm256_fmadd_ps(si, sm, *s));
    }
}

/// The lane sums of six vectors, by horizontal adds.
#[target_feature(enable = "avx")]
#[inline]
fn lane_sums([a, b, c, d, e, f]: [__m256; SETS]) -> [f32; SETS] {
    let (ab, cd, ef) = (
        _mm256_hadd_ps(a, b),
        _mm256_hadd_ps(c, d),
        _mm256_hadd_ps(e, f),
    );
    // Lanes [a b c d] of the low and high halves, then [e f e f].
    let abcd = _mm256_hadd_ps(ab, cd);
    let efef = _mm256_hadd_ps(ef, ef);
    let halves = |v: __m256| _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
    let mut out = Lanes([0.0f32; LANES]);
    let (first, last) = out.0.split_at_mut(4);
    // SAFETY: each half of `out` holds four f32 (unaligned stores).
    unsafe {
        _mm_storeu_ps(first.as_mut_ptr(), halves(abcd));
        _mm_storeu_ps(last.as_mut_ptr(), halves(efef));
    }
    let [s0, s1, s2, s3, s4, s5, _, _] = out.0;
    [s0, s1, s2, s3, s4, s5]
}

/// The six sums of eqs. (7)-(8) with 8-wide AVX and FMA.
#[target_feature(enable = "avx,fma")]
#[inline]
fn accumulate_avx(degree: usize, dir: &Vector3<f32>, blocks: &[Block<f32>; BLOCKS]) -> [f32; SETS] {
    let degree = degree.min(MAX_DEGREE);
    let t = &LANES_F32;
    let [p0, p1, p2, p3] = powers(degree, dir);
    let halves = [(p0, p1), (p2, p3)];
    let z = _mm256_set1_ps(dir.z);
    let mut sums = [_mm256_setzero_ps(); SETS];
    let groups = halves.iter().zip(&t.scale);
    for (g, ((low, high), scale)) in groups.enumerate().take(degree / LANES + 1) {
        let steps = degree + 1 - LANES * g;
        let re = _mm256_set_m128(high.0, low.0);
        let im = _mm256_set_m128(high.1, low.1);
        let k = load(scale);
        let seeds = (_mm256_mul_ps(k, re), _mm256_mul_ps(k, im));
        let blocks = group_blocks(blocks, g, steps);
        add_group(&mut sums, blocks, group_ab(t, g, steps), seeds, z);
    }
    lane_sums(sums)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::indexing_slicing, clippy::unwrap_used)]
    use super::*;
    use crate::sh::{degree_order, MAX_COEFFS};

    #[test]
    fn every_coefficient_has_its_own_slot() {
        let mut seen = [[[false; LANES]; 2]; BLOCKS];
        for k in 0..MAX_COEFFS {
            let (l, m) = degree_order(k);
            let (b, p, r) = slot(l, m).unwrap();
            assert!(!seen[b][p][r], "k = {k}");
            seen[b][p][r] = true;
        }
        assert_eq!(slot(3, 4), None);
        assert_eq!(slot(MAX_DEGREE + 1, 0), None);
    }
}
