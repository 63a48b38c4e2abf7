//! The gust response's size, predicted against flown (issue 17, stop 19):
//! for a kite file (optionally its string offset moved by `--offset`
//! metres or its pitch changed by `--pitch` degrees, as the agreement
//! example's variants), at gust strengths G = 0.25, 0.5, 1 m/s, the
//! standard deviation of the line elevation and of `|Ω|` from the
//! small-gust linearisation and from the equivalent linearisation at the
//! gusts' amplitude ([`omniad_kite::gusts::response_to`]), beside the
//! flights' own: RMS about the rest elevation (and RMS `|Ω|`) over the
//! judged second half of 60 s `kite fly` runs, pooled over seeds 1-12
//! (crashed runs left out and counted).
//! `cargo run --release -p omniad-kite --example sigma -- data/kites/box-three-cell.toml --offset 0.10`

use omniad_kite::{check, flight, gusts, launch, linearise, spec::StringSpec, Design, Library};

const GUSTS: [f64; 3] = [0.25, 0.5, 1.0];
const SEEDS: u64 = 12;

fn variant(path: &str, args: &[String]) -> anyhow::Result<Design> {
    let library = Library::load(&omniad_kite::library::default_dir())?;
    let mut d = Design::load(std::path::Path::new(path), &library)?;
    let base = check::check(&d, None)?.attachment_offset;
    let mut offset = 0.0;
    for pair in args.chunks(2) {
        let value: f64 = pair.get(1).map_or(Ok(0.0), |v| v.parse())?;
        match pair.first().map(String::as_str) {
            Some("--offset") => offset = value,
            Some("--pitch") => d.spec.orientation[1] += value,
            other => anyhow::bail!("unknown argument {other:?}"),
        }
    }
    d.spec.string = StringSpec {
        gamma: None,
        offset: Some(base + offset),
        length: d.spec.string.length,
    };
    Ok(d)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .ok_or_else(|| anyhow::anyhow!("usage: sigma FILE [--offset M] [--pitch DEG]"))?;
    let d = variant(path, &args[1..])?;
    let steady = launch::launch(
        &d,
        &flight::FlightOptions {
            gust: 0.0,
            ..Default::default()
        },
    )?;
    let eq = *steady.state();
    let a = linearise::state_matrix(&steady, &eq);
    let b = linearise::input_matrix(&steady, &eq);
    let rest = steady.line().elevation_deg(&eq);
    println!("{} {:?}: rest {rest:.1} deg", d.spec.name, &args[1..]);
    println!("G m/s | elevation sigma deg: linear / equivalent (iterations) / flown | |Omega| rms rad/s: linear / equivalent / flown | crashed");
    for g in GUSTS {
        let r = gusts::response_to(&steady, &eq, &a, &b, None, g);
        let (mut e2, mut s2, mut n, mut crashed) = (0.0, 0.0, 0usize, 0);
        for seed in 1..=SEEDS {
            let opts = flight::FlightOptions {
                gust: g,
                seed,
                ..Default::default()
            };
            let f = flight::fly(&d, &opts)?;
            if f.crash_time.is_some() {
                crashed += 1;
                continue;
            }
            for s in f.trace.iter().filter(|s| s.t >= opts.seconds / 2.0) {
                e2 += (s.elevation_deg - rest).powi(2);
                s2 += s.spin * s.spin;
                n += 1;
            }
        }
        let n = n.max(1) as f64;
        println!(
            "{g:5} | {:6.2} / {:6.2} ({:?}) / {:6.2} | {:5.3} / {:5.3} / {:5.3} | {crashed}",
            r.sigma_elevation_linear_deg,
            r.sigma_elevation_deg,
            r.equivalent_iterations,
            (e2 / n).sqrt(),
            r.sigma_spin_linear,
            r.sigma_spin,
            (s2 / n).sqrt()
        );
    }
    Ok(())
}
