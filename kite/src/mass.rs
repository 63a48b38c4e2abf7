//! Mass, centre of mass and inertia of a kite from its rods (solid carbon
//! cylinders, thin-rod approximation), coverings (thin plates), sockets
//! (point masses at the joints) and any fitted objects.

use crate::geometry::{Panel, Rod};
use nalgebra::{Matrix3, Vector3};

/// A body's mass properties, design frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassItem {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, design frame, m.
    pub center: Vector3<f64>,
    /// Inertia about its own centre of mass, design frame, kg m².
    pub inertia: Matrix3<f64>,
}

/// Total mass properties.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass M, kg.
    pub mass: f64,
    /// Centre of mass, design frame, m.
    pub center: Vector3<f64>,
    /// Inertia about the centre of mass, kg m².
    pub inertia: Matrix3<f64>,
}

/// A thin rod: mass `ρ π d²/4 ℓ`, inertia `m ℓ²/12 (I - ûûᵀ)`.
pub fn rod_item(rod: &Rod, density: f64) -> MassItem {
    let len = rod.length();
    let mass = density * std::f64::consts::PI * rod.diameter * rod.diameter / 4.0 * len;
    let u = (rod.b - rod.a) / len;
    let inertia = (Matrix3::identity() - u * u.transpose()) * (mass * len * len / 12.0);
    MassItem {
        mass,
        center: (rod.a + rod.b) / 2.0,
        inertia,
    }
}

/// A thin rectangular sheet of areal density `density` (kg/m²).
pub fn panel_item(panel: &Panel, density: f64) -> MassItem {
    let mass = density * panel.area();
    let (a, b) = panel.edges();
    let eu = panel.u.normalize();
    let ev = panel.v.normalize();
    let en = eu.cross(&ev);
    // Principal moments: about u (b²/12), about v (a²/12), normal (a²+b²)/12.
    let inertia = (eu * eu.transpose() * (b * b)
        + ev * ev.transpose() * (a * a)
        + en * en.transpose() * (a * a + b * b))
        * (mass / 12.0);
    MassItem {
        mass,
        center: panel.center,
        inertia,
    }
}

/// A point mass.
pub fn point_item(mass: f64, at: Vector3<f64>) -> MassItem {
    MassItem {
        mass,
        center: at,
        inertia: Matrix3::zeros(),
    }
}

/// Sum of items with the parallel-axis theorem. `None` when the total mass
/// is not positive.
pub fn combine(items: &[MassItem]) -> Option<MassProperties> {
    let mass: f64 = items.iter().map(|i| i.mass).sum();
    if !(mass > 0.0) {
        return None;
    }
    let center = items
        .iter()
        .map(|i| i.center * i.mass)
        .sum::<Vector3<f64>>()
        / mass;
    let mut inertia = Matrix3::zeros();
    for i in items {
        let r = i.center - center;
        inertia += i.inertia + (Matrix3::identity() * r.dot(&r) - r * r.transpose()) * i.mass;
    }
    Some(MassProperties {
        mass,
        center,
        inertia,
    })
}

/// The total mass properties of rods, panels and extra items.
pub fn kite_mass(
    rods: &[Rod],
    panels: &[Panel],
    rod_density: f64,
    covering: f64,
    extra: &[MassItem],
) -> Option<MassProperties> {
    let mut items: Vec<MassItem> = rods.iter().map(|r| rod_item(r, rod_density)).collect();
    items.extend(panels.iter().map(|p| panel_item(p, covering)));
    items.extend_from_slice(extra);
    combine(&items)
}
