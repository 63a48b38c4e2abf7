//! The SIMD path of the weighted sums of eqs. (7)-(8), `Σ_k w_k Y_k(E)`
//! for the six sets (`alpha^1..3`, `beta^1..3`): the orders of the
//! spherical-harmonic recurrence in SIMD lanes.
//!
//! Why: the recurrence ([`crate::sh`]) is a serial chain in the degree `l`
//! for each order `m`, while different orders are independent. With AVX,
//! eight orders run in the eight lanes of one register, all advancing in
//! the step `j = l - m` ([`x86`]), and the coefficients are stored in the
//! same lane layout ([`SimdCoefficients`], kept beside the scalar path's
//! rows by [`crate::Coefficients`]).
//!
//! The scalar path ([`crate::sh::accumulate`]) stays the *portable
//! reference*: it is what the firmware runs, and host and firmware agree
//! on it bit for bit. The SIMD path may round differently (it uses fused
//! multiply-adds and another summation order); tests hold it to the scalar
//! path within single-precision rounding.
//!
//! The lane arithmetic:
//! 1. seeds per order: `w_m = (x + i y)^m` as `w_0 = 1`, `w_1 = (x, y)`,
//!    `w_m = w_{m-1} w_1` for `m = 2, 3`, `u = w_3 w_1` and
//!    `w_m = w_{m-4} u` for `m >= 4` (four orders advance per 4-wide
//!    complex product); then `cm = K_m Re w_m`, `sm = K_m Im w_m` with the
//!    constants `K_0 = Y_00`, `K_m = √2 q_m^m` (the sectoral `q_m^m` do not
//!    depend on the direction, so they are tabulated);
//! 2. `q_0 = 1`, `q_j = (a_j z) q_{j-1} - ab_j q_{j-2}` with `q_{-1} = 0`
//!    and tabulated `ab_j = a_j b_j` (`ab_1 = 0`): the product `a_j z` is
//!    off the serial chain, which bounds the latency. The harmonics are
//!    `Y_{m+j, m} = q_j cm` and `Y_{m+j, -m} = q_j sm`;
//! 3. per order `S_c += w_cos,c Y_{m+j,m} + w_sin,c Y_{m+j,-m}`, and the
//!    result `Σ_m S_m`.
//!
//! Lanes beyond the degree (and the sine part of order 0) have zero
//! coefficients, so they add nothing.

use crate::math::Real;
use crate::sh::{ShScalar, MAX_DEGREE, TABLES};
use nalgebra::Vector3;

#[cfg(target_arch = "x86_64")]
pub mod x86;

/// Number of interleaved coefficient sets: `alpha^1..3`, `beta^1..3`
/// (eqs. 7-8), the width of one row of coefficient storage.
pub const SETS: usize = 6;
/// Orders per SIMD group.
pub const LANES: usize = 8;
/// Groups of orders: `m = 0..=MAX_DEGREE` in eights.
pub const GROUPS: usize = (MAX_DEGREE + LANES) / LANES;
/// Order slots, including the padding of the last group.
pub const ORDERS: usize = GROUPS * LANES;
/// Steps in all groups (group `g` has `MAX_DEGREE + 1 - 8g`).
pub const BLOCKS: usize = group_start(GROUPS);

/// Eight lanes, aligned for 256-bit SIMD loads.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C, align(32))]
pub struct Lanes<T>(pub [T; LANES]);

/// First step of group `g`: `Σ_{h<g} (MAX_DEGREE + 1 - 8h)`.
pub const fn group_start(g: usize) -> usize {
    g * (MAX_DEGREE + 1) - LANES * g * g.saturating_sub(1) / 2
}

/// A scalar a coefficient model is stored in: the SH recurrence's scalar
/// plus the coefficient layout of its SIMD path, if it has one (f32 on
/// x86_64: [`x86::LaneBlocks`]; `()` otherwise).
pub trait LaneScalar: ShScalar {
    /// Coefficient storage of this type's SIMD path.
    type Simd: SimdCoefficients<Self>;
}

impl LaneScalar for f32 {
    #[cfg(target_arch = "x86_64")]
    type Simd = x86::LaneBlocks;
    #[cfg(not(target_arch = "x86_64"))]
    type Simd = ();
}

impl LaneScalar for f64 {
    type Simd = ();
}

/// Code to run compiled for this machine's SIMD features where it has them
/// ([`SimdCoefficients::run`]): eqs. (5)-(6) around the SIMD kernel, so
/// that the kernel inlines into the code around it (normalisation, basis,
/// damping) and the processor overlaps them. Implementations mark `run`
/// `#[inline(always)]`.
pub trait SimdKernel {
    /// What the code computes.
    type Output;
    /// Runs it.
    fn run(&self) -> Self::Output;
}

/// Runs `kernel` compiled for this machine's vector features (AVX and FMA,
/// detected at run time on x86_64) whatever its scalar type; elsewhere, or
/// without them, as it is. Rust never fuses a multiply and an add on its
/// own, so the result is the same either way.
#[inline(always)]
pub fn run_wide<K: SimdKernel>(kernel: &K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        x86::run_wide(kernel)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        kernel.run()
    }
}

/// Coefficient storage for a SIMD path, kept beside the rows of the
/// scalar path by [`crate::Coefficients`] (`()` where there is none).
pub trait SimdCoefficients<T>: Clone + core::fmt::Debug + PartialEq {
    /// All zero.
    fn zeroed() -> Self;
    /// Sets the coefficient of `Y_lm` in set `set` (ignored when out of
    /// range).
    fn set(&mut self, l: usize, m: isize, set: usize, value: T);
    /// The six sums by the SIMD path, if this machine has one.
    fn accumulate(&self, degree: usize, dir: &Vector3<T>) -> Option<[T; SETS]>;
    /// The batch's weighted sums ([`crate::batch`]): `Σ_k rows[k] Y_k(e)`
    /// per lane (rows in walk order, one unit direction per lane), lane by
    /// lane bit for bit as the portable walk ([`crate::sh::accumulate`])
    /// computes them, on this path's vector registers; `None` where it has
    /// none (the batch's generic lanes then run).
    #[inline(always)]
    fn lane_sums(
        _degree: usize,
        _rows: &[[T; SETS]],
        _e: &[Lanes<T>; 3],
    ) -> Option<[Lanes<T>; SETS]> {
        None
    }
    /// Runs `kernel` compiled for this path's SIMD features when the
    /// machine has them. Rust never fuses a multiply and an add on its own,
    /// so code outside the SIMD kernel rounds exactly as elsewhere.
    #[inline(always)]
    fn run<K: SimdKernel>(kernel: &K) -> K::Output {
        kernel.run()
    }
}

impl<T> SimdCoefficients<T> for () {
    fn zeroed() -> Self {}
    fn set(&mut self, _: usize, _: isize, _: usize, _: T) {}
    #[inline(always)]
    fn accumulate(&self, _: usize, _: &Vector3<T>) -> Option<[T; SETS]> {
        None
    }
}

/// The recurrence constants in lane layout, in the scalar type itself (an
/// f64 -> f32 conversion is a software call on the Cortex-M4F).
#[derive(Debug)]
pub struct LaneTables<T> {
    /// `[a, ab]` per step: step 1 `(√(2m+3), 0)`, step `j >= 2`
    /// `(a_lm, a_lm b_lm)` with `l = m + j`; zero where `l` or `m` exceeds
    /// [`MAX_DEGREE`] (so padded lanes stay zero and finite).
    ab: [[Lanes<T>; 2]; BLOCKS],
    /// `K_m`: `Y_00` for `m = 0`, `√2 q_m^m` above, zero beyond
    /// [`MAX_DEGREE`].
    scale: [Lanes<T>; GROUPS],
}

// Indexing in a const initialiser cannot panic at run time: an out-of-range
// index would be a compile error.
#[allow(clippy::indexing_slicing)]
const LANE_AB: [[[f64; LANES]; 2]; BLOCKS] = {
    let mut t = [[[0.0; LANES]; 2]; BLOCKS];
    let mut m = 0;
    while m <= MAX_DEGREE {
        let start = group_start(m / LANES);
        let lane = m % LANES;
        let mut l = m + 1;
        while l <= MAX_DEGREE {
            let j = l - m;
            let (a, ab) = if j == 1 {
                (TABLES.sub[m], 0.0)
            } else {
                let i = l * l + l + m;
                (TABLES.a[i], TABLES.a[i] * TABLES.b[i])
            };
            t[start + j][0][lane] = a;
            t[start + j][1][lane] = ab;
            l += 1;
        }
        m += 1;
    }
    t
};

/// `Y_00 = 1 / √(4π)`.
const Y00: f64 = 0.282_094_791_773_878_14;

/// `K_m` of step 1.
#[allow(clippy::indexing_slicing)]
const LANE_SCALE: [f64; ORDERS] = {
    let mut k = [0.0; ORDERS];
    let mut q = Y00;
    k[0] = Y00;
    let mut m = 1;
    while m <= MAX_DEGREE {
        q *= TABLES.diag[m];
        k[m] = core::f64::consts::SQRT_2 * q;
        m += 1;
    }
    k
};

/// [`LANE_AB`] and [`LANE_SCALE`] rounded once, at compile time, to f32
/// (the SIMD path's type).
#[allow(clippy::indexing_slicing)]
pub static LANES_F32: LaneTables<f32> = {
    let mut t = LaneTables {
        ab: [[Lanes([0.0; LANES]); 2]; BLOCKS],
        scale: [Lanes([0.0; LANES]); GROUPS],
    };
    let mut i = 0;
    while i < BLOCKS {
        let mut p = 0;
        while p < 2 {
            let mut k = 0;
            while k < LANES {
                t.ab[i][p].0[k] = LANE_AB[i][p][k] as f32;
                k += 1;
            }
            p += 1;
        }
        i += 1;
    }
    let mut m = 0;
    while m < ORDERS {
        t.scale[m / LANES].0[m % LANES] = LANE_SCALE[m] as f32;
        m += 1;
    }
    t
};

/// `a b` for complex numbers `(re, im)`, in the canonical operation order.
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn complex_mul<T: Real>(a: (T, T), b: (T, T)) -> (T, T) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// `w_1, w_2, w_3` and `u` of step 1.
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn first_powers<T: Real>(dir: &Vector3<T>) -> [(T, T); 4] {
    let w1 = (dir.x, dir.y);
    let w2 = complex_mul(w1, w1);
    let w3 = complex_mul(w2, w1);
    [w1, w2, w3, complex_mul(w3, w1)]
}

/// The `[a, ab]` constants of group `g`'s steps `0..steps`.
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn group_ab<T>(t: &LaneTables<T>, g: usize, steps: usize) -> &[[Lanes<T>; 2]] {
    let start = group_start(g);
    t.ab.get(start..start + steps).unwrap_or(&[])
}

// Every order has a lane and every step a block.
const _: () = assert!(ORDERS > MAX_DEGREE && group_start(GROUPS) == BLOCKS);
