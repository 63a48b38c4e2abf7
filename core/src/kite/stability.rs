//! Static stability (§7): the Jacobian `J = ∂T_kite/∂Θ` for `R' = R exp[Θ]ₓ`
//! with the attachment point held fixed, the eigen-decomposition of its
//! symmetric part, and a verdict per eigen-axis (negative eigenvalue:
//! restoring torque, stable).

use super::statics::kite_torque;
use super::{skew, Conditions, Kite, KiteError};
use crate::lanes::LaneScalar;
use crate::math::{lit, norm, vector_is_finite, Real};
use nalgebra::{Matrix3, SymmetricEigen, UnitQuaternion, Vector3};

/// Relative step for central differences in the scalar type `T`
/// (about the cube root of its machine epsilon).
fn relative_step<T: Real>() -> T {
    if core::mem::size_of::<T>() <= 4 {
        lit(2e-3)
    } else {
        lit(5e-6)
    }
}

/// `∂(F_p, T_p)/∂V_p` of one primitive's eqs. (5)-(6) at `V_p` (its own
/// frame), by central differences in the air velocity: `(A_p, B_p)`.
fn primitive_sensitivity<T: LaneScalar>(
    coefficients: &crate::Coefficients<T>,
    v: &Vector3<T>,
    air_density: T,
) -> (Matrix3<T>, Matrix3<T>) {
    let h = relative_step::<T>() * norm(v);
    let mut a = Matrix3::zeros();
    let mut b = Matrix3::zeros();
    if !(h > T::zero()) {
        return (a, b);
    }
    let zero = Vector3::zeros();
    for (j, e) in [Vector3::x(), Vector3::y(), Vector3::z()]
        .iter()
        .enumerate()
    {
        let plus = coefficients.wrench(&(v + e * h), &zero, air_density);
        let minus = coefficients.wrench(&(v - e * h), &zero, air_density);
        let two_h = h + h;
        a.set_column(j, &((plus.force - minus.force) / two_h));
        b.set_column(j, &((plus.torque - minus.torque) / two_h));
    }
    (a, b)
}

/// `J = ∂T_kite/∂Θ` at orientation R for attachment point P (body frame),
/// N m/rad, by the chain rule:
///
/// with `w_b = Rᵀ v_wind`, `g_b = Rᵀ g` and `δ(Rᵀ a) = [Rᵀ a]ₓ Θ`,
/// `∂F_air/∂Θ = -Σ Q_p A_p Q_pᵀ [w_b]ₓ`,
/// `∂T_air/∂Θ = -Σ (Q_p B_p Q_pᵀ + [Y_p]ₓ Q_p A_p Q_pᵀ) [w_b]ₓ`,
/// `∂F_string/∂Θ = -M [g_b]ₓ - ∂F_air/∂Θ`,
/// `J = [P]ₓ ∂F_string/∂Θ + ∂T_air/∂Θ`,
/// where `A_p`, `B_p` (the sensitivities of eqs. 5-6 of one primitive to
/// its air velocity) are central differences. [`jacobian_numeric`]
/// differentiates the whole of eq. (15) instead; the two are compared in
/// the tests.
pub fn jacobian<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    orientation: &UnitQuaternion<T>,
    attachment: &Vector3<T>,
) -> Result<Matrix3<T>, KiteError> {
    let w_b = orientation.inverse_transform_vector(&conditions.wind);
    let g_b = orientation.inverse_transform_vector(&conditions.gravity);
    let skew_w = skew(&w_b);
    let mut d_force = Matrix3::zeros();
    let mut d_torque = Matrix3::zeros();
    for p in kite.primitives {
        let q = p.rotation;
        let v_p = q.transpose() * (-w_b);
        let (a, b) = primitive_sensitivity(p.coefficients, &v_p, conditions.air_density);
        let a_body = q * a * q.transpose();
        let b_body = q * b * q.transpose();
        d_force -= a_body * skew_w;
        d_torque -= (b_body + skew(&p.offset) * a_body) * skew_w;
    }
    let d_string = -(skew(&g_b) * kite.mass) - d_force;
    let j = skew(attachment) * d_string + d_torque;
    if j.iter().any(|x| !x.finite()) {
        return Err(KiteError::NonFinite("jacobian"));
    }
    Ok(j)
}

/// `J` by central differences of eq. (15) over `Θ` (step `step` rad),
/// with the string tension recomputed from linear equilibrium at each
/// perturbed orientation.
pub fn jacobian_numeric<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    orientation: &UnitQuaternion<T>,
    attachment: &Vector3<T>,
    step: T,
) -> Result<Matrix3<T>, KiteError> {
    let mut j = Matrix3::zeros();
    for (col, e) in [Vector3::x(), Vector3::y(), Vector3::z()]
        .iter()
        .enumerate()
    {
        let turn = |s: T| orientation * UnitQuaternion::from_scaled_axis(e * s);
        let plus = kite_torque(kite, conditions, &turn(step), attachment)?;
        let minus = kite_torque(kite, conditions, &turn(-step), attachment)?;
        j.set_column(col, &((plus - minus) / (step + step)));
    }
    Ok(j)
}

/// One principal axis of the symmetric part of `J`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis<T: Real> {
    /// Eigenvalue, N m/rad: negative means restoring torque.
    pub eigenvalue: T,
    /// Unit eigenvector, body frame (sign chosen so that its largest
    /// component is positive).
    pub axis: Vector3<T>,
    /// `eigenvalue < 0`.
    pub stable: bool,
}

/// The stability of a kite at one orientation and attachment point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stability<T: Real> {
    /// `J = ∂T_kite/∂Θ`, N m/rad.
    pub jacobian: Matrix3<T>,
    /// The three axes of `(J + Jᵀ)/2`, eigenvalues ascending.
    pub axes: [Axis<T>; 3],
}

impl<T: Real> Stability<T> {
    /// All three eigenvalues negative (§7).
    pub fn is_stable(&self) -> bool {
        self.axes.iter().all(|a| a.stable)
    }
}

/// Eigen-decomposition of a symmetric 3x3 matrix (no allocation):
/// `(eigenvalue, unit eigenvector)` pairs, eigenvalues ascending, each
/// eigenvector's largest component positive.
pub fn symmetric_eigen<T: Real>(m: &Matrix3<T>) -> Result<[(T, Vector3<T>); 3], KiteError> {
    if m.iter().any(|x| !x.finite()) {
        return Err(KiteError::NonFinite("matrix"));
    }
    let sym = (m + m.transpose()) * lit::<T>(0.5);
    let eig =
        SymmetricEigen::try_new(sym, T::default_epsilon(), 200).ok_or(KiteError::EigenFailed)?;
    let vals = eig.eigenvalues;
    let vecs = eig.eigenvectors;
    let mut pairs = [
        (vals.x, canonical_sign(vecs.column(0).into_owned())),
        (vals.y, canonical_sign(vecs.column(1).into_owned())),
        (vals.z, canonical_sign(vecs.column(2).into_owned())),
    ];
    pairs.sort_unstable_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(core::cmp::Ordering::Equal));
    if pairs
        .iter()
        .any(|(l, v)| !l.finite() || !vector_is_finite(v))
    {
        return Err(KiteError::EigenFailed);
    }
    Ok(pairs)
}

/// Flips `v` so that its largest-magnitude component is positive.
fn canonical_sign<T: Real>(v: Vector3<T>) -> Vector3<T> {
    let big = v.iter().fold(
        T::zero(),
        |best, &x| if x.abs() > best.abs() { x } else { best },
    );
    if big < T::zero() {
        -v
    } else {
        v
    }
}

/// Stability at orientation R with attachment P (body frame): the
/// analytic-chain Jacobian and the axes of its symmetric part.
pub fn stability<T: LaneScalar>(
    kite: &Kite<'_, T>,
    conditions: &Conditions<T>,
    orientation: &UnitQuaternion<T>,
    attachment: &Vector3<T>,
) -> Result<Stability<T>, KiteError> {
    let jacobian = jacobian(kite, conditions, orientation, attachment)?;
    let pairs = symmetric_eigen(&jacobian)?;
    let axes = pairs.map(|(eigenvalue, axis)| Axis {
        eigenvalue,
        axis,
        stable: eigenvalue < T::zero(),
    });
    Ok(Stability { jacobian, axes })
}
