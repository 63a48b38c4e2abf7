//! Verdict vs flight on variants of kite files (issue 17's robustness
//! check): each file at its own pitch and string offset, pitched by
//! `--pitch` degrees, and with the offset moved by `--offset` metres, each
//! flown 60 s in 1 m/s gusts on seeds 1-3.
//! `cargo run --release -p omniad-kite --example agreement -- data/kites/*.toml`
//! prints one row per variant (verdict, largest growth rate, the gust
//! response's predicted lowest line elevation / largest spin, each seed's
//! outcome, `*` where it disagrees) and the count of disagreements;
//! `WHY=1` prints each disagreement's flight (mean and lowest elevation,
//! largest spin) on stderr.

use omniad_kite::{check, flight, spec::StringSpec, Design, Library};

const PITCHES: [f64; 4] = [-10.0, -5.0, 5.0, 10.0];
const OFFSETS: [f64; 4] = [-0.10, -0.03, 0.03, 0.10];

fn variants(d: &Design) -> anyhow::Result<Vec<(String, Design)>> {
    let base = check::check(d, None)?.attachment_offset;
    let mut out = vec![("file".to_string(), d.clone())];
    for p in PITCHES {
        let mut v = d.clone();
        v.spec.orientation[1] += p;
        // Keep the file's offset (a pitch change moves the eq. 16 line).
        v.spec.string = StringSpec {
            gamma: None,
            offset: Some(base),
            length: d.spec.string.length,
        };
        out.push((format!("pitch {p:+.0}"), v));
    }
    for o in OFFSETS {
        let mut v = d.clone();
        v.spec.string = StringSpec {
            gamma: None,
            offset: Some(base + o),
            length: d.spec.string.length,
        };
        out.push((format!("offset {o:+.2}"), v));
    }
    Ok(out)
}

fn main() -> anyhow::Result<()> {
    let files: Vec<String> = std::env::args().skip(1).collect();
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
            for seed in 1..=3 {
                let opts = flight::FlightOptions {
                    seed,
                    ..Default::default()
                };
                let (outcome, why) = match flight::fly(&v, &opts) {
                    Ok(f) => (
                        format!("{:?}", f.outcome).to_lowercase(),
                        format!(
                            "{} (elev mean {:.0}°, min {:.0}°, spin <= {:.1})",
                            f.reason, f.mean_elevation_deg, f.min_elevation_deg, f.max_spin
                        ),
                    ),
                    Err(e) => ("crashes".to_string(), format!("{e}")),
                };
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
            println!("{row}");
        }
    }
    println!("{bad} of {total} flights disagree ({stable} called stable, {flies} flew)");
    Ok(())
}
