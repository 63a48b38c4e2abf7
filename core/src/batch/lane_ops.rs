//! Lane-by-lane arithmetic on [`Lanes`]: each operation is the scalar one
//! applied to every lane, in the scalar's own rounding (Rust never fuses a
//! multiply and an add), so a lane computes bit for bit what the scalar
//! code computes. Compiled with AVX (see [`super::run`]) the loops become
//! one or two vector instructions each. No `[T; N]::map` and no closures
//! on these paths: what does not inline is compiled without AVX.

use crate::lanes::{Lanes, LANES};
use crate::math::Real;
use crate::sh::WalkValue;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A lane mask: which of the eight lanes a condition holds in.
pub type Mask = [bool; LANES];

impl<T: Real> Lanes<T> {
    /// `x` in every lane.
    #[inline(always)]
    pub fn splat(x: T) -> Self {
        Self([x; LANES])
    }
    /// Applies `f` lane by lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(T) -> T) -> Self {
        let mut out = self;
        for a in &mut out.0 {
            *a = f(*a);
        }
        out
    }
    /// Applies `f` to pairs of lanes.
    #[inline(always)]
    fn zip_with(self, other: Self, f: impl Fn(T, T) -> T) -> Self {
        let mut out = self;
        for (a, b) in out.0.iter_mut().zip(other.0) {
            *a = f(*a, b);
        }
        out
    }
    /// Square root per lane ([`Real::root_each`], correctly rounded).
    #[inline(always)]
    pub fn root(self) -> Self {
        Self(T::root_each(self.0))
    }
    /// Lanes where `pick` holds from `self`, the rest from `other`.
    #[inline(always)]
    pub fn select(self, pick: &Mask, other: Self) -> Self {
        let mut out = other;
        for ((o, s), &p) in out.0.iter_mut().zip(self.0).zip(pick) {
            if p {
                *o = s;
            }
        }
        out
    }
    /// Lanes holding a value above `x` (false for NaN).
    #[inline(always)]
    pub fn above(self, x: T) -> Mask {
        let mut m = [false; LANES];
        for (m, a) in m.iter_mut().zip(self.0) {
            *m = a > x;
        }
        m
    }
    /// Lanes holding a finite value.
    #[inline(always)]
    pub fn finite(self) -> Mask {
        let mut m = [false; LANES];
        for (m, a) in m.iter_mut().zip(self.0) {
            *m = a.finite();
        }
        m
    }
}

/// Lanes where both masks hold.
#[inline(always)]
pub fn both(a: &Mask, b: &Mask) -> Mask {
    let mut out = *a;
    for (o, &x) in out.iter_mut().zip(b) {
        *o = *o && x;
    }
    out
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<T: Real> $tr for Lanes<T> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, other: Self) -> Self {
                self.zip_with(other, |a, b| a $op b)
            }
        }
    };
}

lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<T: Real> Neg for Lanes<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<T: Real> WalkValue<T> for Lanes<T> {
    #[inline(always)]
    fn splat(x: T) -> Self {
        Lanes::splat(x)
    }
}
