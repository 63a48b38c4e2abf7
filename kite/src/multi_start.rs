//! Several compass searches sharing one budget of evaluations: the
//! search behind `kite optimise` ([`crate::optimise`]), written over any
//! objective so that it can be tested on a small one.
//!
//! Why several: a first-improvement compass (pattern) search takes the
//! first move that improves, so the order of its moves and its start
//! decide which local optimum it ends in. Measured on the bundled kites
//! (BENCHMARKS, issue 17): with one move order the optimiser turned
//! box-classic and box-classic-closed into flyers but not
//! box-classic-low-bridle, with another order the reverse, and on
//! winged-box it ended short of a design within its reach that flies.
//! Several searches from different orders and starts, each given an equal
//! share of the one budget, and a choice among the union of their results
//! (the flight check of [`crate::trial_flights`]) make the result depend
//! less on one path. Each search is deterministic (its restarts draw from
//! a fixed seed), so the whole is.
//!
//! One search ([`climb`]): from its start, try each move `±step` in order
//! and take the first that improves by more than [`GAIN`]; when none does,
//! halve the steps; after [`Compass::halvings`] halvings it has converged
//! and restarts from a seeded random point within
//! [`Compass::restart_radius`] first steps of its best (first steps
//! again), until its share of the budget is spent (Hooke & Jeeves 1961;
//! Kolda, Lewis & Torczon, SIAM Review 45 (2003) §3, "compass search").

use crate::wind::SplitMix64;

/// One search direction: `(parameter, unit)` pairs, moved by the step of
/// the first parameter.
pub type Move = Vec<(usize, f64)>;

/// The least improvement a move must bring to be taken.
const GAIN: f64 = 1e-6;

/// The settings every search shares.
pub struct Compass<'a> {
    /// First step per parameter.
    pub first_steps: &'a [f64],
    /// Lower and upper bound per parameter (a trial outside is not
    /// evaluated; a restart point is clamped inside).
    pub bounds: &'a [(f64, f64)],
    /// Halvings of the steps without a gain before a search restarts.
    pub halvings: usize,
    /// How far a restart point may lie from the best, in first steps per
    /// parameter (0: restart at the best).
    pub restart_radius: f64,
}

/// One search: a name for the report, where it starts and its moves in
/// the order it tries them.
pub struct Plan {
    /// What the report calls it.
    pub name: String,
    /// Its start.
    pub start: Vec<f64>,
    /// Its moves, in order.
    pub moves: Vec<Move>,
}

/// Where one search ended.
#[derive(Clone, Debug)]
pub struct Climb {
    /// Its best parameters.
    pub x: Vec<f64>,
    /// Their value (`-inf` when nothing it tried could be evaluated).
    pub value: f64,
    /// Evaluations it spent.
    pub evaluations: usize,
    /// Times it converged and started again.
    pub restarts: usize,
}

/// Runs each plan in turn on an equal share of `budget` (what one leaves
/// unspent goes to those after it), `f(plan, x)` the objective (`None`:
/// `x` cannot be evaluated, e.g. does not assemble; it still costs an
/// evaluation). Every search's end, in the plans' order.
pub fn run_all(
    compass: &Compass,
    plans: &[Plan],
    budget: usize,
    f: &mut dyn FnMut(usize, &[f64]) -> Option<f64>,
) -> Vec<Climb> {
    let mut spent = 0;
    let mut out = Vec::with_capacity(plans.len());
    for (i, plan) in plans.iter().enumerate() {
        let share = (budget - spent.min(budget)) / (plans.len() - i);
        let seed = RESTART_SEED.wrapping_add(i as u64);
        let c = climb(compass, plan, share, seed, &mut |x| f(i, x));
        spent += c.evaluations;
        out.push(c);
    }
    out
}

/// Seed of the restarts' random points (fixed: a run is reproducible);
/// search `i` draws from `RESTART_SEED + i`.
const RESTART_SEED: u64 = 17;

/// One compass search with restarts (module doc) from `plan.start`, at
/// most `budget` evaluations of `f` (the start included).
pub fn climb(
    compass: &Compass,
    plan: &Plan,
    budget: usize,
    seed: u64,
    f: &mut dyn FnMut(&[f64]) -> Option<f64>,
) -> Climb {
    let first = || compass.first_steps.to_vec();
    let mut rng = SplitMix64::new(seed);
    let mut c = Climb {
        x: plan.start.clone(),
        value: f64::NEG_INFINITY,
        evaluations: 0,
        restarts: 0,
    };
    if budget == 0 {
        return c;
    }
    c.evaluations += 1;
    c.value = f(&plan.start).unwrap_or(f64::NEG_INFINITY);
    let (mut x, mut value, mut step, mut halved) = (c.x.clone(), c.value, first(), 0);
    while c.evaluations < budget {
        if halved >= compass.halvings {
            x = restart_point(compass, &c.x, &mut rng);
            c.evaluations += 1;
            value = f(&x).unwrap_or(f64::NEG_INFINITY);
            (step, halved) = (first(), 0);
            c.restarts += 1;
        } else if let Some((tx, tv)) = improve(
            compass,
            &plan.moves,
            &x,
            value,
            &step,
            budget,
            &mut c.evaluations,
            f,
        ) {
            (x, value) = (tx, tv);
        } else {
            step.iter_mut().for_each(|s| *s /= 2.0);
            halved += 1;
        }
        if value > c.value {
            (c.x, c.value) = (x.clone(), value);
        }
    }
    c
}

/// One sweep: the first neighbour of `x` along `moves` at `step` (inside
/// the bounds) whose value beats `value` by [`GAIN`], counting each
/// evaluation in `spent` and stopping at `budget`.
#[allow(clippy::too_many_arguments)]
fn improve(
    compass: &Compass,
    moves: &[Move],
    x: &[f64],
    value: f64,
    step: &[f64],
    budget: usize,
    spent: &mut usize,
    f: &mut dyn FnMut(&[f64]) -> Option<f64>,
) -> Option<(Vec<f64>, f64)> {
    for m in moves {
        let Some(&(lead, _)) = m.first() else {
            continue;
        };
        let size = step.get(lead).copied().unwrap_or(0.0);
        for sign in [1.0, -1.0] {
            if *spent >= budget {
                return None;
            }
            let mut trial = x.to_vec();
            for &(k, unit) in m {
                if let Some(t) = trial.get_mut(k) {
                    *t += sign * unit * size;
                }
            }
            let outside = trial
                .iter()
                .zip(compass.bounds)
                .any(|(t, (lo, hi))| t < lo || t > hi);
            if outside {
                continue;
            }
            *spent += 1;
            match f(&trial) {
                Some(v) if v > value + GAIN => return Some((trial, v)),
                _ => {}
            }
        }
    }
    None
}

/// A seeded random point within `restart_radius` first steps of `best`
/// on every parameter, clamped inside the bounds.
fn restart_point(compass: &Compass, best: &[f64], rng: &mut SplitMix64) -> Vec<f64> {
    best.iter()
        .zip(compass.first_steps)
        .zip(compass.bounds)
        .map(|((b, s), (lo, hi))| {
            (b + (2.0 * rng.uniform() - 1.0) * compass.restart_radius * s).clamp(*lo, *hi)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two hills: a low one at (1, 0) that the first move along x climbs
    /// and cannot leave, and a ridge rising along y to (0, 4) that the
    /// first move along y climbs.
    fn hills(x: &[f64]) -> Option<f64> {
        let low = 1.0 - (x[0] - 1.0).powi(2) - x[1].powi(2);
        let ridge = x[1] - 0.5 - 10.0 * x[0].powi(2);
        Some(low.max(ridge))
    }

    fn plan(name: &str, first: usize) -> Plan {
        let other = 1 - first;
        Plan {
            name: name.into(),
            start: vec![0.0, 0.0],
            moves: vec![vec![(first, 1.0)], vec![(other, 1.0)]],
        }
    }

    const COMPASS: Compass = Compass {
        first_steps: &[1.0, 1.0],
        bounds: &[(-4.0, 4.0), (-4.0, 4.0)],
        halvings: 4,
        restart_radius: 0.0,
    };

    #[test]
    fn one_order_is_stuck_and_the_union_finds_the_better_optimum() {
        // The x-first search alone, on the whole budget, ends at the low
        // hill.
        let alone = climb(&COMPASS, &plan("x first", 0), 60, 1, &mut |x| hills(x));
        assert!((alone.value - 1.0).abs() < 1e-9, "{alone:?}");
        assert_eq!(alone.evaluations, 60);
        assert!(alone.restarts > 0);
        // Two searches on the same budget: the y-first one reaches the
        // ridge's top at the bound, and the budget is shared.
        let plans = [plan("x first", 0), plan("y first", 1)];
        let mut calls = vec![0; 2];
        let ends = run_all(&COMPASS, &plans, 60, &mut |i, x| {
            calls[i] += 1;
            hills(x)
        });
        assert!((ends[0].value - 1.0).abs() < 1e-9, "{ends:?}");
        assert!((ends[1].value - 3.5).abs() < 1e-9, "{ends:?}");
        assert_eq!(ends[1].x, vec![0.0, 4.0]);
        assert_eq!(calls, vec![30, 30]);
        assert_eq!(ends.iter().map(|c| c.evaluations).sum::<usize>(), 60);
    }

    #[test]
    fn searches_are_deterministic_and_stay_inside_the_bounds() {
        let compass = Compass {
            restart_radius: 2.0,
            ..COMPASS
        };
        let mut seen = Vec::new();
        let mut f = |x: &[f64]| {
            seen.push(x.to_vec());
            hills(x)
        };
        let a = climb(&compass, &plan("x first", 0), 80, 5, &mut f);
        let b = climb(&compass, &plan("x first", 0), 80, 5, &mut |x| hills(x));
        assert_eq!((a.x, a.value, a.restarts), (b.x, b.value, b.restarts));
        assert!(seen.iter().flatten().all(|v| v.abs() <= 4.0));
        // A budget of nothing evaluates nothing.
        let none = climb(&compass, &plan("x first", 0), 0, 5, &mut |x| hills(x));
        assert_eq!((none.evaluations, none.value), (0, f64::NEG_INFINITY));
    }
}
