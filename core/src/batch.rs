//! Batched evaluation: many bodies sharing one coefficient set, eight at a
//! time, one body per SIMD lane (structure of arrays: [`Lanes`] holds one
//! component of eight bodies).
//!
//! Why across bodies rather than across SH orders ([`crate::lanes`]): with
//! one body per lane every lane runs exactly the scalar operations of the
//! portable path in the same order, so there is no horizontal sum and no
//! shuffle, the vector units stay full for every term of eqs. (7)-(8),
//! and each lane's result is *bit for bit* the portable single-body one
//! (for f64, the single-body one: f64 has no other path; for f32 it
//! agrees with the AVX single-body path to single-precision rounding).
//! Runs compiled with AVX where the machine has it ([`run_wide`], detected
//! at run time), as it is elsewhere.
//!
//! * [`wrench`]: eqs. (5)-(8) for eight bodies, and [`wrench_batch`] /
//!   [`wrench_sets`] over slices (one coefficient set, or one per body,
//!   e.g. a kite's primitives, gathered set by set into lanes);
//! * [`rk4`]: the RK4 step of [`crate::integrate`] for eight bodies.

pub mod lane_ops;
pub mod rk4;
pub mod vec;
pub mod wrench;

pub use rk4::{rk4_lanes, StateLanes};
pub use vec::V3;
pub use wrench::WrenchLanes;

use crate::aero::Wrench;
use crate::coefficients::Coefficients;
use crate::lanes::{LaneScalar, Lanes, LANES};
use nalgebra::Vector3;
use wrench::{lane, set_lane};

/// Eqs. (5)-(6) with the spin coupling ([`Coefficients::wrench`]) for
/// every body: `velocities[i]`, `rates[i]` (body frame, m/s, rad/s) give
/// `out[i]`; the shortest of the three slices sets the count. Bodies are
/// packed eight to a lane group.
pub fn wrench_batch<T: LaneScalar>(
    model: &Coefficients<T>,
    velocities: &[Vector3<T>],
    rates: &[Vector3<T>],
    air_density: T,
    out: &mut [Wrench<T>],
) {
    let n = velocities.len().min(rates.len()).min(out.len());
    let chunks = velocities
        .chunks(LANES)
        .zip(rates.chunks(LANES))
        .zip(out.get_mut(..n).unwrap_or(&mut []).chunks_mut(LANES));
    for ((v, w), o) in chunks {
        let (vl, wl) = (pack(v), pack(w));
        let r = model.wrench_lanes(&vl, &wl, air_density);
        unpack(&r, o);
    }
}

/// As [`wrench_batch`] with a coefficient set per body: body `i` uses
/// `models[set_of[i]]` (a kite's primitives, each with its own set). Loops
/// over the sets and gathers each set's bodies into lane groups, so every
/// evaluation runs on full lanes; bodies naming no set get a zero wrench.
pub fn wrench_sets<T: LaneScalar>(
    models: &[Coefficients<T>],
    set_of: &[usize],
    velocities: &[Vector3<T>],
    rates: &[Vector3<T>],
    air_density: T,
    out: &mut [Wrench<T>],
) {
    for o in out.iter_mut() {
        *o = Wrench::zero();
    }
    let n = set_of
        .len()
        .min(velocities.len())
        .min(rates.len())
        .min(out.len());
    for (set, model) in models.iter().enumerate() {
        let mut group = [0usize; LANES];
        let mut filled = 0;
        let flush = |group: &[usize], out: &mut [Wrench<T>]| {
            let (mut v, mut w) = ([Lanes::splat(T::zero()); 3], [Lanes::splat(T::zero()); 3]);
            for (l, &i) in group.iter().enumerate() {
                set_lane(&mut v, l, velocities.get(i).unwrap_or(&Vector3::zeros()));
                set_lane(&mut w, l, rates.get(i).unwrap_or(&Vector3::zeros()));
            }
            let r = model.wrench_lanes(&v, &w, air_density);
            for (l, &i) in group.iter().enumerate() {
                if let Some(o) = out.get_mut(i) {
                    *o = Wrench {
                        force: lane(&r.force, l),
                        torque: lane(&r.torque, l),
                    };
                }
            }
        };
        for (i, _) in set_of.iter().take(n).enumerate().filter(|(_, &s)| s == set) {
            if let Some(g) = group.get_mut(filled) {
                *g = i;
            }
            filled += 1;
            if filled == LANES {
                flush(&group, out);
                filled = 0;
            }
        }
        if filled > 0 {
            flush(group.get(..filled).unwrap_or(&[]), out);
        }
    }
}

/// Up to eight vectors into lanes (missing ones zero).
fn pack<T: LaneScalar>(v: &[Vector3<T>]) -> V3<T> {
    let mut out = [Lanes::splat(T::zero()); 3];
    for (i, x) in v.iter().enumerate() {
        set_lane(&mut out, i, x);
    }
    out
}

/// The first `out.len()` lanes of `w`.
fn unpack<T: LaneScalar>(w: &WrenchLanes<T>, out: &mut [Wrench<T>]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = Wrench {
            force: lane(&w.force, i),
            torque: lane(&w.torque, i),
        };
    }
}
