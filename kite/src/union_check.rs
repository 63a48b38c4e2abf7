//! `kite optimise`'s nonlinear check on the union of its searches'
//! results ([`crate::optimise`], [`crate::multi_start`]): which
//! candidates are flown, in what order, and the flight-margin search from
//! the best of them ([`crate::trial_flights`]).

use crate::check::Verdict;
use crate::design_params::{apply, kind, STEP};
use crate::multi_start::{Climb, Plan};
use crate::objective::{Found, Score, Search, STARTS};
use crate::trial_flights::{fly_on, pick, refine, Flown, CHECK_SEEDS};

/// What the flight check chose.
pub(crate) struct Checked {
    pub(crate) x: Vec<f64>,
    pub(crate) score: Option<Score>,
    pub(crate) flown: Option<Flown>,
    pub(crate) candidates_flown: usize,
    /// The search whose candidate it is (or whose best, when none flew).
    pub(crate) search: String,
    /// The flight-margin search moved it.
    pub(crate) refined: bool,
}

/// The nonlinear check ([`crate::trial_flights`]) on the union of the
/// searches' results: their stable designs (else the `gust_sensitive`
/// ones), each search's best objective first and taken in turn (so every
/// search's best is flown before any search's second), no two within one
/// first step of each other on every parameter; up to [`DISTINCT`] are
/// flown on the optimiser's own seeds and the one with the widest flight
/// margin is kept; then the rest of the `flown_at_most` budget climbs the
/// flight margin itself from there ([`refine`]: compass moves of the
/// first steps, trying only designs of the candidates' verdicts). With no
/// candidate, the searches' best objective, unflown.
pub(crate) fn flight_checked(
    search: &mut Search,
    plans: &[Plan],
    climbs: &[Climb],
    bounds: &[(f64, f64)],
    flown_at_most: usize,
) -> Checked {
    let name = |i: usize| {
        plans.get(i).map_or_else(
            || "the file or its quarter turns".into(),
            |p| p.name.clone(),
        )
    };
    let stable = search
        .found
        .iter()
        .any(|f| f.score.verdict == Verdict::Stable);
    let accepted = if stable {
        [Verdict::Stable; 2]
    } else {
        [Verdict::Stable, Verdict::GustSensitive]
    };
    let found = std::mem::take(&mut search.found);
    let candidates = interleave(
        found
            .into_iter()
            .filter(|f| accepted.contains(&f.score.verdict))
            .collect(),
        plans.len(),
    );
    let (base, assemble) = (search.base, search.assemble);
    let build = |c: &Found| assemble(apply(base, &c.x)).ok();
    let near = |a: &Found, b: &Found| {
        a.x.iter()
            .zip(&b.x)
            .enumerate()
            .all(|(k, (p, q))| (p - q).abs() < STEP[kind(k)])
    };
    let picked = pick(&candidates, &build, &near, flown_at_most.min(DISTINCT));
    let Some((p, c)) = picked
        .and_then(|p| Some((candidates.get(p.index)?.clone(), p)))
        .map(|(c, p)| (p, c))
    else {
        let (i, top) = climbs
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.value.total_cmp(&b.1.value))
            .map_or((STARTS, None), |(i, c)| (i, Some(c)));
        return Checked {
            x: top.map_or_else(
                || bounds.iter().map(|(lo, hi)| (lo + hi) / 2.0).collect(),
                |c| c.x.clone(),
            ),
            score: search.best.get(i).cloned().flatten(),
            flown: None,
            candidates_flown: 0,
            search: name(i),
            refined: false,
        };
    };
    let inside = |k: usize, v: f64| bounds.get(k).is_some_and(|(lo, hi)| v >= *lo && v <= *hi);
    let steps = (0..c.x.len()).map(|k| STEP[kind(k)]).collect();
    let mut trial = |t: &[f64]| {
        let s = search.evaluate(c.plan, t)?;
        accepted
            .contains(&s.verdict)
            .then(|| assemble(apply(base, t)).ok())
            .flatten()
            .map(|d| fly_on(&d, &CHECK_SEEDS))
    };
    let budget = flown_at_most.saturating_sub(p.candidates_flown);
    let (rx, flown, spent) = refine(c.x.clone(), p.flown, steps, &inside, &mut trial, budget);
    let refined = rx != c.x;
    let score = if refined {
        search.evaluate(c.plan, &rx)
    } else {
        None
    };
    Checked {
        x: rx,
        score: Some(score.unwrap_or(c.score)),
        flown: Some(flown),
        candidates_flown: p.candidates_flown + spent,
        search: name(c.plan),
        refined,
    }
}

/// The candidates ordered for the flight check: each search's (and the
/// starts', last) best objective first, exact repeats dropped, then taken
/// one from each search in turn.
fn interleave(mut found: Vec<Found>, plans: usize) -> Vec<Found> {
    found.sort_by(|a, b| b.score.objective.total_cmp(&a.score.objective));
    let mut lists: Vec<Vec<Found>> = vec![Vec::new(); plans + 1];
    for f in found {
        let list = lists.get_mut(f.plan.min(plans));
        if let Some(l) = list.filter(|l| l.iter().all(|g| g.x != f.x)) {
            l.push(f);
        }
    }
    let longest = lists.iter().map(Vec::len).max().unwrap_or(0);
    (0..longest)
        .flat_map(|r| lists.iter().filter_map(move |l| l.get(r).cloned()))
        .collect()
}

/// How many distinct stable designs the nonlinear check flies before it
/// climbs the flight margin from the best of them.
pub(crate) const DISTINCT: usize = 6;
