//! `omniad flight fit`: reading the cycles, selecting effects on the
//! training cycles, scoring before and after on the test cycles (which no
//! fitting step sees), the model file and the plots.

use crate::fit::{Design, Problem};
use crate::kite::KiteProperties;
use crate::log::{find_cycles, read_cycle, LogError};
use crate::sample::{samples, Sample, ASSUMPTIONS};
use crate::select::{select, Tried};
use crate::terms::{Channel, Setup, Term};
use nalgebra::{DVector, Vector3};
use omniad_core::Coefficients;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// What to fit.
#[derive(Clone, Debug)]
pub struct FlightFitConfig {
    /// Folder of cycle files `*_NNNN.csv`.
    pub dir: PathBuf,
    /// Training cycles.
    pub train: Vec<u32>,
    /// Test cycles (never used by a fitting step).
    pub test: Vec<u32>,
    /// Kite and tether.
    pub kite: KiteProperties,
    /// SH degree of C_F.
    pub degree: usize,
}

/// Held-out numbers of one model on the test cycles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HeldOut {
    /// RMS of the aerodynamic force error (vector norm), N.
    pub heldout_force_rms: f64,
    /// RMS of the predicted tether tension's error, N.
    pub heldout_tension_rms: f64,
    /// That RMS relative to the mean measured tension.
    pub tension_relative_error: f64,
}

/// Rows read, used and dropped.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Rows {
    /// Data rows read.
    pub read: usize,
    /// Samples used.
    pub used: usize,
    /// Rows dropped because a required column was missing or non-finite,
    /// by column.
    pub dropped_missing: BTreeMap<String, usize>,
    /// Rows dropped because the airspeed was below 1 m/s or the kite was
    /// at the ground station.
    pub dropped_no_airflow: usize,
}

/// A candidate effect's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Candidate {
    /// As scored by the selection (training cycles, leave-one-cycle-out).
    #[serde(flatten)]
    pub tried: Tried,
    /// The design it was tried in (the base model plus the effects kept
    /// before its step) with it, fitted on all training cycles, on the
    /// test cycles (reported, never used to choose), N.
    pub heldout_force_rms: f64,
}

/// How sure the choice is, given that depower is nearly two-level and
/// follows the flight phase.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Confounding {
    /// Correlation of depower with the reel-in indicator (training).
    pub depower_reel_in_correlation: f64,
    /// Leave-one-cycle-out RMS, base + depower covariate, N.
    pub cv_rms_depower: f64,
    /// Leave-one-cycle-out RMS, base + reel-in indicator instead, N.
    pub cv_rms_reel_in: f64,
    /// Leave-one-cycle-out RMS, base + both, N.
    pub cv_rms_both: f64,
}

/// The whole report (`--json`).
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Training cycles.
    pub train_cycles: Vec<u32>,
    /// Test cycles.
    pub test_cycles: Vec<u32>,
    /// Kite and tether properties used.
    pub kite: KiteProperties,
    /// SH degree.
    pub degree: usize,
    /// The base model on the test cycles.
    pub baseline: HeldOut,
    /// Every candidate.
    pub candidates: Vec<Candidate>,
    /// Selected effects, strongest first.
    pub selected: Vec<String>,
    /// Their fitted scalar parameters and jackknife standard errors over
    /// training cycles (SH blocks: the RMS of their coefficients).
    pub params: BTreeMap<String, (f64, f64)>,
    /// The final model on the test cycles.
    pub after: HeldOut,
    /// `after / baseline` force RMS.
    pub force_ratio: f64,
    /// Depower against flight phase.
    pub confounding: Confounding,
    /// Rows of the training and test cycles.
    pub rows: BTreeMap<String, Rows>,
    /// The force balance's assumptions.
    pub assumptions: Vec<&'static str>,
    /// The conclusion in words.
    pub verdict: String,
}

/// The fitted models and what the plots need.
pub struct Outcome {
    /// The report.
    pub report: Report,
    /// The base model's C_F as a coefficient file (f64).
    pub model: Coefficients<f64>,
    /// SVG figures by file name.
    pub plots: Vec<(String, String)>,
}

/// Samples grouped by cycle: `(cycle number, samples)`.
pub type Cycles = Vec<(u32, Vec<Sample>)>;

fn load(cfg: &FlightFitConfig, which: &[u32]) -> Result<(Cycles, Rows), LogError> {
    let mut rows = Rows::default();
    let mut out = Vec::new();
    for path in find_cycles(&cfg.dir, which)? {
        let c = read_cycle(&path)?;
        let s = samples(&c, &cfg.kite);
        rows.read += c.read;
        rows.used += s.len();
        rows.dropped_no_airflow += c.rows.len() - s.len();
        for (k, v) in &c.dropped {
            *rows.dropped_missing.entry(k.clone()).or_default() += v;
        }
        out.push((c.number, s));
    }
    Ok((out, rows))
}

/// Scores `theta` of `design` on `cycles`.
fn held_out(design: &Design, theta: &DVector<f64>, cycles: &Cycles) -> HeldOut {
    let (mut f2, mut t2, mut t, mut n) = (0.0, 0.0, 0.0, 0usize);
    for s in cycles.iter().flat_map(|c| c.1.iter()) {
        let r = design.predict(theta, s) - s.aero_force;
        f2 += r.norm_squared();
        t2 += r.dot(&s.tether_dir).powi(2);
        t += s.tension;
        n += 1;
    }
    let n = n.max(1) as f64;
    HeldOut {
        heldout_force_rms: (f2 / n).sqrt(),
        heldout_tension_rms: (t2 / n).sqrt(),
        tension_relative_error: (t2 / n).sqrt() / (t / n),
    }
}

fn fitted(design: &Design, train: &Cycles) -> Result<(Problem, f64, DVector<f64>), LogError> {
    let p = Problem::new(design.clone(), train);
    let (l, _) = p.choose_smoothing();
    let theta = p
        .fit(l)
        .ok_or_else(|| LogError("the training cycles do not determine the model".into()))?;
    Ok((p, l, theta))
}

/// The candidate effects of the flight (their setup values from the kite).
pub fn candidates(kite: &KiteProperties, train: &Cycles) -> Vec<Term> {
    let mean = |c: Channel| {
        let (s, n) = train
            .iter()
            .flat_map(|x| x.1.iter())
            .fold((0.0, 0usize), |(s, n), x| (s + c.value(x), n + 1));
        s / n.max(1) as f64
    };
    vec![
        Term::Covariate(Channel::Depower, mean(Channel::Depower)),
        Term::Covariate(Channel::Steering, mean(Channel::Steering)),
        Term::TetherDrag(kite.tether_diameter),
        Term::KiteInertia,
        Term::KcuSwing,
    ]
}

/// An error unless `train` has the cycles leave-one-cycle-out selection
/// needs ([`omniad_acquire::fit::select::MIN_TAKES`]): with fewer, every
/// held-out score is undefined, and the report would print infinite
/// errors and NaN gains as if they were measured.
fn enough_training_cycles(train: &Cycles) -> Result<(), LogError> {
    let min = omniad_acquire::fit::select::MIN_TAKES;
    if train.len() >= min {
        return Ok(());
    }
    let names: Vec<u32> = train.iter().map(|c| c.0).collect();
    Err(LogError(format!(
        "--train: the effects are selected by leaving one training cycle out, which needs at least {min} cycles with data; {} given {names:?}",
        train.len()
    )))
}

/// Runs the whole flight fit.
pub fn run(cfg: &FlightFitConfig, progress: impl FnMut(&str)) -> Result<Outcome, LogError> {
    cfg.kite.validate().map_err(LogError)?;
    if let Some(c) = cfg.test.iter().find(|c| cfg.train.contains(c)) {
        return Err(LogError(format!(
            "cycle {c} is both a training and a test cycle"
        )));
    }
    let (train, train_rows) = load(cfg, &cfg.train)?;
    let (test, test_rows) = load(cfg, &cfg.test)?;
    enough_training_cycles(&train)?;
    let setup = Setup {
        degree: cfg.degree,
        pole: Vector3::z(),
        reference_length: cfg.kite.reference_length,
    };
    let base = Design {
        setup,
        terms: vec![Term::Base],
    };
    let (_, _, base_theta) = fitted(&base, &train)?;
    let baseline = held_out(&base, &base_theta, &test);
    let cands = candidates(&cfg.kite, &train);
    let sel = select(base.clone(), &cands, &train, &cfg.kite, progress);
    let final_p = Problem::new(sel.design.clone(), &train);
    let theta = final_p
        .fit(sel.smoothing)
        .ok_or_else(|| LogError("the selected model is singular".into()))?;
    let after = held_out(&sel.design, &theta, &test);
    let candidates = score_candidates((&base, &sel.design), &cands, &sel.tried, &train, &test)?;
    let confounding = confounding(&base, &cands, &train);
    let params = parameters(&final_p, sel.smoothing, &theta);
    let selected: Vec<String> = sel.design.terms.iter().skip(1).map(Term::name).collect();
    let plots = crate::plots::figures(&base, &base_theta, &sel.design, &theta, &train, &test);
    let model = coefficient_file(&base, &base_theta)?;
    let mut rows = BTreeMap::new();
    rows.insert("train".to_owned(), train_rows);
    rows.insert("test".to_owned(), test_rows);
    let mut report = Report {
        train_cycles: cfg.train.clone(),
        test_cycles: cfg.test.clone(),
        kite: cfg.kite,
        degree: cfg.degree,
        baseline,
        candidates,
        selected,
        params,
        after,
        force_ratio: after.heldout_force_rms / baseline.heldout_force_rms,
        confounding,
        rows,
        assumptions: ASSUMPTIONS.to_vec(),
        verdict: String::new(),
    };
    report.verdict = verdict(&report);
    Ok(Outcome {
        report,
        model,
        plots,
    })
}

/// Every tried candidate's test-cycle force RMS: the design it was tried
/// in (the base plus the effects `selected` had kept before its step)
/// with it, fitted on the training cycles.
fn score_candidates(
    (base, selected): (&Design, &Design),
    cands: &[Term],
    tried: &[Tried],
    train: &Cycles,
    test: &Cycles,
) -> Result<Vec<Candidate>, LogError> {
    let mut out = Vec::new();
    for t in tried {
        let Some(term) = cands.iter().find(|c| c.name() == t.effect) else {
            continue;
        };
        let mut d = base.clone();
        d.terms
            .extend(selected.terms.iter().skip(base.terms.len()).take(t.step));
        d.terms.push(*term);
        let (_, _, theta) = fitted(&d, train)?;
        out.push(Candidate {
            tried: t.clone(),
            heldout_force_rms: held_out(&d, &theta, test).heldout_force_rms,
        });
    }
    Ok(out)
}

fn confounding(base: &Design, cands: &[Term], train: &Cycles) -> Confounding {
    let all: Vec<&Sample> = train.iter().flat_map(|c| c.1.iter()).collect();
    let xs: Vec<f64> = all.iter().map(|s| Channel::Depower.value(s)).collect();
    let ys: Vec<f64> = all.iter().map(|s| Channel::ReelIn.value(s)).collect();
    let depower = cands.first().copied().unwrap_or(Term::Base);
    let reel = Term::Covariate(Channel::ReelIn, mean(&ys));
    let cv = |extra: &[Term]| {
        let mut d = base.clone();
        d.terms.extend_from_slice(extra);
        Problem::new(d, train).choose_smoothing().1.sqrt()
    };
    Confounding {
        depower_reel_in_correlation: correlation(&xs, &ys),
        cv_rms_depower: cv(&[depower]),
        cv_rms_reel_in: cv(&[reel]),
        cv_rms_both: cv(&[depower, reel]),
    }
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

/// Pearson correlation (0 when either is constant).
pub fn correlation(x: &[f64], y: &[f64]) -> f64 {
    let (mx, my) = (mean(x), mean(y));
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx).powi(2);
        syy += (b - my).powi(2);
    }
    if sxx > 0.0 && syy > 0.0 {
        sxy / (sxx * syy).sqrt()
    } else {
        0.0
    }
}

fn parameters(p: &Problem, lambda: f64, theta: &DVector<f64>) -> BTreeMap<String, (f64, f64)> {
    let se = p.jackknife(lambda);
    let mut out = BTreeMap::new();
    for (i, t) in p.design.terms.iter().enumerate().skip(1) {
        let r = p.design.columns_of(i);
        let rms = |v: &DVector<f64>| {
            let s: f64 = r.clone().filter_map(|j| v.get(j)).map(|x| x * x).sum();
            (s / r.len().max(1) as f64).sqrt()
        };
        let value = if t.is_sh() {
            rms(theta)
        } else {
            theta.get(r.start).copied().unwrap_or(f64::NAN)
        };
        let err = match (&se, t.is_sh()) {
            (Some(se), true) => rms(se),
            (Some(se), false) => se.get(r.start).copied().unwrap_or(f64::NAN),
            (None, _) => f64::NAN,
        };
        out.insert(t.name(), (value, err));
    }
    out
}

fn coefficient_file(base: &Design, theta: &DVector<f64>) -> Result<Coefficients<f64>, LogError> {
    let err = |e| LogError(format!("cannot build the coefficient model: {e}"));
    let s = &base.setup;
    let degree = u8::try_from(s.degree).map_err(|_| LogError("degree too large".into()))?;
    let mut m = Coefficients::zeros(degree, s.pole, s.reference_length).map_err(err)?;
    m.set_name("kitepower-v3 flight fit").map_err(err)?;
    let n = omniad_core::sh::coeff_count(s.degree);
    for (j, v) in theta.iter().enumerate() {
        m.set_alpha(j / n, j % n, *v).map_err(err)?;
    }
    Ok(m)
}

fn verdict(r: &Report) -> String {
    let c = &r.confounding;
    let mut v = match r.selected.first() {
        None => "No candidate effect lowered the held-out error enough: the base model stands.".to_owned(),
        Some(first) => format!(
            "The residual points to {first} first (selected: {}); held-out force RMS {:.0} N -> {:.0} N ({:.2} x).",
            r.selected.join(", "),
            r.baseline.heldout_force_rms,
            r.after.heldout_force_rms,
            r.force_ratio
        ),
    };
    let phase_explains = c.cv_rms_reel_in < c.cv_rms_depower;
    v.push_str(&format!(
        " Depower follows the flight phase (correlation {:.2} with reel-in); as the only covariate, depower gives {:.0} N, the reel-in indicator {:.0} N, both {:.0} N (leave-one-cycle-out). ",
        c.depower_reel_in_correlation, c.cv_rms_depower, c.cv_rms_reel_in, c.cv_rms_both
    ));
    v.push_str(if phase_explains {
        "The phase explains the residual at least as well as depower: the data cannot tell depower from what else changes with the phase."
    } else if c.cv_rms_both > 0.98 * c.cv_rms_depower {
        "Depower explains more than the phase, and the phase adds nothing once depower is in: the data favour depower itself."
    } else {
        "Depower explains more than the phase, but the phase still adds to it: part of the effect is something else that changes with the phase."
    });
    v
}
