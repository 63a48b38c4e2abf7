//! Drawing telemetry: a header with time and replay state, then one
//! sparkline per quantity with its current value and range.

use super::series::Series;
use super::TelemetryView;
use crate::theme::Theme;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Sparkline, Widget};

/// The telemetry view as a widget.
pub struct TelemetryWidget<'a> {
    /// State.
    pub view: &'a TelemetryView,
    /// Look.
    pub theme: Theme,
}

impl Widget for TelemetryWidget<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let v = self.view;
        let [head, body, foot] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Fill(1),
            Constraint::Length(1),
        ])
        .areas(area);
        render_header(v, self.theme, head, buf);
        let rows = Layout::vertical(vec![Constraint::Fill(1); v.series.len()]).split(body);
        for (i, (s, r)) in v.series.iter().zip(rows.iter()).enumerate() {
            render_series(v, i, s, self.theme, *r, buf);
        }
        let note = if v.series.iter().any(|s| s.eigen) {
            "λ: stability eigenvalues from the firmware (✓ < 0 stable, ✗ unstable)"
        } else {
            "eigenvalues: replay firmware telemetry (omniad-tui --telemetry FILE.csv)"
        };
        Paragraph::new(Line::styled(note, self.theme.dim())).render(foot, buf);
    }
}

fn render_header(v: &TelemetryView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let t0 = v.time.first().copied().unwrap_or(0.0);
    let t = v.time.get(v.index()).copied().unwrap_or(0.0) - t0;
    let state = if v.playing { "▶" } else { "⏸" };
    Paragraph::new(Line::from(vec![
        Span::styled(format!("{state} ×{} ", v.speed), theme.title()),
        Span::raw(format!("t {t:.1}/{:.1} s  ", v.duration())),
        Span::styled(v.source.clone(), theme.dim()),
    ]))
    .render(area, buf);
}

fn render_series(
    v: &TelemetryView,
    i: usize,
    s: &Series,
    theme: Theme,
    area: Rect,
    buf: &mut Buffer,
) {
    let data: Vec<f64> = v.log.rows.iter().map(|r| s.value(r)).collect();
    let finite = || data.iter().copied().filter(|x| x.is_finite());
    let lo = finite().fold(f64::INFINITY, f64::min);
    let hi = finite().fold(f64::NEG_INFINITY, f64::max);
    let now = data.get(v.index()).copied().unwrap_or(f64::NAN);
    let mark = match (s.eigen, now < 0.0) {
        (false, _) => "",
        (true, true) => " ✓",
        (true, false) => " ✗",
    };
    let (p, u) = (precision(lo, hi), s.unit);
    let title = format!(" {} {now:.p$} {u}{mark}  [{lo:.p$}..{hi:.p$}] ", s.label);
    let block = Block::bordered().title(Line::styled(title, theme.series(i)));
    let inner = block.inner(area);
    block.render(area, buf);
    let end = v.index() + 1;
    let window = data
        .get(end.saturating_sub(inner.width as usize)..end)
        .unwrap_or(&[]);
    let span = if hi > lo { hi - lo } else { 1.0 };
    let bar = |x: &f64| {
        if x.is_finite() {
            1 + ((x - lo) / span * 99.0) as u64
        } else {
            0
        }
    };
    let bars: Vec<u64> = window.iter().map(bar).collect();
    Sparkline::default()
        .data(&bars)
        .max(100)
        .style(theme.series(i))
        .render(inner, buf);
}

/// Decimals that show a range `lo..hi` usefully.
fn precision(lo: f64, hi: f64) -> usize {
    let m = lo.abs().max(hi.abs());
    if m >= 100.0 {
        0
    } else if m >= 1.0 {
        1
    } else {
        3
    }
}
