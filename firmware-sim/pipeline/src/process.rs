//! The per-frame computation.

use crate::eig;
use crate::frame::{SensorFrame, Telemetry};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use omniad_core::aero::Wrench;
use omniad_core::coefficients::MassProperties;
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::{AirForces, Environment, Forces, RigidBody, State};
use omniad_core::{Coefficients, ModelError, Real};

/// Air density used for every frame, kg/m³ (ISA sea level).
pub const AIR_DENSITY: f32 = 1.225;
/// Standard gravity, m/s², along +z of NED.
pub const GRAVITY: f32 = 9.806_65;
/// RK4 look-ahead: number of steps.
pub const LOOKAHEAD_STEPS: usize = 5;
/// RK4 look-ahead: step, s (5 x 0.02 s = one 10 Hz frame period).
pub const LOOKAHEAD_DT: f32 = 0.02;
/// Rotation used by the finite-difference torque Jacobian, rad.
pub const JACOBIAN_ANGLE: f64 = 0.02;
/// cos and sin of [`JACOBIAN_ANGLE`] (literals: no trigonometry at run time).
const JACOBIAN_COS: f32 = 0.9998000066665778_f64 as f32;
const JACOBIAN_SIN: f32 = 0.01999866669333308_f64 as f32;

/// Mass properties used when the coefficient file has none: the Kitepower
/// V3 kite with its control unit, 36.2 kg (11 + 3.2 + 19.2 + 2.8 kg), and
/// a rough inertia (canopy as a 8.3 m span plate, KCU as a point mass
/// about 8 m below the centre of mass), kg m².
pub const DEFAULT_BODY: MassProperties = MassProperties {
    mass: 36.2,
    inertia: [1100.0, 1000.0, 150.0, 0.0, 0.0, 0.0],
};

/// Everything fixed during a run.
pub struct Processor<'a> {
    model: &'a Coefficients<f32>,
    body: RigidBody<f32>,
    mass: f32,
    environment: Environment<f32>,
}

/// The core's air model plus a constant world-frame tether force through
/// the centre of mass.
struct KiteForces<'a> {
    air: AirForces<'a, f32>,
    tether_world: Vector3<f32>,
}

impl Forces<f32> for KiteForces<'_> {
    // Not inlined: rk4_step calls it four times, and each inlined copy
    // would get its own stack slots.
    #[inline(never)]
    fn wrench(&self, t: f32, state: &State<f32>) -> Wrench<f32> {
        let mut w = self.air.wrench(t, state);
        w.force += state
            .orientation
            .inverse_transform_vector(&self.tether_world);
        w
    }

    /// A model's added mass (a named effect) joins the kite's mass in the
    /// look-ahead, as in every other simulation of the core.
    fn added_mass(&self) -> Option<nalgebra::Matrix3<f32>> {
        self.air.added_mass()
    }
}

impl<'a> Processor<'a> {
    /// A processor for `model`; mass properties from the file or
    /// [`DEFAULT_BODY`].
    pub fn new(model: &'a Coefficients<f32>) -> Result<Self, ModelError> {
        let props = model.body.unwrap_or(DEFAULT_BODY);
        let body = RigidBody::<f32>::from_properties(&props)?;
        Ok(Self {
            model,
            mass: body.mass,
            body,
            environment: Environment {
                gravity: Vector3::new(0.0, 0.0, GRAVITY),
                air_density: AIR_DENSITY,
                wind: Vector3::zeros(),
            },
        })
    }

    /// Force and torque at body-frame air velocity `v` and rates `omega`:
    /// the core's `Coefficients::<f32>::wrench`, eqs. (5)-(6).
    #[inline(never)]
    pub fn wrench(&self, v: &Vector3<f32>, omega: &Vector3<f32>) -> Wrench<f32> {
        self.model.wrench(v, omega, AIR_DENSITY)
    }

    /// Everything for one validated frame (see [`Telemetry`]). `seq` and
    /// `rejected` are copied into the record.
    pub fn process(&self, seq: u32, rejected: u32, f: &SensorFrame) -> Telemetry {
        let [w, x, y, z] = f.attitude;
        let q = Quaternion::new(w, x, y, z);
        let n = q.coords.dot(&q.coords).root();
        let attitude = UnitQuaternion::new_unchecked(q / n);
        let (v_body, omega) = air_inputs(f);
        let wrench = if self.model.effects().is_empty() && self.model.gravity_coupling().is_none() {
            self.wrench(&v_body, &omega)
        } else {
            // Terms that need the attitude (buoyancy, gravity coupling) and
            // the named effects: the whole air force, as `AirForces`.
            let g_body = attitude.inverse_transform_vector(&self.environment.gravity);
            self.model
                .wrench_in_gravity(&v_body, &omega, &g_body, AIR_DENSITY)
        };

        // Quasi-steady: the tether balances aerodynamic force plus weight.
        let net = attitude.transform_vector(&wrench.force) + self.environment.gravity * self.mass;
        let predicted = net.dot(&net).root();
        let tether_world = if predicted > 0.0 {
            net * (-f.tether_force / predicted)
        } else {
            Vector3::zeros()
        };

        let eigenvalues = self.stability(&v_body);

        let forces = KiteForces {
            air: AirForces {
                model: self.model,
                environment: self.environment,
            },
            tether_world,
        };
        let mut state = State {
            position: Vector3::zeros(),
            orientation: attitude,
            velocity: attitude.transform_vector(&v_body),
            angular_velocity: omega,
        };
        let mut t = 0.0f32;
        for _ in 0..LOOKAHEAD_STEPS {
            state = rk4_step(
                &self.body,
                &self.environment,
                &forces,
                t,
                LOOKAHEAD_DT,
                &state,
            );
            t += LOOKAHEAD_DT;
        }
        let la = state.orientation.quaternion();
        Telemetry {
            seq,
            time_ms: f.time_ms,
            force: wrench.force.into(),
            torque: wrench.torque.into(),
            tether_predicted: predicted,
            tether_residual: predicted - f.tether_force,
            eigenvalues,
            lookahead_attitude: [la.w, la.i, la.j, la.k],
            lookahead_rates: state.angular_velocity.into(),
            lookahead_airspeed: state.velocity.dot(&state.velocity).root(),
            rejected,
            instructions: 0,
        }
    }

    /// Eigenvalues (ascending) of the symmetric part of `dT/dθ`, the
    /// aerodynamic torque's Jacobian w.r.t. small body rotations θ about
    /// the body axes, by central differences (six wrench evaluations).
    /// Rotating the body by +δ turns the body-frame air velocity by -δ.
    pub fn stability(&self, v: &Vector3<f32>) -> [f32; 3] {
        let (c, s) = (JACOBIAN_COS, JACOBIAN_SIN);
        const INV: f32 = (0.5 / JACOBIAN_ANGLE) as f32;
        let inv = INV;
        let zero = Vector3::zeros();
        let torque = |u: Vector3<f32>| self.wrench(&u, &zero).torque;
        let col = |plus: Vector3<f32>, minus: Vector3<f32>| (torque(plus) - torque(minus)) * inv;
        // R_x(a) v = (x, c y - s z, s y + c z), a = ∓δ.
        let jx = col(
            Vector3::new(v.x, c * v.y + s * v.z, -s * v.y + c * v.z),
            Vector3::new(v.x, c * v.y - s * v.z, s * v.y + c * v.z),
        );
        let jy = col(
            Vector3::new(c * v.x - s * v.z, v.y, s * v.x + c * v.z),
            Vector3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z),
        );
        let jz = col(
            Vector3::new(c * v.x + s * v.y, -s * v.x + c * v.y, v.z),
            Vector3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z),
        );
        // J = [jx jy jz] (columns); symmetric part.
        let h = 0.5f32;
        eig::symmetric3(
            jx.x,
            jy.y,
            jz.z,
            h * (jy.x + jx.y),
            h * (jz.x + jx.z),
            h * (jz.y + jy.z),
        )
    }
}

/// The model's inputs from a frame: body velocity relative to the air
/// (FRD, from the Pitot airspeed and the vane's angle of attack, no
/// sideslip: `alpha = atan(w/u)`) and the body rates.
pub fn air_inputs(f: &SensorFrame) -> (Vector3<f32>, Vector3<f32>) {
    let (s, c) = sin_cos(f.angle_of_attack);
    (
        Vector3::new(f.airspeed * c, 0.0, f.airspeed * s),
        Vector3::from(f.rates),
    )
}

/// `(sin a, cos a)` for |a| <= π/2 by Taylor polynomials in Horner form
/// (degree 11 and 10): absolute error below 4e-6 on that range, plain
/// `f32` arithmetic, so identical on host and firmware.
pub fn sin_cos(a: f32) -> (f32, f32) {
    let x2 = a * a;
    let s = a
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0
                    + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0 + x2 * (-1.0 / 39_916_800.0))))));
    let c = 1.0
        + x2 * (-0.5
            + x2 * (1.0 / 24.0
                + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0)))));
    (s, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_accuracy() {
        let mut a = -core::f32::consts::FRAC_PI_2;
        while a <= core::f32::consts::FRAC_PI_2 {
            let (s, c) = sin_cos(a);
            assert!((s as f64 - (a as f64).sin()).abs() < 4e-6, "{a}");
            assert!((c as f64 - (a as f64).cos()).abs() < 4e-6, "{a}");
            a += 0.01;
        }
    }
}
