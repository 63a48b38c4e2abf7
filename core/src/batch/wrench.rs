//! Eqs. (5)-(8) for eight bodies sharing one coefficient set, one body per
//! lane: the same operations as [`Coefficients::wrench`] on the portable
//! path ([`crate::sh::accumulate`]), lane by lane.

use super::lane_ops::{both, Mask};
use super::vec::{add3, cross3, dot3, mat_vec, scale3, splat3, sub3, V3};
use crate::basis::vector_basis;
use crate::coefficients::Coefficients;
use crate::effect::EffectInputs;
use crate::lanes::{run_wide, LaneScalar, Lanes, SimdCoefficients, SimdKernel, LANES, SETS};
use crate::math::{lit, vector_is_finite, Real};
use crate::sh::walk_values;
use nalgebra::Vector3;

/// Force (N) and torque (N m) of eight bodies, body frames, one per lane.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct WrenchLanes<T> {
    /// Force, N.
    pub force: V3<T>,
    /// Torque about the centre of mass, N m.
    pub torque: V3<T>,
}

/// Lane `i` of `v` (zero beyond the lanes).
#[inline(always)]
pub fn lane<T: Real>(v: &V3<T>, i: usize) -> Vector3<T> {
    let c = |k: usize| v.get(k).and_then(|l| l.0.get(i)).copied();
    Vector3::new(c(0), c(1), c(2)).map(|x| x.unwrap_or_else(T::zero))
}

/// Sets lane `i` of `v` to `x` (ignored beyond the lanes).
#[inline(always)]
pub fn set_lane<T: Real>(v: &mut V3<T>, i: usize, x: &Vector3<T>) {
    for (c, value) in v.iter_mut().zip(x.iter()) {
        if let Some(slot) = c.0.get_mut(i) {
            *slot = *value;
        }
    }
}

impl<T: LaneScalar> Coefficients<T> {
    /// Eqs. (5)-(6) for eight bodies (one per lane) with this model and its
    /// spin coupling, as [`Self::wrench`] on the portable path computes
    /// them for each: `velocity` V (m/s) and `angular_velocity` Ω (rad/s)
    /// in each body's frame, ρ (kg/m³). Runs with AVX where the machine
    /// has it; every lane agrees bit for bit with the portable single-body
    /// path (and so, for f64, with [`Self::wrench`]).
    pub fn wrench_lanes(
        &self,
        velocity: &V3<T>,
        angular_velocity: &V3<T>,
        air_density: T,
    ) -> WrenchLanes<T> {
        self.run_lanes(velocity, angular_velocity, None, air_density)
    }

    /// [`Self::wrench_lanes`] plus the gravity coupling, as
    /// [`Self::wrench_in_gravity`]: `gravity_body` is `Rᵀg` per lane, m/s².
    pub fn wrench_in_gravity_lanes(
        &self,
        velocity: &V3<T>,
        angular_velocity: &V3<T>,
        gravity_body: &V3<T>,
        air_density: T,
    ) -> WrenchLanes<T> {
        self.run_lanes(velocity, angular_velocity, Some(gravity_body), air_density)
    }

    /// Both of the above, compiled with AVX where the machine has it.
    fn run_lanes(
        &self,
        velocity: &V3<T>,
        angular_velocity: &V3<T>,
        gravity_body: Option<&V3<T>>,
        air_density: T,
    ) -> WrenchLanes<T> {
        run_wide(&LanesKernel {
            model: self,
            velocity,
            angular_velocity,
            gravity_body,
            air_density,
        })
    }

    /// The body of [`Self::wrench_in_gravity_lanes`], inlined into the
    /// caller (the batch RK4 step).
    #[inline(always)]
    pub(crate) fn wrench_lanes_inline(
        &self,
        velocity: &V3<T>,
        angular_velocity: &V3<T>,
        gravity_body: Option<&V3<T>>,
        air_density: T,
    ) -> WrenchLanes<T> {
        let mut w = self.air_lanes(velocity, angular_velocity, air_density);
        self.add_extensions(
            &mut w,
            velocity,
            angular_velocity,
            gravity_body,
            air_density,
        );
        w
    }

    /// Eqs. (5)-(6) without extensions: `wrench_inline` of
    /// [`crate::aero`] with every branch a lane mask.
    #[inline(always)]
    fn air_lanes(&self, velocity: &V3<T>, omega: &V3<T>, air_density: T) -> WrenchLanes<T> {
        let l = self.reference_length();
        let half_rho = lit::<T>(0.5) * air_density;
        let k = Lanes::splat;
        // Second term of eq. (6): -½ρ D |Ω| Ω L⁵.
        let spin = dot3(omega, omega).root();
        let spinning = spin.above(T::zero());
        let l2 = l * l;
        let scale = k(half_rho) * spin * k(l2) * k(l2) * k(l);
        let damping = scale3(&mat_vec(&self.damping(), omega), scale);
        let speed_sq = dot3(velocity, velocity);
        let moving = both(&speed_sq.above(T::zero()), &speed_sq.finite());
        let e = scale3(velocity, k(T::one()) / speed_sq.root());
        let (cf, ct) = self.direction_lanes(&e, &moving);
        let q = k(half_rho) * speed_sq;
        let force = select(&scale3(&cf, q * k(l) * k(l)), &moving);
        let torque = select(&scale3(&ct, q * k(l) * k(l) * k(l)), &moving);
        WrenchLanes {
            force,
            torque: sub3(&torque, &select(&damping, &spinning)),
        }
    }

    /// `C_F(E)`, `C_T(E)` (eqs. 7-8) at unit directions `e`: the §4.2
    /// basis by its fast formula, lanes near the poles (`valid` ones only)
    /// by [`vector_basis`] itself, and the SH sums on the portable rows.
    #[inline(always)]
    fn direction_lanes(&self, e: &V3<T>, valid: &Mask) -> (V3<T>, V3<T>) {
        let pole = self.pole();
        let cross = cross3(e, &splat3(&pole));
        let len = dot3(&cross, &cross).root();
        let fast = len.above(lit(1.0 / 16.0));
        let e2 = scale3(&cross, Lanes::splat(T::one()) / len);
        let mut b = [*e, e2, cross3(e, &e2)];
        let near_pole = fast.iter().zip(valid).any(|(&f, &v)| v && !f);
        if near_pole {
            pole_lanes(&mut b, e, &pole, &fast, valid);
        }
        let s = sums(self.basis_degree() as usize, self.portable_rows(), e);
        let [a1, a2, a3, t1, t2, t3] = s;
        (combine(&b, [a1, a2, a3]), combine(&b, [t1, t2, t3]))
    }

    /// The extensions' forces lane by lane, each as the single-body path
    /// adds it (a non-finite term adds nothing).
    #[inline(always)]
    fn add_extensions(
        &self,
        w: &mut WrenchLanes<T>,
        velocity: &V3<T>,
        omega: &V3<T>,
        gravity_body: Option<&V3<T>>,
        air_density: T,
    ) {
        let l = self.reference_length();
        let mut add = |i: usize, f: Vector3<T>| {
            if vector_is_finite(&f) {
                let sum = lane(&w.force, i) + f;
                set_lane(&mut w.force, i, &sum);
            }
        };
        if let Some(spin) = self.spin_coupling() {
            for i in 0..LANES {
                add(
                    i,
                    spin.force(&lane(velocity, i), &lane(omega, i), air_density, l),
                );
            }
        }
        if let (Some(g), Some(gravity)) = (self.gravity_coupling(), gravity_body) {
            for i in 0..LANES {
                add(i, g.force(&lane(gravity, i), air_density, l));
            }
        }
        // The named effects, as `wrench_in_gravity` adds them (only with
        // the attitude; added mass's -M_a dV/dt is the equations' job).
        if let (false, Some(gravity)) = (self.effects().is_empty(), gravity_body) {
            for i in 0..LANES {
                let inputs = EffectInputs {
                    velocity: lane(velocity, i),
                    angular_velocity: lane(omega, i),
                    gravity: lane(gravity, i),
                    velocity_rate: Vector3::zeros(),
                    air_density,
                    reference_length: l,
                };
                for effect in self.effects() {
                    let e = effect.wrench(&inputs);
                    if vector_is_finite(&e.force) && vector_is_finite(&e.torque) {
                        let f = lane(&w.force, i) + e.force;
                        set_lane(&mut w.force, i, &f);
                        let t = lane(&w.torque, i) + e.torque;
                        set_lane(&mut w.torque, i, &t);
                    }
                }
            }
        }
    }
}

/// The basis of the valid lanes near the poles by [`vector_basis`] itself
/// (rare: kept out of line so the common path stays small).
#[cold]
#[inline(never)]
fn pole_lanes<T: Real>(
    b: &mut [V3<T>; 3],
    e: &V3<T>,
    pole: &Vector3<T>,
    fast: &Mask,
    valid: &Mask,
) {
    for (i, (&f, &v)) in fast.iter().zip(valid).enumerate() {
        if v && !f {
            let basis = vector_basis(&lane(e, i), pole);
            for (bk, x) in b.iter_mut().zip(&basis) {
                set_lane(bk, i, x);
            }
        }
    }
}

/// `v` where `m` holds, zero elsewhere.
#[inline(always)]
fn select<T: Real>(v: &V3<T>, m: &Mask) -> V3<T> {
    let zero = Lanes::splat(T::zero());
    let [x, y, z] = *v;
    [x.select(m, zero), y.select(m, zero), z.select(m, zero)]
}

/// `b1 a1 + b2 a2 + b3 a3` (eqs. 7-8 in the basis, the single-body order).
#[inline(always)]
fn combine<T: Real>([b1, b2, b3]: &[V3<T>; 3], [a1, a2, a3]: [Lanes<T>; 3]) -> V3<T> {
    add3(&add3(&scale3(b1, a1), &scale3(b2, a2)), &scale3(b3, a3))
}

/// `Σ_k rows[k] Y_k(e)` per lane: [`crate::sh::accumulate`] with lanes.
#[inline(always)]
fn sums<T: LaneScalar>(degree: usize, rows: &[[T; SETS]], e: &V3<T>) -> [Lanes<T>; SETS] {
    if let Some(s) = T::Simd::lane_sums(degree, rows, e) {
        return s;
    }
    let mut acc = [Lanes::splat(T::zero()); SETS];
    let mut rows = rows.iter();
    walk_values(degree, *e, |y: Lanes<T>| {
        if let Some(row) = rows.next() {
            for (a, &w) in acc.iter_mut().zip(row) {
                *a = *a + Lanes::splat(w) * y;
            }
        }
    });
    acc
}

/// [`Coefficients::wrench_lanes`] as a [`SimdKernel`], so that it runs
/// compiled with AVX.
struct LanesKernel<'a, T: LaneScalar> {
    model: &'a Coefficients<T>,
    velocity: &'a V3<T>,
    angular_velocity: &'a V3<T>,
    gravity_body: Option<&'a V3<T>>,
    air_density: T,
}

impl<T: LaneScalar> SimdKernel for LanesKernel<'_, T> {
    type Output = WrenchLanes<T>;
    #[inline(always)]
    fn run(&self) -> WrenchLanes<T> {
        self.model.wrench_lanes_inline(
            self.velocity,
            self.angular_velocity,
            self.gravity_body,
            self.air_density,
        )
    }
}
