//! Rigid-body state and equations of motion, eqs. (1)-(2).

use crate::coefficients::{Coefficients, MassProperties, ModelError};
use crate::lanes::LaneScalar;
use crate::math::{symmetric_from_six, vector_is_finite, Real};
use crate::wrench::Wrench;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Mass properties in the model's scalar type, with the inverse inertia
/// precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody<T: Real> {
    /// Mass M, kg.
    pub mass: T,
    /// Inertia tensor I about the centre of mass, body frame, kg m².
    pub inertia: Matrix3<T>,
    /// I⁻¹, 1/(kg m²).
    pub inverse_inertia: Matrix3<T>,
}

impl<T: Real> RigidBody<T> {
    /// A body of mass `mass` (kg, > 0) and inertia `inertia` (kg m², body
    /// frame, symmetric positive definite).
    pub fn new(mass: T, inertia: Matrix3<T>) -> Result<Self, ModelError> {
        if !mass.finite() || inertia.iter().any(|x| !x.finite()) {
            return Err(ModelError::NonFinite("body"));
        }
        if mass <= T::zero() {
            return Err(ModelError::BadBody);
        }
        let sym = (inertia + inertia.transpose()) * T::of_f64(0.5);
        // Positive definite: Cholesky succeeds.
        if sym.cholesky().is_none() {
            return Err(ModelError::BadBody);
        }
        let inverse_inertia = sym.try_inverse().ok_or(ModelError::BadBody)?;
        Ok(Self {
            mass,
            inertia: sym,
            inverse_inertia,
        })
    }

    /// From stored mass properties.
    pub fn from_properties(p: &MassProperties) -> Result<Self, ModelError> {
        Self::new(
            T::of_f64(p.mass),
            symmetric_from_six(p.inertia.map(T::of_f64)),
        )
    }
}

/// The world the body moves in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment<T: Real> {
    /// Gravity g, world frame, m/s² (z up: `[0, 0, -9.81]`).
    pub gravity: Vector3<T>,
    /// Air density ρ, kg/m³.
    pub air_density: T,
    /// Uniform wind velocity, world frame, m/s.
    pub wind: Vector3<T>,
}

impl<T: Real> Environment<T> {
    /// Standard air (ρ = 1.2 kg/m³, the paper's), g = 9.81 m/s² down, no wind.
    pub fn standard() -> Self {
        Self {
            gravity: Vector3::new(T::zero(), T::zero(), T::of_f64(-9.81)),
            air_density: T::of_f64(1.2),
            wind: Vector3::zeros(),
        }
    }
    /// No air: gravity only.
    pub fn vacuum() -> Self {
        Self {
            air_density: T::zero(),
            ..Self::standard()
        }
    }
}

/// Rigid-body state `s = (y, q, v, Ω)` (§4.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<T: Real> {
    /// Centre of mass y, world frame, m.
    pub position: Vector3<T>,
    /// Orientation, body -> world (`x = y + R X`).
    pub orientation: UnitQuaternion<T>,
    /// Velocity of the centre of mass v, world frame, m/s.
    pub velocity: Vector3<T>,
    /// Angular velocity Ω, body frame, rad/s.
    pub angular_velocity: Vector3<T>,
}

impl<T: Real> State<T> {
    /// At rest at `position` with identity orientation.
    pub fn at_rest(position: Vector3<T>) -> Self {
        Self {
            position,
            orientation: UnitQuaternion::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
        }
    }

    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        vector_is_finite(&self.position)
            && self.orientation.coords.iter().all(|x| x.finite())
            && vector_is_finite(&self.velocity)
            && vector_is_finite(&self.angular_velocity)
    }

    /// Velocity relative to the air in the body frame, `V = Rᵀ(v - v_wind)`.
    pub fn air_velocity_body(&self, wind: &Vector3<T>) -> Vector3<T> {
        self.orientation
            .inverse_transform_vector(&(self.velocity - wind))
    }

    /// Kinetic energy, J.
    pub fn kinetic_energy(&self, body: &RigidBody<T>) -> T {
        let h = T::of_f64(0.5);
        h * body.mass * self.velocity.dot(&self.velocity)
            + h * self
                .angular_velocity
                .dot(&(body.inertia * self.angular_velocity))
    }

    /// Angular momentum about the centre of mass, world frame, kg m²/s.
    pub fn angular_momentum_world(&self, body: &RigidBody<T>) -> Vector3<T> {
        self.orientation
            .transform_vector(&(body.inertia * self.angular_velocity))
    }
}

/// Time derivative of a [`State`]; the quaternion part is the derivative of
/// its raw coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateRate<T: Real> {
    /// ẏ = v, m/s.
    pub position: Vector3<T>,
    /// q̇ = ½ q ⊗ (0, Ω).
    pub orientation: Quaternion<T>,
    /// v̇, m/s², eq. (1).
    pub velocity: Vector3<T>,
    /// Ω̇, rad/s², eq. (2).
    pub angular_velocity: Vector3<T>,
}

/// Anything that puts a force and torque on the body (body frame): the
/// OmniAD air model, a kite string, a test's analytic field, ...
pub trait Forces<T: Real> {
    /// The wrench on the body at time `t` (s) in state `state`, body frame.
    fn wrench(&self, t: T, state: &State<T>) -> Wrench<T>;

    /// The air's added-mass tensor M_a (kg, body frame), if these forces
    /// have one: it joins the body's mass in the equations of motion
    /// ([`state_rate_with_added_mass`]).
    fn added_mass(&self) -> Option<Matrix3<T>> {
        None
    }
}

/// No force at all (vacuum).
#[derive(Clone, Copy, Debug, Default)]
pub struct NoForces;

impl<T: Real> Forces<T> for NoForces {
    fn wrench(&self, _t: T, _state: &State<T>) -> Wrench<T> {
        Wrench::zero()
    }
}

/// The OmniAD air model (eqs. 5-6) in an environment.
#[derive(Clone, Copy, Debug)]
pub struct AirForces<'a, T: LaneScalar> {
    /// The coefficients.
    pub model: &'a Coefficients<T>,
    /// ρ and wind are read from here.
    pub environment: Environment<T>,
}

impl<T: LaneScalar> Forces<T> for AirForces<'_, T> {
    /// Eqs. (5)-(6) and the model's extensions, including the gravity
    /// coupling, which needs the attitude.
    fn wrench(&self, _t: T, state: &State<T>) -> Wrench<T> {
        let v = state.air_velocity_body(&self.environment.wind);
        let gravity_body = state
            .orientation
            .inverse_transform_vector(&self.environment.gravity);
        self.model.wrench_in_gravity(
            &v,
            &state.angular_velocity,
            &gravity_body,
            self.environment.air_density,
        )
    }

    fn added_mass(&self) -> Option<Matrix3<T>> {
        self.model
            .effect(crate::effect::EffectKind::AddedMass)
            .and_then(|e| e.added_mass())
    }
}

/// Eqs. (1)-(2): `M v̇ = M g + R F`, `I Ω̇ = -Ω × I Ω + T`.
pub fn state_rate<T: Real>(
    body: &RigidBody<T>,
    gravity: &Vector3<T>,
    state: &State<T>,
    wrench: &Wrench<T>,
) -> StateRate<T> {
    let q = state.orientation.quaternion();
    let omega = state.angular_velocity;
    let omega_q = Quaternion::from_parts(T::zero(), omega);
    let accel = gravity + state.orientation.transform_vector(&wrench.force) / body.mass;
    let i_omega = body.inertia * omega;
    let alpha = body.inverse_inertia * (wrench.torque - omega.cross(&i_omega));
    StateRate {
        position: state.velocity,
        orientation: (q * omega_q) * T::of_f64(0.5),
        velocity: accel,
        angular_velocity: alpha,
    }
}

/// Eqs. (1)-(2) with the air's added mass M_a (Kirchhoff; Lamb,
/// *Hydrodynamics* §126) in a steady wind `wind` (world, m/s). With
/// `U = Rᵀ(v - w)` the body-frame air velocity, the linear momentum
/// balance in the body frame is
/// `(M I + M_a) dU/dt = M Rᵀg + F - M Ω × U`,
/// where `F` (body frame) already holds the effect's `-Ω × (M_a U)` and
/// Munk moment ([`crate::effect::Effect::wrench`]); then
/// `v̇ = R (dU/dt + Ω × U)`. Rotational added inertia is not modelled.
/// A singular `M I + M_a` (impossible for PSD M_a) falls back to eq. (1).
pub fn state_rate_with_added_mass<T: Real>(
    body: &RigidBody<T>,
    environment: &Environment<T>,
    state: &State<T>,
    wrench: &Wrench<T>,
    added_mass: &Matrix3<T>,
) -> StateRate<T> {
    let mut rate = state_rate(body, &environment.gravity, state, wrench);
    let u = state.air_velocity_body(&environment.wind);
    let omega = state.angular_velocity;
    let g_body = state
        .orientation
        .inverse_transform_vector(&environment.gravity);
    let total = Matrix3::identity() * body.mass + added_mass;
    let rhs = g_body * body.mass + wrench.force - omega.cross(&u) * body.mass;
    if let Some(inv) = total.try_inverse() {
        let du = inv * rhs;
        rate.velocity = state.orientation.transform_vector(&(du + omega.cross(&u)));
    }
    rate
}
