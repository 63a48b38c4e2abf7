//! 3-vectors, 3x3 matrices and quaternions over [`Lanes`], one body per
//! lane. Each function repeats nalgebra's operation order for the same
//! operation on one body (noted per function), so that a lane rounds
//! exactly as the single-body code ([`crate::aero`],
//! [`crate::rigid_body`], [`crate::integrate`]) does; the tests of
//! [`super`] compare them bit for bit.

use crate::lanes::Lanes;
use crate::math::Real;
use nalgebra::{Matrix3, Quaternion, Vector3};

/// A 3-vector per lane: `[x, y, z]`.
pub type V3<T> = [Lanes<T>; 3];
/// A quaternion per lane in nalgebra's coordinate order `[i, j, k, w]`.
pub type Q4<T> = [Lanes<T>; 4];

/// `v` in every lane.
#[inline(always)]
pub fn splat3<T: Real>(v: &Vector3<T>) -> V3<T> {
    [Lanes::splat(v.x), Lanes::splat(v.y), Lanes::splat(v.z)]
}

/// `a + b`.
#[inline(always)]
pub fn add3<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    let [x, y, z] = *a;
    [x + b[0], y + b[1], z + b[2]]
}

/// `a - b`.
#[inline(always)]
pub fn sub3<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    let [x, y, z] = *a;
    [x - b[0], y - b[1], z - b[2]]
}

/// `a s` (nalgebra's vector times scalar: each component times `s`).
#[inline(always)]
pub fn scale3<T: Real>(a: &V3<T>, s: Lanes<T>) -> V3<T> {
    let [x, y, z] = *a;
    [x * s, y * s, z * s]
}

/// `a / s` (each component divided, as nalgebra does).
#[inline(always)]
pub fn div3<T: Real>(a: &V3<T>, s: Lanes<T>) -> V3<T> {
    let [x, y, z] = *a;
    [x / s, y / s, z / s]
}

/// `a · b` = `(a_x b_x + a_y b_y) + a_z b_z` (nalgebra's 3-vector dot).
#[inline(always)]
pub fn dot3<T: Real>(a: &V3<T>, b: &V3<T>) -> Lanes<T> {
    let [x, y, z] = *a;
    x * b[0] + y * b[1] + z * b[2]
}

/// `a × b` (nalgebra's component formulas).
#[inline(always)]
pub fn cross3<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    let ([ax, ay, az], [bx, by, bz]) = (*a, *b);
    [ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx]
}

/// `M v` for one matrix shared by all lanes: row `i` is
/// `(M_i0 v_0 + M_i1 v_1) + M_i2 v_2`, nalgebra's column-by-column `gemv`.
#[inline(always)]
pub fn mat_vec<T: Real>(m: &Matrix3<T>, v: &V3<T>) -> V3<T> {
    let e = |i: usize, j: usize| Lanes::splat(m.get((i, j)).copied().unwrap_or_else(T::zero));
    let [x, y, z] = *v;
    [
        e(0, 0) * x + e(0, 1) * y + e(0, 2) * z,
        e(1, 0) * x + e(1, 1) * y + e(1, 2) * z,
        e(2, 0) * x + e(2, 1) * y + e(2, 2) * z,
    ]
}

/// `q s` per component.
#[inline(always)]
pub fn scale4<T: Real>(q: &Q4<T>, s: Lanes<T>) -> Q4<T> {
    let [i, j, k, w] = *q;
    [i * s, j * s, k * s, w * s]
}

/// `q` in every lane.
#[inline(always)]
pub fn splat4<T: Real>(q: &Quaternion<T>) -> Q4<T> {
    [
        Lanes::splat(q.i),
        Lanes::splat(q.j),
        Lanes::splat(q.k),
        Lanes::splat(q.w),
    ]
}

/// The Hamilton product `a b` (nalgebra's formulas, term order included).
#[inline(always)]
pub fn quat_mul<T: Real>(a: &Q4<T>, b: &Q4<T>) -> Q4<T> {
    let ([ai, aj, ak, aw], [bi, bj, bk, bw]) = (*a, *b);
    [
        aw * bi + ai * bw + aj * bk - ak * bj,
        aw * bj - ai * bk + aj * bw + ak * bi,
        aw * bk + ai * bj - aj * bi + ak * bw,
        aw * bw - ai * bi - aj * bj - ak * bk,
    ]
}

/// `R v` for unit quaternions `q` (nalgebra's `UnitQuaternion * Vector3`:
/// `t = 2 q_v × v`, `v + w t + q_v × t`, summed as `(t w + q_v × t) + v`).
#[inline(always)]
pub fn rotate<T: Real>(q: &Q4<T>, v: &V3<T>) -> V3<T> {
    let [i, j, k, w] = *q;
    let qv = [i, j, k];
    let t = scale3(&cross3(&qv, v), Lanes::splat(T::one() + T::one()));
    let c = cross3(&qv, &t);
    add3(&add3(&scale3(&t, w), &c), v)
}

/// `Rᵀ v`: [`rotate`] by the conjugate (nalgebra's
/// `inverse_transform_vector`; negation is exact).
#[inline(always)]
pub fn rotate_back<T: Real>(q: &Q4<T>, v: &V3<T>) -> V3<T> {
    let [i, j, k, w] = *q;
    rotate(&[-i, -j, -k, w], v)
}
