//! The frame around the views: tab bar, status line, help overlay, and
//! the "terminal too small" notice.

use crate::app::{App, ViewId, MIN_SIZE};
use crate::help;
use crate::kite::view::KiteWidget;
use crate::sim::view::SimWidget;
use crate::sphere::render::SphereWidget;
use crate::telemetry::view::TelemetryWidget;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Flex, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget, Wrap};

impl Widget for &App {
    fn render(self, area: Rect, buf: &mut Buffer) {
        if area.width < MIN_SIZE.0 || area.height < MIN_SIZE.1 {
            return render_too_small(area, buf);
        }
        let [tabs, body, status] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Fill(1),
            Constraint::Length(1),
        ])
        .areas(area);
        render_tabs(self, tabs, buf);
        render_view(self, body, buf);
        render_status(self, status, buf);
        if self.help {
            render_help(self, body, buf);
        }
    }
}

fn render_too_small(area: Rect, buf: &mut Buffer) {
    let text = format!(
        "terminal too small: {}x{}, need {}x{}",
        area.width, area.height, MIN_SIZE.0, MIN_SIZE.1
    );
    Paragraph::new(text)
        .wrap(Wrap { trim: true })
        .render(area, buf);
}

fn render_tabs(app: &App, area: Rect, buf: &mut Buffer) {
    let mut spans = vec![Span::styled("OmniAD ", app.theme.title())];
    for (i, v) in ViewId::ALL.iter().enumerate() {
        let text = format!(" {} {} ", i + 1, v.title());
        if *v == app.view {
            spans.push(Span::styled(
                format!("[{}]", text.trim()),
                app.theme.selected(),
            ));
        } else {
            spans.push(Span::raw(text));
        }
    }
    Paragraph::new(Line::from(spans)).render(area, buf);
}

fn render_view(app: &App, area: Rect, buf: &mut Buffer) {
    let theme = app.theme;
    match app.view {
        ViewId::Sphere => SphereWidget {
            view: &app.sphere,
            theme,
        }
        .render(area, buf),
        ViewId::Kite => KiteWidget {
            view: &app.kite,
            theme,
        }
        .render(area, buf),
        ViewId::Sim => SimWidget {
            view: &app.sim,
            theme,
        }
        .render(area, buf),
        ViewId::Telemetry => TelemetryWidget {
            view: &app.telemetry,
            theme,
        }
        .render(area, buf),
    }
}

fn render_status(app: &App, area: Rect, buf: &mut Buffer) {
    let s = app.stats;
    let rate = if s.fps > 0.0 {
        format!("{:.0} fps", s.fps)
    } else {
        "-- fps".into()
    };
    let idle = if app.animating() { "" } else { " idle" };
    let left = Line::from(vec![
        Span::styled("?", app.theme.key()),
        Span::raw(" help  "),
        Span::styled("q", app.theme.key()),
        Span::raw(" quit  "),
        Span::styled("Tab", app.theme.key()),
        Span::raw(" view"),
    ]);
    let right = format!("{rate} draw {:.1} ms{idle}", s.draw_ms);
    let [l, r] = Layout::horizontal([Constraint::Fill(1), Constraint::Length(right.len() as u16)])
        .areas(area);
    Paragraph::new(left).render(l, buf);
    Paragraph::new(Line::styled(right, app.theme.dim())).render(r, buf);
}

fn render_help(app: &App, area: Rect, buf: &mut Buffer) {
    let keys = help::keys(app.view);
    let mut lines: Vec<Line> = Vec::new();
    for (k, what) in help::GLOBAL.iter().chain(keys) {
        lines.push(Line::from(vec![
            Span::styled(format!("{k:>18} "), app.theme.key()),
            Span::raw(*what),
        ]));
    }
    let h = (lines.len() as u16 + 2).min(area.height);
    let w = 64.min(area.width);
    let [v] = Layout::vertical([Constraint::Length(h)])
        .flex(Flex::Center)
        .areas(area);
    let [r] = Layout::horizontal([Constraint::Length(w)])
        .flex(Flex::Center)
        .areas(v);
    Clear.render(r, buf);
    let title = format!(" keys: {} ", app.view.title());
    Paragraph::new(lines)
        .block(Block::bordered().title(Line::styled(title, app.theme.title())))
        .render(r, buf);
}
