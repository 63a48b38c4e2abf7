//! Force and torque on a kite, eqs. (14)-(15), linear equilibrium, and the
//! optimal string attachment line, eq. (16).

use super::{Conditions, Kite, KiteError, Primitive};
use crate::lanes::LaneScalar;
use crate::math::{norm, vector_is_finite, Real};
use crate::wrench::Wrench;
use nalgebra::{UnitQuaternion, Vector3};

/// The air's wrench on the whole kite about its centre of mass, body frame:
/// `F = Σ Q_p F_p`, `T_air = Σ Q_p T_p + Y_p × (Q_p F_p)` (eqs. 14-15).
///
/// * `velocity`: the kite's velocity relative to the air at its centre of
///   mass, body frame, m/s (`V = Rᵀ(v - v_wind)`);
/// * `angular_velocity`: Ω, body frame, rad/s. Primitive `p` then moves
///   through the air at `V_p = Q_pᵀ (V + Ω × Y_p)` and spins at
///   `Ω_p = Q_pᵀ Ω` (its damping term of eq. 6 included);
/// * `air_density`: ρ, kg/m³.
pub fn air_wrench<T: LaneScalar>(
    primitives: &[Primitive<'_, T>],
    velocity: &Vector3<T>,
    angular_velocity: &Vector3<T>,
    air_density: T,
) -> Wrench<T> {
    let mut out = Wrench::zero();
    for p in primitives {
        let q_t = p.rotation.transpose();
        let v_p = q_t * (velocity + angular_velocity.cross(&p.offset));
        let w = p
            .coefficients
            .wrench(&v_p, &(q_t * angular_velocity), air_density);
        let force = p.rotation * w.force;
        out.force += force;
        out.torque += p.rotation * w.torque + p.offset.cross(&force);
    }
    out
}

/// The static balance of a kite at orientation R (§7: `v = 0`, `Ω = 0`,
/// `f_kite = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equilibrium<T: Real> {
    /// The air's wrench, body frame (force N, `T_air` N m).
    pub air: Wrench<T>,
    /// String tension `f_string = -(M g + R Σ Q_p F_p)`, world frame, N
    /// (the force the string exerts on the kite; eq. 14 with `f_kite = 0`).
    pub string_world: Vector3<T>,
    /// `F_string = Rᵀ f_string`, body frame, N.
    pub string_body: Vector3<T>,
    /// `f_string · g > 0`: the string pulls the kite downward, as it must
    /// for the kite to fly.
    pub pulls_down: bool,
}

/// Linear equilibrium at orientation `orientation` (R, body -> world): the
/// kite at rest in the wind, eq. (14) solved for `f_string`.
pub fn equilibrium<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    orientation: &UnitQuaternion<T>,
) -> Result<Equilibrium<T>, KiteError> {
    if kite.primitives.is_empty() {
        return Err(KiteError::NoPrimitives);
    }
    let velocity = orientation.inverse_transform_vector(&(-conditions.wind));
    let air = air_wrench(
        kite.primitives,
        &velocity,
        &Vector3::zeros(),
        conditions.air_density,
    );
    let string_world = -(conditions.gravity * kite.mass + orientation.transform_vector(&air.force));
    if !vector_is_finite(&string_world) || !vector_is_finite(&air.torque) {
        return Err(KiteError::NonFinite("kite wrench"));
    }
    Ok(Equilibrium {
        air,
        string_world,
        string_body: orientation.inverse_transform_vector(&string_world),
        pulls_down: string_world.dot(&conditions.gravity) > T::zero(),
    })
}

/// The unbalanced torque `T_kite = P × F_string + T_air`, eq. (15), body
/// frame, N m, for the string attached at `attachment` (P, body frame, m).
pub fn unbalanced_torque<T: Real>(eq: &Equilibrium<T>, attachment: &Vector3<T>) -> Vector3<T> {
    attachment.cross(&eq.string_body) + eq.air.torque
}

/// The attachment point on the optimal line, eq. (16), body frame, m:
/// `P(γ) = T_air × F_string / |F_string|² + γ F_string`.
///
/// Every point of this line gives the smallest possible unbalanced torque,
/// `T_kite = (T_air · F̂) F̂` (the part along the string, which no
/// attachment point can cancel).
///
/// Note on the sign: the paper prints `F_string × T_air`; with its own
/// eq. (15) (`P × F_string`) that point doubles the cancellable torque
/// instead of removing it, so the operands are swapped here (the tests
/// check the minimum property directly). `γ` has units of m/N.
pub fn attachment_point<T: Real>(eq: &Equilibrium<T>, gamma: T) -> Result<Vector3<T>, KiteError> {
    let f = eq.string_body;
    let f2 = f.dot(&f);
    if !(f2 > T::zero()) {
        return Err(KiteError::NoTension);
    }
    Ok(eq.air.torque.cross(&f) / f2 + f * gamma)
}

/// `γ` expressed as a distance: the signed offset of `P(γ)` from the
/// line's foot point along the string direction, m (`γ |F_string|`).
pub fn gamma_distance<T: Real>(eq: &Equilibrium<T>, gamma: T) -> T {
    gamma * norm(&eq.string_body)
}

/// `γ` (m/N) that puts the attachment point `distance` metres from the
/// line's foot point along the string direction. Zero tension gives
/// [`KiteError::NoTension`].
pub fn gamma_for_distance<T: Real>(eq: &Equilibrium<T>, distance: T) -> Result<T, KiteError> {
    let f = norm(&eq.string_body);
    if !(f > T::zero()) {
        return Err(KiteError::NoTension);
    }
    Ok(distance / f)
}

/// The unbalanced torque at orientation R for a fixed attachment point P
/// (body frame), recomputing the string tension from linear equilibrium.
pub fn kite_torque<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    orientation: &UnitQuaternion<T>,
    attachment: &Vector3<T>,
) -> Result<Vector3<T>, KiteError> {
    let eq = equilibrium(kite, conditions, orientation)?;
    Ok(unbalanced_torque(&eq, attachment))
}
