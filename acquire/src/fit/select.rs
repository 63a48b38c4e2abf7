//! Leave-one-take-out selection: the one engine that chooses the
//! smoothing of the force and torque fits (weight and Sobolev order,
//! [`crate::fit::smoothing`]) and the model extensions kept
//! ([`crate::fit::extensions`]).
//!
//! A take's force errors are strongly correlated in time (the smoother's
//! error along the line of sight wanders slowly), so frames are not
//! independent and per-frame criteria such as GCV would follow that noise;
//! holding out whole takes does not. Each candidate is fitted without one
//! take and scored on that take's frames, all from per-take normal
//! equations (no frame is visited twice).

use crate::fit::normals::Normals;
use nalgebra::DMatrix;

/// Fewest takes for leave-one-take-out selection (with fewer, the fits
/// use their configured smoothing and fit no extensions).
pub const MIN_TAKES: usize = 3;

/// Each candidate's held-out score over `takes` takes: `fold(c, t, s)`
/// adds to the running score `s` the error on take `t` of candidate `c`
/// fitted without it, `None` when that fold cannot be solved. `None`
/// (no selection) with fewer than [`MIN_TAKES`] takes; a candidate with a
/// failed fold scores `None`. Candidates are scored on all cores, results
/// in candidate order, so nothing depends on the threads.
pub(crate) fn held_out_scores<P: Sync>(
    takes: usize,
    candidates: &[P],
    fold: impl Fn(&P, usize, f64) -> Option<f64> + Sync,
) -> Option<Vec<Option<f64>>> {
    if takes < MIN_TAKES {
        return None;
    }
    Some(crate::parallel::map(candidates, |_, c| {
        (0..takes).try_fold(0.0, |score, t| fold(c, t, score))
    }))
}

/// Every fold's result `fold(t)` (take `t` held out) on all cores, in
/// take order, for selections that need each held-out take's error (a
/// paired test across takes, `crate::residual`) and not only their sum;
/// `None` with fewer than [`MIN_TAKES`] takes.
pub fn per_fold<T: Send>(takes: usize, fold: impl Fn(usize) -> T + Sync) -> Option<Vec<T>> {
    if takes < MIN_TAKES {
        return None;
    }
    let folds: Vec<usize> = (0..takes).collect();
    Some(crate::parallel::map(&folds, |_, &t| fold(t)))
}

/// The first candidate of lowest score (`None` scores lose) with its
/// score, or `fallback` (score infinite) when none scores below infinity.
pub(crate) fn best<P: Copy>(candidates: &[P], scores: &[Option<f64>], fallback: P) -> (f64, P) {
    let mut best = (f64::INFINITY, fallback);
    for (c, s) in candidates.iter().zip(scores) {
        let s = s.unwrap_or(f64::INFINITY);
        if s < best.0 {
            best = (s, *c);
        }
    }
    best
}

/// The candidate penalty whose fits without each take predict that take's
/// forces best (summed squared error), with that held-out score, or
/// `fallback` (score infinite) with fewer than [`MIN_TAKES`] takes. `takes` and `total` are the fit's (weighted)
/// normal equations; each held-out take is scored with its entry of
/// `held_out` (same unknowns, possibly other weights). `regularise(ata, c)`
/// adds candidate `c`'s smoothing term (scaled from the whole data, so that
/// every fold is smoothed alike).
pub(crate) fn choose<P: Copy + Sync>(
    takes: &[Normals],
    held_out: &[Normals],
    total: &Normals,
    candidates: &[P],
    fallback: P,
    regularise: impl Fn(&mut DMatrix<f64>, P) + Sync,
) -> (f64, P) {
    let n = takes.len().min(held_out.len());
    let fold = |c: &P, i: usize, score: f64| {
        let (t, h) = (takes.get(i)?, held_out.get(i)?);
        let mut ata = &total.ata - &t.ata;
        regularise(&mut ata, *c);
        let chol = ata.cholesky()?;
        // Held-out error: (b - Ac)ᵀW(b - Ac) = bᵀWb - 2 cᵀAᵀWb + cᵀAᵀWA c.
        let score = score + h.btb;
        let x = chol.solve(&(&total.atb - &t.atb));
        Some(score + (x.dot(&(&h.ata * &x)) - 2.0 * x.dot(&h.atb)))
    };
    match held_out_scores(n, candidates, fold) {
        Some(scores) => best(candidates, &scores, fallback),
        None => (f64::INFINITY, fallback),
    }
}
