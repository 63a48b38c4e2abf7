// scratch (not committed): linear gust prediction vs flight statistics
use omniad_kite::{check, flight, spec::StringSpec, Design, Library};
fn main() -> anyhow::Result<()> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let library = Library::load(&omniad_kite::library::default_dir())?;
    let mut d = Design::load(std::path::Path::new(&a[0]), &library)?;
    let base = check::check(&d, None)?.attachment_offset;
    let dp: f64 = a.get(1).map_or(0.0, |s| s.parse().unwrap());
    let doff: f64 = a.get(2).map_or(0.0, |s| s.parse().unwrap());
    d.spec.orientation[1] += dp;
    d.spec.string = StringSpec {
        gamma: None,
        offset: Some(base + doff),
        length: d.spec.string.length,
    };
    let c = check::check(&d, None)?;
    println!(
        "{} growth {:+.3}",
        c.verdict.name(),
        c.modes.max_growth_rate
    );
    if let Some(g) = &c.modes.gusts {
        println!("{g:?}");
    }
    for seed in 1..=3 {
        let f = flight::fly(
            &d,
            &flight::FlightOptions {
                seed,
                gust: std::env::var("GUST").map_or(1.0, |g| g.parse().unwrap()),
                seconds: std::env::var("SECS").map_or(60.0, |g| g.parse().unwrap()),
                ..Default::default()
            },
        )?;
        let half: Vec<_> = f.trace.iter().filter(|s| s.t >= f.seconds / 2.0).collect();
        let n = half.len() as f64;
        let m = half.iter().map(|s| s.elevation_deg).sum::<f64>() / n;
        let sd = (half
            .iter()
            .map(|s| (s.elevation_deg - m).powi(2))
            .sum::<f64>()
            / n)
            .sqrt();
        let all: Vec<_> = f.trace.iter().collect();
        let ma = all.iter().map(|s| s.elevation_deg).sum::<f64>() / all.len() as f64;
        let sda = (all
            .iter()
            .map(|s| (s.elevation_deg - ma).powi(2))
            .sum::<f64>()
            / all.len() as f64)
            .sqrt();
        let spin = (half.iter().map(|s| s.spin * s.spin).sum::<f64>() / n).sqrt();
        println!("seed {seed}: {:?} half mean {m:.1} sd {sd:.1} min {:.1}; all mean {ma:.1} sd {sda:.1}; spin rms {spin:.2} max {:.2}", f.outcome, f.min_elevation_deg, f.max_spin);
    }
    Ok(())
}
