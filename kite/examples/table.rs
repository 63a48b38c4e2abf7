//! The static-verdict vs simulated-outcome table over kite files:
//! `cargo run --release -p omniad-kite --example table -- data/kites/*.toml`.
//! Options (before the files): `--seconds S`, `--gust G`, `--seed N`.

use omniad_kite::{check, flight, trimming, Design, Library};

fn main() -> anyhow::Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut opts = flight::FlightOptions::default();
    while args.first().is_some_and(|a| a.starts_with("--")) {
        let flag = args.remove(0);
        let value: f64 = args
            .first()
            .ok_or_else(|| anyhow::anyhow!("{flag} needs a value"))?
            .parse()?;
        args.remove(0);
        match flag.as_str() {
            "--seconds" => opts.seconds = value,
            "--gust" => opts.gust = value,
            "--seed" => opts.seed = value as u64,
            _ => anyhow::bail!("unknown option {flag}"),
        }
    }
    let library = Library::load(&omniad_kite::library::default_dir())?;
    println!("| kite | mass g | pulls down | eigenvalues (N m/rad) | verdict | largest mode growth 1/s | trim | flight ({} s, gust {} m/s, seed {}) |", opts.seconds, opts.gust, opts.seed);
    println!("|---|---|---|---|---|---|---|---|");
    for path in &args {
        let design = match Design::load(std::path::Path::new(path), &library) {
            Ok(d) => d,
            Err(e) => {
                println!("| {path} | error: {e:#} |||||");
                continue;
            }
        };
        let c = check::check(&design, None)?;
        let eig: Vec<String> = c
            .axes
            .iter()
            .map(|a| format!("{:+.3}", a.eigenvalue))
            .collect();
        let t = trimming::trim(&design, None)?;
        let f = flight::fly(&design, &opts)?;
        let flight = match f.crash_time {
            Some(tc) => format!("crashes at {tc:.1} s"),
            None => format!(
                "{:?} (elev {:.0}°, min {:.0}°, spin ≤ {:.1})",
                f.outcome, f.mean_elevation_deg, f.min_elevation_deg, f.max_spin
            )
            .to_lowercase(),
        };
        println!(
            "| {} | {:.0} | {} | {} | {} | {:+.2} | {} | {} |",
            c.name,
            c.mass * 1e3,
            c.pulls_down,
            eig.join(" "),
            c.verdict.name(),
            c.modes.max_growth_rate,
            t.summary(),
            flight
        );
    }
    Ok(())
}
