//! Direction coverage (§6's 32 x 16 sphere grid about the pole): which
//! body-frame directions E the data covers and how densely.
//!
//! Cell `lon * 16 + lat` (longitude-major, as `Provenance::coverage`):
//! latitude `θ = acos(E·Z)` in 16 bands from +Z to -Z, longitude
//! `φ = atan2(E·Y', E·X')` in 32 sectors from 0 to 2π, where `X'` is the
//! body axis least aligned with the pole Z made orthogonal to it, and
//! `Y' = Z × X'`.

use nalgebra::Vector3;
use omniad_core::coefficients::{COVERAGE_LAT, COVERAGE_LON};
use std::f64::consts::PI;

/// The grid frame `(X', Y', Z)` about a unit pole.
pub fn pole_frame(pole: &Vector3<f64>) -> [Vector3<f64>; 3] {
    let a = pole.map(f64::abs);
    let axis = if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let x = (axis - pole * pole.dot(&axis)).normalize();
    [x, pole.cross(&x), *pole]
}

/// Cell index of a unit direction.
pub fn cell(frame: &[Vector3<f64>; 3], e: &Vector3<f64>) -> usize {
    let [x, y, z] = frame;
    let theta = e.dot(z).clamp(-1.0, 1.0).acos();
    let phi = e.dot(y).atan2(e.dot(x)).rem_euclid(2.0 * PI);
    let lat = ((theta / PI * COVERAGE_LAT as f64) as usize).min(COVERAGE_LAT - 1);
    let lon = ((phi / (2.0 * PI) * COVERAGE_LON as f64) as usize).min(COVERAGE_LON - 1);
    lon * COVERAGE_LAT + lat
}

/// Unit direction at the centre of a cell and its solid angle (sr).
pub fn cell_centre(frame: &[Vector3<f64>; 3], index: usize) -> (Vector3<f64>, f64) {
    let (lon, lat) = (index / COVERAGE_LAT, index % COVERAGE_LAT);
    let dtheta = PI / COVERAGE_LAT as f64;
    let dphi = 2.0 * PI / COVERAGE_LON as f64;
    let theta = (lat as f64 + 0.5) * dtheta;
    let phi = (lon as f64 + 0.5) * dphi;
    let [x, y, z] = frame;
    let e = (x * phi.cos() + y * phi.sin()) * theta.sin() + z * theta.cos();
    let area = dphi * ((theta - 0.5 * dtheta).cos() - (theta + 0.5 * dtheta).cos());
    (e, area)
}

/// Frames per cell for the given directions (saturating at `u16::MAX`).
pub fn histogram(pole: &Vector3<f64>, directions: impl Iterator<Item = Vector3<f64>>) -> Vec<u16> {
    let frame = pole_frame(pole);
    let mut counts = vec![0u16; COVERAGE_LON * COVERAGE_LAT];
    for e in directions {
        if let Some(c) = counts.get_mut(cell(&frame, &e)) {
            *c = c.saturating_add(1);
        }
    }
    counts
}

/// Number of `directions` within `angle` (rad) of the unit vector `e`.
pub fn count_within(directions: &[Vector3<f64>], e: &Vector3<f64>, angle: f64) -> usize {
    let c = angle.cos();
    directions.iter().filter(|d| d.dot(e) >= c).count()
}

/// Unit directions and solid angles (sr) of an `nlon x nlat` grid about body z.
pub fn sphere_grid(nlon: usize, nlat: usize) -> Vec<(Vector3<f64>, f64)> {
    let dt = PI / nlat as f64;
    let dp = 2.0 * PI / nlon as f64;
    let mut out = Vec::with_capacity(nlon * nlat);
    for i in 0..nlon {
        for j in 0..nlat {
            let (t, p) = ((j as f64 + 0.5) * dt, (i as f64 + 0.5) * dp);
            let e = Vector3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
            out.push((e, dp * ((t - 0.5 * dt).cos() - (t + 0.5 * dt).cos())));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_centres_fall_in_their_cells_and_tile_the_sphere() {
        let pole = Vector3::new(0.0, 1.0, 0.0);
        let f = pole_frame(&pole);
        let mut total = 0.0;
        for i in 0..COVERAGE_LON * COVERAGE_LAT {
            let (e, area) = cell_centre(&f, i);
            assert_eq!(cell(&f, &e), i);
            total += area;
        }
        assert!((total - 4.0 * PI).abs() < 1e-9);
    }
}
