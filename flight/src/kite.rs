//! The kite and tether of the flight (the data set's README), as defaults
//! that command-line options override.

use serde::Serialize;

/// Physical properties used by the force balance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct KiteProperties {
    /// Airborne mass moving with the kite, kg: canopy 11 + canopy-mounted
    /// equipment 3.2 + control unit (KCU) with cover 19.2 + onboard wind
    /// turbine 2.8.
    pub mass: f64,
    /// Of that, the control unit's (KCU, turbine) mass hanging below the
    /// canopy on the bridle, kg: 19.2 + 2.8.
    pub kcu_mass: f64,
    /// Projected wing area S, m².
    pub projected_area: f64,
    /// Reference length L of the OmniAD model, m: bounding-box diagonal of
    /// the 8.3 x 2.5 x 3 m canopy (as the firmware's default model).
    pub reference_length: f64,
    /// Tether density, kg/m³ (Dyneema).
    pub tether_density: f64,
    /// Tether diameter, m.
    pub tether_diameter: f64,
    /// Share of the tether's weight the kite carries (0: none, as a
    /// straight massless line; 0.5: half, a line hanging symmetrically).
    pub tether_weight_share: f64,
    /// Tether drag the balance removes, as the drag coefficient share `c`
    /// of `c ½ρ|V|² d l` along the apparent wind (0: none, the default —
    /// the `tether_drag` candidate effect then finds it from the data; a
    /// uniform line moving with the kite gives about C_d / 4 ≈ 0.3,
    /// Argatov et al. 2009).
    pub tether_drag_share: f64,
}

impl Default for KiteProperties {
    fn default() -> Self {
        Self {
            mass: 11.0 + 3.2 + 19.2 + 2.8,
            kcu_mass: 19.2 + 2.8,
            projected_area: 19.75,
            reference_length: 9.2,
            tether_density: 724.0,
            tether_diameter: 0.01,
            tether_weight_share: 0.5,
            tether_drag_share: 0.0,
        }
    }
}

impl KiteProperties {
    /// Tether mass per metre, kg/m.
    pub fn tether_mass_per_metre(&self) -> f64 {
        self.tether_density * std::f64::consts::PI * 0.25 * self.tether_diameter.powi(2)
    }

    /// Checks every property is finite and in range; names the field.
    pub fn validate(&self) -> Result<(), String> {
        let positive = [
            ("mass", self.mass),
            ("projected_area", self.projected_area),
            ("reference_length", self.reference_length),
            ("tether_density", self.tether_density),
            ("tether_diameter", self.tether_diameter),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a positive number, found {v}"));
            }
        }
        if !(self.kcu_mass.is_finite() && (0.0..=self.mass).contains(&self.kcu_mass)) {
            return Err(format!(
                "kcu_mass must be between 0 and mass, found {}",
                self.kcu_mass
            ));
        }
        if !(0.0..=2.0).contains(&self.tether_drag_share) {
            return Err(format!(
                "tether_drag_share must be between 0 and 2, found {}",
                self.tether_drag_share
            ));
        }
        if !(0.0..=1.0).contains(&self.tether_weight_share) {
            return Err(format!(
                "tether_weight_share must be between 0 and 1, found {}",
                self.tether_weight_share
            ));
        }
        Ok(())
    }
}
