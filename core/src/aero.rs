//! Aerodynamic force and torque: eqs. (5)-(8).

use crate::basis::vector_basis;
use crate::coefficients::Coefficients;
use crate::effect::EffectInputs;
use crate::lanes::{LaneScalar, SimdCoefficients, SimdKernel};
use crate::math::{lit, norm, Real};
use nalgebra::Vector3;

pub use crate::wrench::Wrench;

/// The non-dimensional coefficients `C_F(E)`, `C_T(E)` at one direction
/// (body frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCoefficients<T: Real> {
    /// Force coefficient `C_F(E)`, eq. (7).
    pub force: Vector3<T>,
    /// Torque coefficient `C_T(E)`, eq. (8).
    pub torque: Vector3<T>,
}

impl<T: LaneScalar> Coefficients<T> {
    /// `C_F(E)` and `C_T(E)`, eqs. (7)-(8), at a body-frame direction.
    ///
    /// `direction` need not be unit length; it is normalised. A zero or
    /// non-finite direction gives `None`.
    pub fn at_direction(&self, direction: &Vector3<T>) -> Option<DirectionCoefficients<T>> {
        let len = norm(direction);
        if !(len > T::zero()) || !len.finite() {
            return None;
        }
        Some(self.at_unit_direction(&(direction / len)))
    }

    /// As [`Self::at_direction`] for a unit `e` (not checked).
    pub fn at_unit_direction(&self, e: &Vector3<T>) -> DirectionCoefficients<T> {
        self.at_unit_direction_inline(e)
    }

    #[inline(always)]
    fn at_unit_direction_inline(&self, e: &Vector3<T>) -> DirectionCoefficients<T> {
        // The basis first: its square roots and divisions form a long
        // latency chain that then overlaps with the (longer) SH sums
        // instead of following them.
        let basis = vector_basis(e, &self.pole());
        let s = self.sh_sums(e);
        let [b1, b2, b3] = basis;
        let lane = |i: usize| s.get(i).copied().unwrap_or_else(T::zero);
        let [a1, a2, a3, t1, t2, t3] = [0, 1, 2, 3, 4, 5].map(lane);
        DirectionCoefficients {
            force: b1 * a1 + b2 * a2 + b3 * a3,
            torque: b1 * t1 + b2 * t2 + b3 * t3,
        }
    }

    /// Force and torque of the air on the body, eqs. (5)-(6), body frame.
    ///
    /// * `velocity`: body velocity relative to the air, body frame, m/s
    ///   (`V = Rᵀ(v - v_wind)`);
    /// * `angular_velocity`: Ω, body frame, rad/s;
    /// * `air_density`: ρ, kg/m³.
    ///
    /// `V = 0` gives no velocity term; `Ω = 0` no damping term. A model
    /// with the spin-coupling extension ([`crate::spin_coupling`]) adds its
    /// force.
    pub fn wrench(
        &self,
        velocity: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        air_density: T,
    ) -> Wrench<T> {
        let mut w = T::Simd::run(&WrenchKernel {
            model: self,
            velocity,
            angular_velocity,
            air_density,
        });
        if let Some(spin) = self.spin_coupling() {
            let f = spin.force(
                velocity,
                angular_velocity,
                air_density,
                self.reference_length(),
            );
            // Like eqs. (5)-(6) above: a non-finite input adds nothing.
            if crate::math::vector_is_finite(&f) {
                w.force += f;
            }
        }
        w
    }

    /// [`Self::wrench`] plus the gravity coupling
    /// ([`crate::gravity_coupling`]), which needs the attitude, and the
    /// named effects ([`crate::effect`], buoyancy needs the attitude too):
    /// `gravity_body` is `Rᵀg`, the gravity vector in the body frame, m/s².
    /// This is the whole air force of a model with every extension it
    /// has, but for added mass's `-M_a dV/dt`, which the equations of
    /// motion carry. Like eqs. (5)-(6), a non-finite term adds nothing.
    #[inline]
    pub fn wrench_in_gravity(
        &self,
        velocity: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        gravity_body: &Vector3<T>,
        air_density: T,
    ) -> Wrench<T> {
        let mut w = self.wrench(velocity, angular_velocity, air_density);
        if let Some(g) = self.gravity_coupling() {
            let f = g.force(gravity_body, air_density, self.reference_length());
            if crate::math::vector_is_finite(&f) {
                w.force += f;
            }
        }
        let inputs = EffectInputs {
            velocity: *velocity,
            angular_velocity: *angular_velocity,
            gravity: *gravity_body,
            // Added mass's -M_a dV/dt is carried by the equations of motion
            // (`rigid_body::state_rate_with_added_mass`), not by the force.
            velocity_rate: Vector3::zeros(),
            air_density,
            reference_length: self.reference_length(),
        };
        for effect in self.effects() {
            let e = effect.wrench(&inputs);
            if crate::math::vector_is_finite(&e.force) && crate::math::vector_is_finite(&e.torque) {
                w.force += e.force;
                w.torque += e.torque;
            }
        }
        w
    }

    /// [`Self::wrench`] without extensions, inlined into the caller.
    #[inline(always)]
    fn wrench_inline(
        &self,
        velocity: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        air_density: T,
    ) -> Wrench<T> {
        let l = self.reference_length();
        let half_rho = lit::<T>(0.5) * air_density;
        // Damping first, second term of eq. (6): -½ρ D |Ω| Ω L⁵. Its square
        // root then runs while the SH sums are computed.
        let spin = norm(angular_velocity);
        let damping = if spin > T::zero() {
            let l2 = l * l;
            self.damping() * angular_velocity * (half_rho * spin * l2 * l2 * l)
        } else {
            Vector3::zeros()
        };
        let mut out = Wrench::zero();
        let speed_sq = velocity.dot(velocity);
        if speed_sq > T::zero() && speed_sq.finite() {
            let e = velocity * (T::one() / speed_sq.root());
            let c = self.at_unit_direction_inline(&e);
            let q = half_rho * speed_sq;
            out.force = c.force * (q * l * l);
            out.torque = c.torque * (q * l * l * l);
        }
        out.torque -= damping;
        out
    }
}

/// Eqs. (5)-(6) as a [`SimdKernel`], so that [`Coefficients::wrench`] runs
/// compiled for the SIMD path's features with the SH kernel inlined.
struct WrenchKernel<'a, T: LaneScalar> {
    model: &'a Coefficients<T>,
    velocity: &'a Vector3<T>,
    angular_velocity: &'a Vector3<T>,
    air_density: T,
}

impl<T: LaneScalar> SimdKernel for WrenchKernel<'_, T> {
    type Output = Wrench<T>;
    #[inline(always)]
    fn run(&self) -> Wrench<T> {
        self.model
            .wrench_inline(self.velocity, self.angular_velocity, self.air_density)
    }
}
