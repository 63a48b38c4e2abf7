//! Verdict vs flight on variants of kite files (issue 17's robustness
//! check): each file at its own pitch and string offset, pitched by
//! `--pitch` degrees, and with the offset moved by `--offset` metres, each
//! flown 60 s in 1 m/s gusts on seeds 1-3. `PITCHES=-7,-3,3,7` and
//! `OFFSETS=-0.06,0.06` replace the default changes (±5/±10°, ±0.03/±0.10
//! m), to fly variants the designs were not checked against.
//! `cargo run --release -p omniad-kite --example agreement -- data/kites/*.toml`
//! prints one row per variant (verdict, largest growth rate, the gust
//! response's predicted lowest line elevation / largest spin, each seed's
//! outcome, `*` where it disagrees) and the count of disagreements;
//! `WHY=1` prints each disagreement's flight (mean and lowest elevation,
//! largest spin) on stderr.
//!
//! Held-out seeds (kv2's method, BENCHMARKS issue 17): `SEEDS=12` flies
//! seeds 1-12 and adds, per seed triple (1-3, 4-6, ...), the design-level
//! disagreements (verdict `stable` against "flies on all three seeds of
//! the triple"), how many of them a verdict could have avoided (refused
//! but flies on all three, or `stable` but crashes on all three), how
//! many variants' seeds split within the triple (read flight by flight,
//! no verdict agrees with all three), and the flights that disagree.
//! `FLIGHTS=FILE` keeps each flight's outcome in FILE (one
//! `name<TAB>variant<TAB>seed<TAB>outcome` line), so a second run with a
//! changed verdict flies nothing again (the flights do not depend on it).

use omniad_kite::{check, flight, spec::StringSpec, Design, Library};

const PITCHES: [f64; 4] = [-10.0, -5.0, 5.0, 10.0];
const OFFSETS: [f64; 4] = [-0.10, -0.03, 0.03, 0.10];

/// The changes to try: `var` (comma-separated numbers, e.g.
/// `PITCHES=-7,-3,3,7`) or the defaults above, so variants other than
/// the ones designs were tuned against can be flown.
fn changes(var: &str, default: &[f64]) -> anyhow::Result<Vec<f64>> {
    match std::env::var(var) {
        Ok(s) => s
            .split(',')
            .map(|t| {
                t.trim()
                    .parse::<f64>()
                    .map_err(|e| anyhow::anyhow!("{var}: {t:?}: {e}"))
            })
            .collect(),
        Err(_) => Ok(default.to_vec()),
    }
}

/// `x` with `digits` decimals when that is exact, else in full (keeps
/// the cache keys of the default variants, "offset -0.10").
fn label(x: f64, digits: usize) -> String {
    let short = format!("{x:+.digits$}");
    if short.parse::<f64>() == Ok(x) {
        short
    } else {
        format!("{x:+}")
    }
}

fn variants(d: &Design) -> anyhow::Result<Vec<(String, Design)>> {
    let base = check::check(d, None)?.attachment_offset;
    let mut out = vec![("file".to_string(), d.clone())];
    for p in changes("PITCHES", &PITCHES)? {
        let mut v = d.clone();
        v.spec.orientation[1] += p;
        // Keep the file's offset (a pitch change moves the eq. 16 line).
        v.spec.string = StringSpec {
            gamma: None,
            offset: Some(base),
            length: d.spec.string.length,
        };
        out.push((format!("pitch {}", label(p, 0)), v));
    }
    for o in changes("OFFSETS", &OFFSETS)? {
        let mut v = d.clone();
        v.spec.string = StringSpec {
            gamma: None,
            offset: Some(base + o),
            length: d.spec.string.length,
        };
        out.push((format!("offset {}", label(o, 2)), v));
    }
    Ok(out)
}

/// One seed triple's tally over the variants (`SEEDS` > 3).
#[derive(Clone, Copy, Debug, Default)]
struct Triple {
    /// Verdict `stable` against "flies on all three".
    design: usize,
    /// Errors a verdict could have avoided: refused but flies on all
    /// three, or `stable` but crashes on all three.
    avoidable: usize,
    /// Variants whose three flights differ among themselves: read flight
    /// by flight, every verdict disagrees with one of them.
    split: usize,
    /// Flights whose outcome differs from the verdict.
    flights: usize,
}

impl Triple {
    fn add(&mut self, stable: bool, flew: &[bool]) {
        let (all, none) = (flew.iter().all(|f| *f), flew.iter().all(|f| !*f));
        self.design += usize::from(all != stable);
        self.avoidable += usize::from((stable && none) || (!stable && all));
        self.split += usize::from(!all && !none);
        self.flights += flew.iter().filter(|f| **f != stable).count();
    }
}

/// Flight outcomes by `name\tvariant\tseed`.
type Cache = std::collections::BTreeMap<String, String>;

fn load_cache(path: Option<&std::path::Path>) -> anyhow::Result<Cache> {
    let Some(path) = path.filter(|p| p.exists()) else {
        return Ok(Cache::new());
    };
    let text = std::fs::read_to_string(path)?;
    Ok(text
        .lines()
        .filter_map(|l| l.rsplit_once('\t'))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect())
}

/// The outcome of `v` on `seed`, from the cache or flown (and cached).
fn outcome(cache: &mut Cache, key: String, v: &Design, seed: u64) -> (String, String) {
    if let Some(o) = cache.get(&key) {
        return (o.clone(), "cached".into());
    }
    let opts = flight::FlightOptions {
        seed,
        ..Default::default()
    };
    let (o, why) = match flight::fly(v, &opts) {
        Ok(f) => (
            format!("{:?}", f.outcome).to_lowercase(),
            format!(
                "{} (elev mean {:.0}°, min {:.0}°, spin <= {:.1})",
                f.reason, f.mean_elevation_deg, f.min_elevation_deg, f.max_spin
            ),
        ),
        Err(e) => ("crashes".to_string(), format!("{e}")),
    };
    cache.insert(key, o.clone());
    (o, why)
}

fn main() -> anyhow::Result<()> {
    let files: Vec<String> = std::env::args().skip(1).collect();
    let seeds: u64 = std::env::var("SEEDS").map_or(Ok(3), |s| s.parse())?;
    let cache_path = std::env::var_os("FLIGHTS").map(std::path::PathBuf::from);
    let mut cache = load_cache(cache_path.as_deref())?;
    let mut triples = vec![Triple::default(); (seeds / 3) as usize];
    let library = Library::load(&omniad_kite::library::default_dir())?;
    let (mut total, mut bad, mut stable, mut flies) = (0, 0, 0, 0);
    for path in &files {
        let design = Design::load(std::path::Path::new(path), &library)?;
        for (label, v) in variants(&design)? {
            let (verdict, growth, gust) = match check::check(&v, None) {
                Ok(c) => (
                    c.verdict.name().to_string(),
                    c.modes.max_growth_rate,
                    c.modes.gusts.map_or(String::from("-"), |g| {
                        format!("{:.0}°/{:.1}", g.min_elevation_deg, g.max_spin)
                    }),
                ),
                Err(e) => (format!("error: {e}"), f64::NAN, String::new()),
            };
            let mut row = format!(
                "{:<22} {label:<12} {verdict:<20} {growth:+.3} {gust:<9}",
                design.spec.name
            );
            let mut flew = Vec::new();
            for seed in 1..=seeds {
                let key = format!("{}\t{label}\t{seed}", design.spec.name);
                let (outcome, why) = outcome(&mut cache, key, &v, seed);
                flew.push(outcome == "flies");
                if seed > 3 {
                    continue;
                }
                total += 1;
                stable += usize::from(verdict == "stable");
                flies += usize::from(outcome == "flies");
                let agree = (verdict == "stable") == (outcome == "flies");
                bad += usize::from(!agree);
                if !agree && std::env::var_os("WHY").is_some() {
                    eprintln!("  {} {label} seed {seed}: {why}", design.spec.name);
                }
                row += &format!(" {outcome:<8}{}", if agree { " " } else { "*" });
            }
            for (t, chunk) in flew.chunks_exact(3).enumerate() {
                if let Some(n) = triples.get_mut(t) {
                    n.add(verdict == "stable", chunk);
                }
            }
            println!("{row}");
        }
    }
    println!("{bad} of {total} flights disagree ({stable} called stable, {flies} flew)");
    if seeds > 3 {
        let column = |f: fn(&Triple) -> usize| triples.iter().map(f).collect::<Vec<_>>();
        println!(
            "design-level disagreements per seed triple (1-3, 4-6, ...): {:?}",
            column(|t| t.design)
        );
        println!("  of which avoidable: {:?}", column(|t| t.avoidable));
        println!(
            "variants whose seeds split within the triple: {:?}",
            column(|t| t.split)
        );
        println!(
            "flights that disagree per triple: {:?}",
            column(|t| t.flights)
        );
    }
    if let Some(path) = cache_path {
        let text: String = cache.iter().map(|(k, v)| format!("{k}\t{v}\n")).collect();
        omniad_io::write_atomic(&path, text.as_bytes())?;
    }
    Ok(())
}
