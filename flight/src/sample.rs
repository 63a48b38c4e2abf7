//! Per-sample quantities derived from a logged row: the aerodynamic force
//! from the balance of forces on the kite, the air velocity in the body
//! frame, the air density, and the channels the candidate effects use.
//!
//! Force balance (Newton's second law for the airborne system, NED):
//! `m a = (m + s μ l) g + F_tether + F_aero`, so
//! `F_aero = m a - (m + s μ l) g - F_tether`, with
//! - `a` the measured acceleration of the kite (IMU 1, NED), m/s²;
//! - `F_tether = -T p̂`: the tension `T` measured at the ground station
//!   (kg-force in the log, times [`KGF`]), pulling from the kite towards the ground
//!   station along the unit vector `p̂` of the kite's position — a straight
//!   tether (sag and the tether's own drag are left to the candidate
//!   effects);
//! - `s μ l`: the share `s` of the tether's weight (`μ` kg/m, length `l`
//!   = the kite's distance) that the kite carries;
//! - optionally (`tether_drag_share` c > 0), the tether's drag lumped at the
//!   kite, `-c ½ρ|V|² d l E` in the body frame, removed from the result.
//!
//! Every assumption is also listed in [`ASSUMPTIONS`], which the report
//! prints.

use crate::frames::{air_velocity_frd, frd_to_ned, position_ned, GRAVITY_NED};
use crate::kite::KiteProperties;
use crate::log::{Col, Cycle, Row};
use nalgebra::{Rotation3, Vector3};

/// The assumptions of the force balance, in words, for the report.
pub const ASSUMPTIONS: [&str; 8] = [
    "the airborne system (canopy, equipment, control unit) moves as one body with the canopy IMU's acceleration (kite_1_ax..az, NED)",
    "the tether is straight from the kite to the ground station; its tension at the kite equals the ground station's load-cell force (ground_tether_force in kgf x 9.80665 N)",
    "the kite carries the given share of the tether's weight (default one half: a line hanging symmetrically)",
    "the tether's own drag is removed only when --tether-drag-share is given (default none; the tether_drag candidate tests it)",
    "air velocity in the body frame (FRD) from the Pitot airspeed and the vane's angle of attack, no sideslip (not measured in this flight), as the firmware computes it",
    "air density from the Pitot's temperature and the ISA pressure at the kite's height above the ground station (elevation -5 m)",
    "angular acceleration by central differences of the body rates within a cycle",
    "the force is expressed in the body frame (FRD) by the attitude of IMU 1 (3-2-1 Euler angles)",
];

/// One kilogram-force in newtons (standard gravity, by definition): the
/// log gives the tether force in kg, as the firmware's reader converts it.
pub const KGF: f64 = 9.806_65;

/// Elevation of the ground station above sea level, m (README).
pub const GROUND_ELEVATION: f64 = -5.0;

/// One usable sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Cycle number.
    pub cycle: u32,
    /// Time since the cycle's first row, s.
    pub time: f64,
    /// Body (FRD) -> NED.
    pub attitude: Rotation3<f64>,
    /// Body velocity relative to the air, FRD, m/s.
    pub air_velocity: Vector3<f64>,
    /// Air density, kg/m³.
    pub air_density: f64,
    /// Aerodynamic force from the balance, FRD, N.
    pub aero_force: Vector3<f64>,
    /// Unit vector from the ground station to the kite, FRD.
    pub tether_dir: Vector3<f64>,
    /// Measured tether tension, N.
    pub tension: f64,
    /// Tether length (the kite's distance), m.
    pub tether_length: f64,
    /// Acceleration, FRD, m/s².
    pub acceleration: Vector3<f64>,
    /// Body rates, FRD, rad/s.
    pub rates: Vector3<f64>,
    /// Angular acceleration, FRD, rad/s².
    pub angular_acceleration: Vector3<f64>,
    /// Depower, fraction of the full range (0-1).
    pub depower: f64,
    /// Steering, fraction of the range in one direction (-1 to 1).
    pub steering: f64,
    /// Flight phase index (`flight_phase_index`: 1 reel-out, 2 reel-out to
    /// reel-in, 3 reel-in, 4 reel-in to reel-out; 0 where the log has none).
    pub phase: f64,
}

/// Air density, kg/m³, from the temperature (°C) and the ISA pressure at
/// `altitude` m above sea level: `p = 101325 (1 - 2.25577e-5 h)^5.25588`,
/// `ρ = p / (287.05 T)`.
pub fn air_density(temperature_c: f64, altitude: f64) -> f64 {
    let p = 101_325.0 * (1.0 - 2.25577e-5 * altitude).powf(5.25588);
    p / (287.05 * (temperature_c + 273.15))
}

/// The samples of a cycle (rows kept by the reader, in order).
pub fn samples(cycle: &Cycle, kite: &KiteProperties) -> Vec<Sample> {
    let rows = &cycle.rows;
    let t0 = rows.first().map_or(0.0, |r| r.get(Col::Time));
    (0..rows.len())
        .filter_map(|i| {
            let r = rows.get(i)?;
            let prev = rows.get(i.wrapping_sub(1)).unwrap_or(r);
            let next = rows.get(i + 1).unwrap_or(r);
            sample(cycle.number, t0, prev, r, next, kite)
        })
        .collect()
}

fn rates(r: &Row) -> Vector3<f64> {
    Vector3::new(
        r.get(Col::RollRate),
        r.get(Col::PitchRate),
        r.get(Col::YawRate),
    )
}

fn sample(
    cycle: u32,
    t0: f64,
    prev: &Row,
    r: &Row,
    next: &Row,
    kite: &KiteProperties,
) -> Option<Sample> {
    let attitude = frd_to_ned(r.get(Col::Roll), r.get(Col::Pitch), r.get(Col::Yaw));
    let p = position_ned(r.get(Col::North), r.get(Col::East), r.get(Col::Height));
    let dir_ned = p.try_normalize(1e-9)?;
    let tension = r.get(Col::TetherForce) * KGF;
    let length = r.get(Col::Distance);
    let a_ned = Vector3::new(r.get(Col::Ax), r.get(Col::Ay), r.get(Col::Az));
    let carried = kite.tether_weight_share * kite.tether_mass_per_metre() * length;
    let aero_ned = a_ned * kite.mass - GRAVITY_NED * (kite.mass + carried) + dir_ned * tension;
    let inv = attitude.inverse();
    let dt = next.get(Col::Time) - prev.get(Col::Time);
    let angular_acceleration = if dt > 0.0 {
        (rates(next) - rates(prev)) / dt
    } else {
        Vector3::zeros()
    };
    let air_velocity = air_velocity_frd(r.get(Col::Airspeed), r.get(Col::AngleOfAttack));
    let density = air_density(
        r.get(Col::Temperature),
        GROUND_ELEVATION + r.get(Col::Height),
    );
    let tether_drag = air_velocity
        .try_normalize(1e-9)
        .map_or(Vector3::zeros(), |e| {
            -e * (kite.tether_drag_share
                * 0.5
                * density
                * air_velocity.norm_squared()
                * kite.tether_diameter
                * length)
        });
    let s = Sample {
        cycle,
        time: r.get(Col::Time) - t0,
        attitude,
        air_velocity,
        air_density: density,
        aero_force: inv * aero_ned - tether_drag,
        tether_dir: inv * dir_ned,
        tension,
        tether_length: length,
        acceleration: inv * a_ned,
        rates: rates(r),
        angular_acceleration,
        depower: r.get(Col::Depower) / 100.0,
        steering: r.get(Col::Steering) / 100.0,
        phase: r.get(Col::PhaseIndex),
    };
    (s.air_velocity.norm() > 1.0 && s.air_density.is_finite()).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::REQUIRED;

    #[test]
    fn air_density_is_isa_at_sea_level_and_15_c() {
        assert!((air_density(15.0, 0.0) - 1.225).abs() < 1e-3);
        assert!(air_density(15.0, 300.0) < air_density(15.0, 0.0));
    }

    /// A kite hovering straight above the ground station at rest: the air
    /// must carry its weight plus the tension, straight up (FRD -z when
    /// level).
    #[test]
    fn the_balance_of_a_hovering_kite_is_weight_plus_tension() {
        let mut v = [0.0; REQUIRED.len()];
        v[Col::Height as usize] = 100.0;
        v[Col::Distance as usize] = 100.0;
        v[Col::TetherForce as usize] = 100.0; // kg
        v[Col::Airspeed as usize] = 10.0;
        v[Col::Temperature as usize] = 15.0;
        let row = Row(v);
        let cycle = Cycle {
            number: 1,
            path: "x_0001.csv".into(),
            rows: vec![row],
            read: 1,
            dropped: Default::default(),
        };
        let kite = KiteProperties::default();
        let s = samples(&cycle, &kite);
        let carried = 0.5 * kite.tether_mass_per_metre() * 100.0;
        let expected = -(kite.mass + carried) * 9.81 - 100.0 * KGF;
        assert_eq!(s.len(), 1);
        assert!((s[0].aero_force - Vector3::new(0.0, 0.0, expected)).norm() < 1e-9);
        assert!((s[0].tether_dir - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        // With a tether-drag share, its drag along the apparent wind (body
        // +x here, no angle of attack) is removed from the kite's force.
        let with_drag = KiteProperties {
            tether_drag_share: 0.3,
            ..kite
        };
        let d = samples(&cycle, &with_drag);
        let drag = 0.3 * 0.5 * s[0].air_density * 100.0 * kite.tether_diameter * 100.0;
        assert!((d[0].aero_force - s[0].aero_force - Vector3::new(drag, 0.0, 0.0)).norm() < 1e-9);
    }
}
