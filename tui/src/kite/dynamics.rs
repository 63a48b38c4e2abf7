//! The kite view's dynamic panel, beside §7's static eigenvalues: the
//! modes of the linearised tethered kite (`kite check`'s `modes`, from
//! [`omniad_kite::modes`]) as a bar per mode of its growth rate σ (1/s,
//! red when it grows), with frequency, damping and the motion in words;
//! and the check's warnings (primitives overlapping along the wind, a
//! frame in pieces) above them. Numbers are the check's; nothing is
//! computed here.

use super::bar::eigen_bar;
use super::KiteView;
use crate::theme::Theme;
use omniad_kite::check::{CheckReport, Verdict};
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Widget};

/// The check's warnings about the geometry, one line each: pairs of
/// primitives overlapping along the wind (one shadows the other, which
/// the paper's sum of independent primitives does not model) and parts
/// of the frame not joined to the rest, and rods of an old file whose
/// ends are coordinates rather than named corners (they do not follow a
/// moved primitive).
pub fn warnings(a: &CheckReport) -> Vec<String> {
    let mut out: Vec<String> = a
        .overlaps
        .iter()
        .map(|[p, q]| format!("⚠ overlap along the wind: {p} shadows {q}"))
        .collect();
    if !a.unjoined.is_empty() {
        out.push(format!("⚠ not joined: {}", a.unjoined.join(", ")));
    }
    if !a.joined_by_coordinates.is_empty() {
        out.push(format!(
            "⚠ joined by coordinates, not named corners: {}",
            a.joined_by_coordinates.join(", ")
        ));
    }
    out
}

/// Height the panel wants: warnings, optimiser lines, modes, border.
pub fn height(v: &KiteView) -> u16 {
    let n = match &v.analysis {
        Ok(a) => warnings(a).len() + a.modes.modes.len().max(1) + 1,
        Err(_) => 1,
    };
    (n + v.optimised.len() + 2).min(16) as u16
}

/// Draws the panel.
pub fn render_dynamics(v: &KiteView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let mut lines: Vec<Line> = Vec::new();
    let Ok(a) = &v.analysis else {
        return;
    };
    for w in warnings(a) {
        lines.push(Line::styled(w, theme.bad()));
    }
    let m = &a.modes;
    let verdict = Line::styled(
        format!("verdict: {}", a.verdict.name()),
        if a.verdict == Verdict::Stable {
            theme.good()
        } else {
            theme.bad()
        },
    );
    lines.push(verdict);
    if m.equilibrium.is_none() {
        lines.push(Line::styled("no equilibrium on the line", theme.bad()));
    }
    let scale = m.modes.iter().map(|x| x.real.abs()).fold(0.0, f64::max);
    let half = (area.width.saturating_sub(50) / 2).clamp(2, 12) as usize;
    for mode in &m.modes {
        let st = if mode.stable {
            theme.good()
        } else {
            theme.bad()
        };
        let kind = if mode.imag > 0.0 {
            format!("{:.2} Hz ζ{:+.2}", mode.frequency_hz, mode.damping_ratio)
        } else {
            "real".to_string()
        };
        lines.push(Line::from(vec![
            Span::raw(format!("σ {:+.2} ", mode.real)),
            Span::styled(eigen_bar(mode.real, scale, half), st),
            Span::raw(format!("{kind:<15} ")),
            Span::styled(mode.motion.clone(), theme.dim()),
        ]));
    }
    for l in &v.optimised {
        lines.push(Line::styled(l.clone(), theme.dim()));
    }
    let title = if m.max_growth_rate.is_finite() {
        format!(" modes on the line, σ 1/s (max {:+.3}) ", m.max_growth_rate)
    } else {
        " modes on the line, σ 1/s ".to_string()
    };
    Paragraph::new(lines)
        .block(Block::bordered().title(Line::styled(
            title,
            if m.stable { theme.good() } else { theme.bad() },
        )))
        .render(area, buf);
}
