//! The SVG text of a [`Figure`].

use crate::axis::{nice_ticks, Range};
use crate::{Figure, Style};
use std::fmt::Write as _;

/// Colour-blind-safe palette (Okabe-Ito).
const PALETTE: [&str; 7] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000",
];
/// Margins: left, right, top, bottom, px.
const MARGIN: (f64, f64, f64, f64) = (70.0, 20.0, 40.0, 50.0);

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    }
}

/// Renders `fig` at `w` x `h` pixels.
pub fn render(fig: &Figure, w: f64, h: f64) -> String {
    let pts = || fig.series.iter().flat_map(|s| s.points.iter());
    let (xr, xt) = nice_ticks(Range::of(pts().map(|p| p.0)), 6);
    let (yr, yt) = nice_ticks(Range::of(pts().map(|p| p.1)), 5);
    let (ml, mr, mt, mb) = MARGIN;
    let (x0, x1, y0, y1) = (ml, w - mr, h - mb, mt);
    let px = |x: f64| xr.map(x, x0, x1);
    let py = |y: f64| yr.map(y, y0, y1);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        escape(&fig.title)
    );
    for t in &xt {
        let x = px(*t);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{y0}" x2="{x:.1}" y2="{y1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            y0 + 16.0,
            label(*t)
        );
    }
    for t in &yt {
        let y = py(*t);
        let _ = writeln!(
            s,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{x1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            x0 - 6.0,
            y + 4.0,
            label(*t)
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{x0}" y="{y1}" width="{}" height="{}" fill="none" stroke="#333"/>"##,
        x1 - x0,
        y0 - y1
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        (x0 + x1) / 2.0,
        h - 12.0,
        escape(&fig.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(16 {}) rotate(-90)" text-anchor="middle">{}</text>"#,
        (y0 + y1) / 2.0,
        escape(&fig.y_label)
    );
    for (i, series) in fig.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let finite = series
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite());
        match series.style {
            Style::Line => {
                let path: Vec<String> = finite
                    .map(|p| format!("{:.1},{:.1}", px(p.0), py(p.1)))
                    .collect();
                let _ = writeln!(
                    s,
                    r#"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/>"#,
                    path.join(" ")
                );
            }
            Style::Points => {
                for p in finite {
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{:.1}" cy="{:.1}" r="1.8" fill="{colour}" fill-opacity="0.6"/>"#,
                        px(p.0),
                        py(p.1)
                    );
                }
            }
        }
        let ly = y1 + 16.0 + 16.0 * i as f64;
        let _ = writeln!(
            s,
            r#"<rect x="{:.1}" y="{:.1}" width="12" height="4" fill="{colour}"/><text x="{:.1}" y="{:.1}">{}</text>"#,
            x1 - 170.0,
            ly - 6.0,
            x1 - 152.0,
            ly,
            escape(&series.name)
        );
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use crate::{Figure, Series};

    #[test]
    fn a_figure_is_a_well_formed_svg_with_every_series() {
        let fig = Figure::new("force <measured>", "t (s)", "F (N)")
            .with(Series::line(
                "measured",
                vec![(0.0, 1.0), (1.0, 3.0), (2.0, f64::NAN)],
            ))
            .with(Series::points("model", vec![(0.5, 2.0)]));
        let svg = fig.to_svg();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("force &lt;measured&gt;"), "title escaped");
        assert_eq!(svg.matches("<polyline").count(), 1);
        assert_eq!(svg.matches("<circle").count(), 1);
        assert!(svg.contains(">measured<") && svg.contains(">model<"));
        assert!(!svg.contains("NaN"), "non-finite points skipped");
    }
}
