//! Named physical effects outside the paper's eqs. (5)-(6), each with few
//! parameters, its source, units and frames — the library the residual
//! analysis (`omniad residual`) chooses from and the model files store.
//!
//! Every effect here is linear in its parameters, so the fit's regressor
//! columns are the effect evaluated at unit parameters ([`Effect::unit`]),
//! and the physics has this one owner: synthesis, simulation, the fit and
//! the firmware all call [`Effect::wrench`].
//!
//! Inputs are body-frame quantities ([`EffectInputs`]); forces and torques
//! come out in the body frame, N and N m, about the centre of mass.

mod kinds;
mod storage;

pub use kinds::{EffectKind, MAX_PARAMS};
pub use storage::PAYLOAD_VERSION;

use crate::math::{symmetric_from_six, Real};
use crate::wrench::Wrench;
use nalgebra::{Matrix3, Vector3};

/// Dynamic viscosity of air used by [`EffectKind::LinearDrag`], kg/(m s)
/// (the paper's §3 value).
pub const AIR_VISCOSITY: f64 = 1.8e-5;

/// What an effect's force and torque depend on, body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectInputs<T: Real> {
    /// Velocity relative to the air `V = Rᵀ(v - w)`, m/s.
    pub velocity: Vector3<T>,
    /// Angular velocity Ω, rad/s.
    pub angular_velocity: Vector3<T>,
    /// Gravity seen from the body `Rᵀg`, m/s².
    pub gravity: Vector3<T>,
    /// Rate of change of `V` as seen in the body frame, `dV/dt` (the
    /// components' derivative), m/s². Only added mass uses it.
    pub velocity_rate: Vector3<T>,
    /// Air density ρ, kg/m³.
    pub air_density: T,
    /// Reference length L, m.
    pub reference_length: T,
}

/// One named effect with its parameters (`kind.param_count()` of them,
/// in the order its documentation gives).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effect<T: Real> {
    /// Which effect.
    pub kind: EffectKind,
    /// Its parameters; entries past `kind.param_count()` are zero.
    pub params: [T; MAX_PARAMS],
}

impl<T: Real> Effect<T> {
    /// The effect with parameters `params` (extra entries are an error,
    /// missing ones zero).
    pub fn new(kind: EffectKind, params: &[T]) -> Option<Self> {
        if params.len() > kind.param_count() || params.iter().any(|p| !p.finite()) {
            return None;
        }
        let mut p = [T::zero(); MAX_PARAMS];
        for (slot, v) in p.iter_mut().zip(params) {
            *slot = *v;
        }
        Some(Self { kind, params: p })
    }

    /// The effect with parameter `j` one and the others zero: the fit's
    /// regressor column `j` (every effect is linear in its parameters).
    pub fn unit(kind: EffectKind, j: usize) -> Self {
        let mut params = [T::zero(); MAX_PARAMS];
        if let Some(p) = params.get_mut(j) {
            *p = T::one();
        }
        Self { kind, params }
    }

    /// The parameters that count: the first `kind.param_count()`.
    pub fn used_params(&self) -> &[T] {
        self.params
            .get(..self.kind.param_count())
            .unwrap_or(&self.params)
    }

    fn p(&self, j: usize) -> T {
        self.params.get(j).copied().unwrap_or_else(T::zero)
    }

    /// The symmetric 3x3 of parameters 0..6 (`[xx, yy, zz, xy, xz, yz]`).
    fn symmetric(&self) -> Matrix3<T> {
        symmetric_from_six([
            self.p(0),
            self.p(1),
            self.p(2),
            self.p(3),
            self.p(4),
            self.p(5),
        ])
    }

    /// The force and torque of the effect, body frame (see [`EffectKind`]
    /// for each formula and its source).
    pub fn wrench(&self, x: &EffectInputs<T>) -> Wrench<T> {
        let (v, w, rho, l) = (
            x.velocity,
            x.angular_velocity,
            x.air_density,
            x.reference_length,
        );
        let half = T::of_f64(0.5);
        let force_only = |force: Vector3<T>| Wrench {
            force,
            torque: Vector3::zeros(),
        };
        match self.kind {
            EffectKind::Buoyancy => force_only(x.gravity * (-rho * self.p(0))),
            EffectKind::RotationalLift => force_only(w.cross(&v) * (rho * l * l * l * self.p(0))),
            EffectKind::LinearDrag => force_only(v * (-self.p(0) * T::of_f64(AIR_VISCOSITY) * l)),
            EffectKind::PropellerThrust => {
                let k = Matrix3::new(
                    self.p(0),
                    self.p(1),
                    self.p(2),
                    self.p(3),
                    self.p(4),
                    self.p(5),
                    self.p(6),
                    self.p(7),
                    self.p(8),
                );
                let l4 = l * l * l * l;
                force_only(k * w * (half * rho * l4 * w.norm()))
            }
            EffectKind::AddedMass | EffectKind::AddedMassCoupling => {
                let m = self.symmetric();
                let p = m * v;
                let coupling = -w.cross(&p);
                Wrench {
                    force: match self.kind {
                        EffectKind::AddedMass => coupling - m * x.velocity_rate,
                        _ => coupling,
                    },
                    torque: -v.cross(&p),
                }
            }
        }
    }

    /// The added-mass tensor M_a (kg, body frame) when this is
    /// [`EffectKind::AddedMass`]: it enters the equations of motion
    /// (`(M I + M_a) dV/dt = ...`), not only the force.
    pub fn added_mass(&self) -> Option<Matrix3<T>> {
        (self.kind == EffectKind::AddedMass).then(|| self.symmetric())
    }
}

#[cfg(test)]
mod tests;
