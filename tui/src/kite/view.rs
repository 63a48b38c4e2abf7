//! Drawing the kite design view: primitive list, the selected
//! primitive's numbers, equilibrium numbers and the eigenvalue bars.

use super::bar::eigen_bar;
use super::drawing::{render_drawing, Projection};
use super::dynamics;
use super::{KiteView, Tool};
use crate::theme::Theme;
use omniad_kite::check::{AxisReport, CheckReport};
use omniad_kite::spec::KiteSpec;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};

/// The kite view as a widget.
pub struct KiteWidget<'a> {
    /// State.
    pub view: &'a KiteView,
    /// Look.
    pub theme: Theme,
}

impl Widget for KiteWidget<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (v, theme) = (self.view, self.theme);
        if let Some(e) = &v.load_error {
            return render_load_error(v, e, theme, area, buf);
        }
        let [left, right] =
            Layout::horizontal([Constraint::Percentage(45), Constraint::Percentage(55)])
                .areas(area);
        let rows = (v.spec.primitives.len() as u16 + 2).clamp(3, 10);
        let [list, detail, side] = Layout::vertical([
            Constraint::Length(rows),
            Constraint::Length(8),
            Constraint::Fill(1),
        ])
        .areas(left);
        render_list(v, theme, list, buf);
        render_detail(v, theme, detail, buf);
        render_drawing(v, Projection::Side, theme, side, buf);
        // The dynamic panel sits under the static eigenvalues; on a short
        // terminal it takes the top projection's place.
        let dyn_h = dynamics::height(v);
        let both = right.height >= 17 + dyn_h + 8;
        let [eq, eig, modes, top] = Layout::vertical([
            Constraint::Length(9),
            Constraint::Length(8),
            Constraint::Length(if both { dyn_h } else { 0 }),
            Constraint::Fill(1),
        ])
        .areas(right);
        let modes = if both { modes } else { top };
        match &v.analysis {
            Ok(a) => {
                render_equilibrium(v, a, theme, eq, buf);
                render_eigen(a, theme, eig, buf);
            }
            Err(e) => Paragraph::new(format!("no equilibrium: {e}"))
                .wrap(Wrap { trim: true })
                .block(Block::bordered().title(" equilibrium "))
                .render(eq.union(eig), buf),
        }
        if both {
            render_drawing(v, Projection::Top, theme, top, buf);
        }
        dynamics::render_dynamics(v, theme, modes, buf);
    }
}

fn v3(v: &[f64; 3], prec: usize) -> String {
    format!("({:+.p$} {:+.p$} {:+.p$})", v[0], v[1], v[2], p = prec)
}

/// A kite file that did not load: the error, and that `w` will not save
/// over it.
fn render_load_error(v: &KiteView, error: &str, theme: Theme, area: Rect, buf: &mut Buffer) {
    let lines = vec![
        Line::styled(format!("cannot open kite file {}", v.path), theme.bad()),
        Line::raw(error.to_string()),
        Line::raw(""),
        Line::styled(
            "Nothing is shown or saved for it (w will not write over it); fix the file and start again.",
            theme.dim(),
        ),
        Line::styled(v.message.clone(), theme.dim()),
    ];
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(Block::bordered().title(Line::styled(" kite file ", theme.title())))
        .render(area, buf);
}

fn render_list(v: &KiteView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let title = format!(" {} · primitives ", v.spec.name);
    let mut lines = Vec::new();
    for (i, p) in v.spec.primitives.iter().enumerate() {
        let sel = i == v.selected;
        let mark = if sel { "▶ " } else { "  " };
        let [a, b, c] = p.size;
        let text = format!(
            "{mark}{:<8} {:<5} {a:.2}×{b:.2}×{c:.2}",
            p.name,
            p.kind.name()
        );
        lines.push(Line::styled(
            text,
            if sel { theme.selected() } else { Style::new() },
        ));
    }
    let skip = v
        .selected
        .saturating_sub(area.height.saturating_sub(3) as usize);
    Paragraph::new(lines)
        .scroll((skip as u16, 0))
        .block(Block::bordered().title(Line::styled(title, theme.title())))
        .render(area, buf);
}

fn render_detail(v: &KiteView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let Some(p) = v.spec.primitives.get(v.selected) else {
        return;
    };
    let row = |label: &'static str, t: Tool, a: &[f64; 3], unit: &'static str| {
        let mut spans = vec![Span::styled(format!("{label:<4}"), theme.dim())];
        for (i, x) in a.iter().enumerate() {
            let active = v.tool == t && v.axis == i;
            let st = if active {
                theme.selected()
            } else {
                Style::new()
            };
            spans.push(Span::styled(format!(" {}{x:+.2}", ["x", "y", "z"][i]), st));
        }
        spans.push(Span::styled(format!(" {unit}"), theme.dim()));
        Line::from(spans)
    };
    let lines = vec![
        row("pos", Tool::Move, &p.position, "m"),
        row("rot", Tool::Rotate, &p.rotation, "°"),
        row("size", Tool::Scale, &p.size, "m"),
        Line::from(vec![
            Span::styled("tool ", theme.dim()),
            Span::styled(v.tool.name(), theme.title()),
            Span::styled(
                format!(" axis {}", ["x", "y", "z"][v.axis.min(2)]),
                theme.title(),
            ),
        ]),
        Line::from(vec![
            Span::styled("rods ", theme.dim()),
            Span::raw(joined_rods(&v.spec, &p.name)),
        ]),
        Line::styled(v.message.clone(), theme.dim()),
    ];
    Paragraph::new(lines)
        .block(Block::bordered().title(Line::styled(format!(" {} ", p.name), theme.title())))
        .render(area, buf);
}

/// The `[[rod]]`s with an end on primitive `name`, as a builder reads
/// them: `rod[0] +x+y-z→rear -x-y-z` (this primitive's corner, then the
/// other end). Rods by coordinates name no primitive and are not listed.
fn joined_rods(spec: &KiteSpec, name: &str) -> String {
    let out: Vec<String> = (spec.rods.iter().enumerate())
        .flat_map(|(k, r)| {
            [(&r.from, &r.to), (&r.to, &r.from)]
                .into_iter()
                .filter(|(own, _)| own.primitive() == Some(name))
                .map(move |(own, other)| {
                    let mine = own.describe();
                    let mine = mine.strip_prefix(name).unwrap_or(&mine).trim_start();
                    format!("rod[{k}] {mine}→{}", other.describe())
                })
        })
        .collect();
    if out.is_empty() {
        "none named".into()
    } else {
        out.join(", ")
    }
}

fn render_equilibrium(v: &KiteView, a: &CheckReport, theme: Theme, area: Rect, buf: &mut Buffer) {
    let d = &v.spec;
    let (ok, bad) = (theme.good(), theme.bad());
    let pulls = if a.pulls_down {
        Span::styled("✓ pulls down", ok)
    } else {
        Span::styled("✗ does not pull down", bad)
    };
    let lines = vec![
        Line::raw(format!(
            "wind {:.1} m/s ρ{:.2} rpy {:+.0} {:+.0} {:+.0}° {:.1} g",
            d.wind.speed,
            d.wind.air_density,
            d.orientation[0],
            d.orientation[1],
            d.orientation[2],
            a.mass * 1000.0
        )),
        Line::from(vec![
            Span::raw(format!("tension {} N ", v3(&a.tension_world, 2))),
            pulls,
        ]),
        Line::raw(format!("|T| {:.3} N", a.tension)),
        Line::raw(format!("torque {} N·m", v3(&a.unbalanced_torque, 4))),
        Line::raw(format!("attach P {} m", v3(&a.attachment, 3))),
        Line::raw(format!(
            "γ {:.4} m/N  offset {:+.2} m",
            a.gamma, a.attachment_offset
        )),
    ];
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(Block::bordered().title(Line::styled(" equilibrium ", theme.title())))
        .render(area, buf);
}

fn render_eigen(a: &CheckReport, theme: Theme, area: Rect, buf: &mut Buffer) {
    let scale = a
        .axes
        .iter()
        .map(|x| x.eigenvalue.abs())
        .fold(0.0, f64::max);
    let half = (area.width.saturating_sub(30) / 2).clamp(2, 20) as usize;
    let mut lines = Vec::new();
    for (
        i,
        AxisReport {
            eigenvalue, axis, ..
        },
    ) in a.axes.iter().enumerate()
    {
        let val = *eigenvalue;
        let (st, verdict) = if val < 0.0 {
            (theme.good(), "✓ stable")
        } else {
            (theme.bad(), "✗ UNSTABLE")
        };
        lines.push(Line::from(vec![
            Span::raw(format!("λ{} {val:+.4} ", i + 1)),
            Span::styled(eigen_bar(val, scale, half), st),
            Span::styled(verdict, st),
        ]));
        lines.push(Line::styled(
            format!("   axis {}", v3(axis, 2)),
            theme.dim(),
        ));
    }
    let all = a.axes.iter().all(|x| x.eigenvalue < 0.0);
    let title = if all {
        " stability N·m/rad: stable "
    } else {
        " stability N·m/rad: unstable "
    };
    Paragraph::new(lines)
        .block(Block::bordered().title(Line::styled(
            title,
            if all { theme.good() } else { theme.bad() },
        )))
        .render(area, buf);
}
