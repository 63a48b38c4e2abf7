//! Choosing the force fit's smoothing weight by leave-one-take-out
//! cross-validation.
//!
//! The Tikhonov weight of [`crate::fit::lsq`] trades the reconstructed
//! forces' noise against the SH truncation: from exact states less
//! smoothing is better, from noisy reconstructions (early refinement
//! iterations, §6; noisy tracks) more. A take's force errors are strongly
//! correlated in time (the smoother's error along the line of sight wanders
//! slowly), so frames are not independent and per-frame criteria such as
//! GCV would follow that noise; holding out whole takes does not. Each
//! candidate weight is fitted without one take and scored on that take's
//! frames, all from per-take normal equations (no frame is visited twice).

use crate::fit::normals::Normals;
use nalgebra::DMatrix;


/// Fewest takes for cross-validation (else the configured weight is used).
pub const MIN_TAKES: usize = 3;



/// The candidate penalty whose fits without each take predict that take's
/// forces best (summed squared error), or `fallback` with fewer than
/// [`MIN_TAKES`] takes. `takes` and `total` are the fit's (weighted)
/// normal equations; each held-out take is scored with its entry of
/// `held_out` (same unknowns, possibly other weights). `regularise(ata, c)`
/// adds candidate `c`'s smoothing term (scaled from the whole data, so that
/// every fold is smoothed alike).
pub fn choose<P: Copy + Sync>(
    takes: &[Normals],
    held_out: &[Normals],
    total: &Normals,
    candidates: &[P],
    fallback: P,
    regularise: impl Fn(&mut DMatrix<f64>, P) + Sync,
) -> P {
    if takes.len() < MIN_TAKES {
        return fallback;
    }
    // Candidates are scored on all cores; the first best in candidate
    // order wins, so the choice does not depend on the threads.
    let score = |candidate: P| held_out_error(takes, held_out, total, |m| regularise(m, candidate));
    let scores = crate::parallel::map(candidates, |_, c| score(*c));
    let mut best = (f64::INFINITY, fallback);
    for (c, s) in candidates.iter().zip(scores) {
        if s < best.0 {
            best = (s, *c);
        }
    }
    best.1
}

/// Summed squared error on each held-out take of the fit without it,
/// regularised by `regularise` (infinite when a fold is singular).
fn held_out_error(
    takes: &[Normals],
    held_out: &[Normals],
    total: &Normals,
    regularise: impl Fn(&mut DMatrix<f64>),
) -> f64 {
    let mut score = 0.0;
    for (t, h) in takes.iter().zip(held_out) {
        let mut ata = &total.ata - &t.ata;
        regularise(&mut ata);
        let Some(chol) = ata.cholesky() else {
            return f64::INFINITY;
        };
        // Held-out error: (b - Ac)ᵀW(b - Ac) = bᵀWb - 2 cᵀAᵀWb + cᵀAᵀWA c.
        score += h.btb;
        let c = chol.solve(&(&total.atb - &t.atb));
        score += c.dot(&(&h.ata * &c)) - 2.0 * c.dot(&h.atb);
    }
    score
}
