//! Scans the attachment offset along the eq. (16) line and prints the
//! eigenvalues (development aid for choosing `string.offset`):
//! `cargo run -p omniad-kite --example scan -- FILE [PITCH_DEG...]`.

use omniad_kite::{check, spec::StringSpec, Design, Library};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let library = Library::load(&omniad_kite::library::default_dir())?;
    let path = args
        .first()
        .ok_or_else(|| anyhow::anyhow!("usage: scan FILE [PITCH...]"))?;
    let mut design = Design::load(std::path::Path::new(path), &library)?;
    let pitches: Vec<f64> = args.iter().skip(1).filter_map(|a| a.parse().ok()).collect();
    for pitch in if pitches.is_empty() {
        vec![design.spec.orientation[1]]
    } else {
        pitches
    } {
        design.spec.orientation[1] = pitch;
        for i in -2..=12 {
            let offset = i as f64 * 0.01;
            design.spec.string = StringSpec {
                gamma: None,
                offset: Some(offset),
                length: design.spec.string.length,
            };
            let c = check::check(&design, None)?;
            let e: Vec<String> = c
                .axes
                .iter()
                .map(|a| {
                    format!(
                        "{:+.3}@[{:+.2},{:+.2},{:+.2}]",
                        a.eigenvalue, a.axis[0], a.axis[1], a.axis[2]
                    )
                })
                .collect();
            println!("pitch {pitch:5.1} offset {offset:+.2}  P=[{:+.3},{:+.3},{:+.3}] elev {:.0} {:?} {}", c.attachment[0], c.attachment[1], c.attachment[2], c.line_elevation_deg, c.verdict, e.join(" "));
        }
    }
    Ok(())
}
