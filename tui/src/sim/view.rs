//! Drawing the falling bodies: side (x-z) and top (x-y) projections in
//! braille, and the control panel.

use super::tethered::Tethered;
use super::world::{HALF_WIDTH, SPAWN_Z};
use super::SimView;
use crate::theme::Theme;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CLine, Points};
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};

/// The simulation view as a widget.
pub struct SimWidget<'a> {
    /// State.
    pub view: &'a SimView,
    /// Look.
    pub theme: Theme,
}

impl Widget for SimWidget<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let [panels, controls] =
            Layout::vertical([Constraint::Fill(1), Constraint::Length(4)]).areas(area);
        let [side, top] = Layout::horizontal([Constraint::Fill(1); 2]).areas(panels);
        if let Some(k) = &self.view.kite {
            render_kite(k, Proj::Side, self.theme, side, buf);
            render_kite(k, Proj::Top, self.theme, top, buf);
            return render_kite_controls(self.view, k, self.theme, controls, buf);
        }
        render_side(self.view, self.theme, side, buf);
        render_top(self.view, self.theme, top, buf);
        render_controls(self.view, self.theme, controls, buf);
    }
}

const X_RANGE: f64 = 2.0 * HALF_WIDTH;

fn render_side(v: &SimView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let pts: Vec<(f64, f64)> = v
        .world
        .bodies
        .iter()
        .map(|s| (s.position.x, s.position.z))
        .collect();
    Canvas::default()
        .block(Block::bordered().title(Line::styled(" side x-z ", theme.title())))
        .marker(Marker::Braille)
        .x_bounds([-X_RANGE, X_RANGE])
        .y_bounds([0.0, SPAWN_Z.1])
        .paint(|ctx| {
            ctx.draw(&CLine::new(
                -X_RANGE,
                0.0,
                X_RANGE,
                0.0,
                theme.dim().fg.unwrap_or_default(),
            ));
            ctx.draw(&Points {
                coords: &pts,
                color: theme.series(0).fg.unwrap_or_default(),
            });
        })
        .render(area, buf);
}

fn render_top(v: &SimView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let pts: Vec<(f64, f64)> = v
        .world
        .bodies
        .iter()
        .map(|s| (s.position.x, s.position.y))
        .collect();
    Canvas::default()
        .block(Block::bordered().title(Line::styled(" top x-y ", theme.title())))
        .marker(Marker::Braille)
        .x_bounds([-X_RANGE, X_RANGE])
        .y_bounds([-X_RANGE, X_RANGE])
        .paint(|ctx| {
            ctx.draw(&Points {
                coords: &pts,
                color: theme.series(1).fg.unwrap_or_default(),
            })
        })
        .render(area, buf);
}

fn render_controls(v: &SimView, theme: Theme, area: Rect, buf: &mut Buffer) {
    let p = v.params;
    let model = v.model_line();
    let (l0, m0) = v.main().map_or((0.0, 0.0), |m| {
        (
            m.coefficients.reference_length(),
            m.coefficients.body.map_or(0.0, |b| b.mass),
        )
    });
    let k = |s: &'static str| Span::styled(s, theme.key());
    let state = if v.running {
        "▶ running"
    } else {
        "⏸ paused"
    };
    let lines = vec![
        Line::from(vec![
            Span::styled(state, theme.title()),
            Span::raw(format!(
                "  t {:.1} s  bodies {}  landed {}  step {:.1} ms",
                v.world.time,
                v.world.bodies.len(),
                v.world.landed,
                v.step_ms
            )),
        ]),
        Line::from(vec![
            Span::raw(format!("ρ {:.3} kg/m³ ", p.air_density)),
            k("d/D"),
            Span::raw(format!("  L {:.3} m ", l0 * p.size)),
            k("s/S"),
            Span::raw(format!(
                "  M {:.2} g (×{:.2}) ",
                1000.0 * m0 * p.mass_scale,
                p.mass_scale
            )),
            k("w/W"),
        ]),
        Line::from(vec![
            Span::raw(format!("model {model} ")),
            k("o"),
            Span::raw("  run/pause "),
            k("space"),
            Span::raw(" step "),
            k("."),
            Span::raw(" bodies "),
            k("+/-"),
            Span::raw(" reset "),
            k("0"),
        ]),
    ];
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .block(Block::new())
        .render(area, buf);
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Proj {
    Side,
    Top,
}

fn flat(p: &nalgebra::Vector3<f64>, proj: Proj) -> (f64, f64) {
    match proj {
        Proj::Side => (p.x, p.z),
        Proj::Top => (p.x, p.y),
    }
}

/// The tethered kite: line from the anchor, the kite's trail, and the
/// kite as a marker.
fn render_kite(k: &Tethered, proj: Proj, theme: Theme, area: Rect, buf: &mut Buffer) {
    let title = if proj == Proj::Side {
        " kite side x-z, wind → "
    } else {
        " kite top x-y "
    };
    let line = k.flight.line();
    let r = line.length * 1.2;
    let (ylo, yhi) = if proj == Proj::Side {
        (-0.5, r)
    } else {
        (-r / 2.0, r / 2.0)
    };
    let trail: Vec<(f64, f64)> = k.trail.iter().map(|p| flat(p, proj)).collect();
    let (x, y) = flat(&k.position(), proj);
    let (ax, ay) = flat(&line.anchor, proj);
    Canvas::default()
        .block(Block::bordered().title(Line::styled(title, theme.title())))
        .marker(Marker::Braille)
        .x_bounds([-1.0, r])
        .y_bounds([ylo, yhi])
        .paint(|ctx| {
            ctx.draw(&Points {
                coords: &trail,
                color: theme.dim().fg.unwrap_or_default(),
            });
            ctx.draw(&CLine::new(
                ax,
                ay,
                x,
                y,
                theme.series(0).fg.unwrap_or_default(),
            ));
            ctx.print(ax, ay, "▲");
            ctx.print(x, y, Line::styled("◆", theme.series(1)));
        })
        .render(area, buf);
}

fn render_kite_controls(v: &SimView, k: &Tethered, theme: Theme, area: Rect, buf: &mut Buffer) {
    let w = k.flight.wind_now();
    let key = |s: &'static str| Span::styled(s, theme.key());
    let state = if v.running {
        "▶ running"
    } else {
        "⏸ paused"
    };
    let p = k.position();
    let lines = vec![
        Line::from(vec![
            Span::styled(state, theme.title()),
            Span::raw(format!(
                "  t {:.1} s  kite at ({:+.1} {:+.1} {:+.1}) m  crashes {}",
                k.time, p.x, p.y, p.z, k.crashes
            )),
        ]),
        Line::from(vec![
            Span::raw(format!("wind {:.1} m/s (now {:.1}) ", k.wind, w.norm())),
            key("u/U"),
            Span::raw(format!("  gusts ±{:.0}% ", 100.0 * k.gust)),
            key("g/G"),
            Span::raw(format!("  line {:.0} m", k.flight.line().length)),
        ]),
        Line::from(vec![
            Span::raw("bodies "),
            key("k"),
            Span::raw("  run/pause "),
            key("space"),
        ]),
    ];
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .render(area, buf);
}
