//! The scalar type and the few vector helpers the model needs.
//!
//! The core is generic over [`Real`] (implemented for `f32` and `f64`)
//! rather than using a feature-selected alias: the firmware needs `f32`
//! (single-precision FPU) while the host fits in `f64`, and both must be
//! usable from one build (e.g. the host compares its `f32` results
//! bit-for-bit with the firmware's, and benchmarks both). Cargo features are
//! unified across a build, so an alias could not give both at once.
//!
//! This module is the bottom layer of the core: it depends on no other
//! module. What else a scalar must provide lives with its user: the SH
//! recurrence constants ([`crate::sh::ShScalar`]) and the SIMD coefficient
//! layout ([`crate::lanes::LaneScalar`]).

use nalgebra::{Matrix3, RealField, Vector3};

/// A floating-point scalar usable by the model: `f32` or `f64`.
pub trait Real: RealField + Copy + Default + core::fmt::Debug {
    /// Converts from `f64` (rounding to nearest for `f32`).
    fn of_f64(x: f64) -> Self;
    /// Widens to `f64` (exact).
    fn as_f64(self) -> f64;
    /// Square root. Kept on this trait so that targets with a hardware
    /// square root can route it there.
    fn root(self) -> Self;
    /// [`Self::root`] of every element, bit for bit (square roots are
    /// correctly rounded everywhere). On x86_64 four f32 or two f64 per
    /// SSE `sqrtps`/`sqrtpd` (baseline there): libm's square root is
    /// inline assembly, which the compiler cannot vectorise, and the batch
    /// path ([`crate::batch`]) takes three roots of eight bodies per
    /// evaluation.
    fn root_each<const N: usize>(x: [Self; N]) -> [Self; N];
    /// True when the value is neither NaN nor infinite.
    fn finite(self) -> bool;
}

impl Real for f32 {
    #[inline(always)]
    fn of_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn root(self) -> Self {
        // Hard-float Arm (e.g. Cortex-M4F): the FPU's `vsqrt.f32` (14
        // cycles) instead of libm's software loop; both are correctly
        // rounded, so results are bit-identical. Stable Rust cannot name
        // VFP registers in `asm!` (the `vfp2` feature is unstable), so the
        // value goes through a core register and s0 is saved and restored.
        #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
        {
            let mut bits = self.to_bits();
            // SAFETY: register-only FPU instructions, present on every
            // hard-float Arm target; s0 is restored before the block ends.
            unsafe {
                core::arch::asm!(
                    "vmov {saved}, s0",
                    "vmov s0, {x}",
                    "vsqrt.f32 s0, s0",
                    "vmov {x}, s0",
                    "vmov s0, {saved}",
                    x = inout(reg) bits,
                    saved = out(reg) _,
                    options(pure, nomem, nostack),
                );
            }
            f32::from_bits(bits)
        }
        #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
        {
            libm::sqrtf(self)
        }
    }
    #[inline(always)]
    fn root_each<const N: usize>(mut x: [Self; N]) -> [Self; N] {
        #[cfg(target_arch = "x86_64")]
        {
            use core::arch::x86_64::{_mm_loadu_ps, _mm_sqrt_ps, _mm_storeu_ps};
            let mut fours = x.chunks_exact_mut(4);
            for c in &mut fours {
                // SAFETY: `c` holds four f32 (unaligned load and store);
                // SSE is part of the x86_64 baseline.
                unsafe { _mm_storeu_ps(c.as_mut_ptr(), _mm_sqrt_ps(_mm_loadu_ps(c.as_ptr()))) };
            }
            for r in fours.into_remainder() {
                *r = r.root();
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for r in &mut x {
            *r = r.root();
        }
        x
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
}

impl Real for f64 {
    #[inline(always)]
    fn of_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn root(self) -> Self {
        libm::sqrt(self)
    }
    #[inline(always)]
    fn root_each<const N: usize>(mut x: [Self; N]) -> [Self; N] {
        #[cfg(target_arch = "x86_64")]
        {
            use core::arch::x86_64::{_mm_loadu_pd, _mm_sqrt_pd, _mm_storeu_pd};
            let mut pairs = x.chunks_exact_mut(2);
            for c in &mut pairs {
                // SAFETY: `c` holds two f64 (unaligned load and store);
                // SSE2 is part of the x86_64 baseline.
                unsafe { _mm_storeu_pd(c.as_mut_ptr(), _mm_sqrt_pd(_mm_loadu_pd(c.as_ptr()))) };
            }
            for r in pairs.into_remainder() {
                *r = r.root();
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for r in &mut x {
            *r = r.root();
        }
        x
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
}

/// Shorthand for a literal converted to `T`.
#[inline(always)]
pub fn lit<T: Real>(x: f64) -> T {
    T::of_f64(x)
}

/// True when every component is finite.
pub fn vector_is_finite<T: Real>(v: &Vector3<T>) -> bool {
    v.iter().all(|x| x.finite())
}

/// Euclidean norm through [`Real::root`].
#[inline(always)]
pub fn norm<T: Real>(v: &Vector3<T>) -> T {
    v.dot(v).root()
}

/// `v` over its length, or `None` when it is zero or not finite. Scaled by
/// its largest component first only when its plain length is not a normal
/// number above 1e-15 (the squares of 1e200s overflow, and `v / inf` is
/// the zero vector; those of 1e-162s are subnormal, imprecise, or zero;
/// f32 squares stay normal above 1e-15), so that an ordinary vector, a
/// stored unit pole above all, comes back bit for bit.
pub fn unit_vector<T: Real>(v: &Vector3<T>) -> Option<Vector3<T>> {
    if !vector_is_finite(v) {
        return None;
    }
    let mut v = *v;
    let mut len = norm(&v);
    if !(len.finite() && len > T::of_f64(1e-15)) {
        let largest = v.iter().fold(T::zero(), |m, &c| m.max(c.abs()));
        if largest <= T::zero() {
            return None;
        }
        v /= largest;
        len = norm(&v);
    }
    (len > T::zero()).then(|| v / len)
}

/// The packing of a symmetric 3x3 matrix into six numbers: `[xx, yy, zz,
/// xy, xz, yz]`. Every symmetric tensor of the model uses it (the damping
/// tensor D, inertia tensors in files and [`crate::coefficients::MassProperties`],
/// the unknowns of the damping fits), so it is written here once.
///
/// A symmetric 3x3 matrix from its six entries.
pub fn symmetric_from_six<T: Real>(s: [T; 6]) -> Matrix3<T> {
    let [xx, yy, zz, xy, xz, yz] = s;
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

/// The six entries (see [`symmetric_from_six`]) of the symmetric part of
/// `m`.
pub fn six_from_symmetric<T: Real>(m: &Matrix3<T>) -> [T; 6] {
    let h = lit::<T>(0.5);
    [
        m.m11,
        m.m22,
        m.m33,
        (m.m12 + m.m21) * h,
        (m.m13 + m.m31) * h,
        (m.m23 + m.m32) * h,
    ]
}

/// The rows of the 3x6 matrix `M(w)` with `S w = M(w) s` for the symmetric
/// matrix `S` of six entries `s` (see [`symmetric_from_six`]): how a
/// least-squares fit of a symmetric tensor (e.g. D of eq. 6 from torques
/// `-½ρ D |Ω| Ω L⁵`) sees its unknowns.
pub fn symmetric_times_vector_rows<T: Real>(w: &Vector3<T>) -> [[T; 6]; 3] {
    let o = T::zero();
    [
        [w.x, o, o, w.y, w.z, o],
        [o, w.y, o, w.x, o, w.z],
        [o, o, w.z, o, w.x, w.y],
    ]
}

/// The positive semi-definite matrix nearest (Frobenius) to the symmetric
/// `m`: negative eigenvalues clipped to zero.
pub fn nearest_psd(m: &Matrix3<f64>) -> Matrix3<f64> {
    let eig = m.symmetric_eigen();
    let clipped = eig.eigenvalues.map(|x| x.max(0.0));
    eig.eigenvectors * Matrix3::from_diagonal(&clipped) * eig.eigenvectors.transpose()
}

/// Whether a symmetric matrix given by six entries is positive
/// semi-definite, by Sylvester-style checks on all principal minors
/// (with a tolerance relative to the largest entry).
pub fn is_positive_semidefinite(s: [f64; 6]) -> bool {
    let [xx, yy, zz, xy, xz, yz] = s;
    let scale = s
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()))
        .max(f64::MIN_POSITIVE);
    let tol = 1e-9 * scale;
    let tol2 = tol * scale;
    let tol3 = tol2 * scale;
    let minors1 = [xx, yy, zz];
    let minors2 = [xx * yy - xy * xy, xx * zz - xz * xz, yy * zz - yz * yz];
    let det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    minors1.iter().all(|&m| m >= -tol) && minors2.iter().all(|&m| m >= -tol2) && det >= -tol3
}
