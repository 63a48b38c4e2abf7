//! Drawing the coefficient sphere: braille dots dithered by the shaded
//! value (so shading survives `NO_COLOR`), colour on top when allowed,
//! arrow glyphs for lift or torque, and a probe readout.

use super::{coverage_cell, Mode, SphereView};
use crate::models::Model;
use crate::theme::Theme;
use nalgebra::{Rotation3, Vector3};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};

/// The sphere view as a widget.
pub struct SphereWidget<'a> {
    /// State.
    pub view: &'a SphereView,
    /// Look.
    pub theme: Theme,
}

impl Widget for SphereWidget<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let v = self.view;
        let second = v.models.get(v.compare_with).filter(|_| v.compare);
        match (v.models.first(), second) {
            (Some(a), Some(b)) => {
                let [l, r] = Layout::horizontal([Constraint::Fill(1); 2]).areas(area);
                render_stacked(v, a, self.theme, l, buf);
                render_stacked(v, b, self.theme, r, buf);
            }
            (Some(a), None) => render_single(v, a, self.theme, area, buf),
            _ => Paragraph::new("no model loaded").render(area, buf),
        }
    }
}

/// One model: sphere on the left, readout on the right (or below when
/// the area is tall and narrow).
fn render_single(v: &SphereView, m: &Model, theme: Theme, area: Rect, buf: &mut Buffer) {
    if area.width < 2 * area.height + 36 && area.height > 2 * READOUT_LINES {
        return render_stacked(v, m, theme, area, buf);
    }
    let sphere_w = (area.height * 2 + 2).min(area.width.saturating_sub(36));
    let [s, r] =
        Layout::horizontal([Constraint::Length(sphere_w), Constraint::Fill(1)]).areas(area);
    render_sphere(v, m, theme, s, buf);
    render_readout(v, m, theme, r, buf);
}

/// Lines of the probe readout.
const READOUT_LINES: u16 = 9;

/// Sphere above, readout below.
fn render_stacked(v: &SphereView, m: &Model, theme: Theme, area: Rect, buf: &mut Buffer) {
    let lines = READOUT_LINES.min(area.height / 2);
    let [s, r] = Layout::vertical([Constraint::Fill(1), Constraint::Length(lines)]).areas(area);
    render_sphere(v, m, theme, s, buf);
    render_readout(v, m, theme, r, buf);
}

/// The shaded quantity and the arrow vector at body direction `e`.
fn sample(m: &Model, mode: Mode, e: &Vector3<f64>) -> (f64, Vector3<f64>) {
    let c = &m.coefficients;
    let Some(dc) = c.at_direction(e) else {
        return (0.0, Vector3::zeros());
    };
    match mode {
        Mode::Force => {
            let along = dc.force.dot(e);
            (-along, dc.force - e * along)
        }
        Mode::Torque => (dc.torque.norm(), dc.torque),
        Mode::Coverage => {
            let cells = &c.provenance.coverage;
            let n = cells.get(coverage_cell(e, &c.pole())).copied().unwrap_or(0);
            (f64::from(n), Vector3::zeros())
        }
    }
}

/// Range of the shaded value over the sphere, and the largest arrow.
fn value_range(m: &Model, mode: Mode) -> (f64, f64, f64) {
    let (mut lo, mut hi, mut big) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for i in 0..12 {
        let th = std::f64::consts::PI * (f64::from(i) + 0.5) / 12.0;
        for j in 0..24 {
            let ph = std::f64::consts::TAU * f64::from(j) / 24.0;
            let e = Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            let (val, arrow) = sample(m, mode, &e);
            lo = lo.min(val);
            hi = hi.max(val);
            big = big.max(arrow.norm());
        }
    }
    if mode == Mode::Coverage {
        lo = 0.0;
    }
    (lo, hi, big)
}

/// Ordered-dither thresholds for the 2 x 4 braille dots.
const BAYER: [[f64; 2]; 4] = [[0.0, 4.0], [6.0, 2.0], [1.0, 5.0], [7.0, 3.0]];
/// Braille dot bits by (row, column).
const DOTS: [[u32; 2]; 4] = [[0x01, 0x08], [0x02, 0x10], [0x04, 0x20], [0x40, 0x80]];

/// Geometry of the disc in braille-dot units.
struct Disc {
    cx: f64,
    cy: f64,
    r: f64,
}

impl Disc {
    fn of(area: Rect) -> Self {
        let (w, h) = (f64::from(area.width) * 2.0, f64::from(area.height) * 4.0);
        Self {
            cx: w / 2.0,
            cy: h / 2.0,
            r: (w.min(h) / 2.0 - 1.0).max(0.5),
        }
    }
    /// Camera-frame point of dot (x, y), if on the front hemisphere.
    fn point(&self, x: f64, y: f64) -> Option<Vector3<f64>> {
        let (sx, sy) = ((x + 0.5 - self.cx) / self.r, -(y + 0.5 - self.cy) / self.r);
        let q = sx * sx + sy * sy;
        (q <= 1.0).then(|| Vector3::new(sx, sy, (1.0 - q).sqrt()))
    }
}

/// The shaded disc, outline, arrows and probe marker.
fn render_sphere(v: &SphereView, m: &Model, theme: Theme, area: Rect, buf: &mut Buffer) {
    let block = Block::bordered().title(Line::styled(format!(" {} ", m.label), theme.title()));
    let inner = block.inner(area);
    block.render(area, buf);
    if inner.width < 2 || inner.height < 2 {
        return;
    }
    let disc = Disc::of(inner);
    let inv = v.camera().inverse();
    let (lo, hi, big) = value_range(m, v.mode);
    let span = if hi > lo { hi - lo } else { 1.0 };
    for row in 0..inner.height {
        for col in 0..inner.width {
            shade_cell(
                &disc,
                &inv,
                (m, v.mode),
                (lo, span),
                (col, row),
                inner,
                theme,
                buf,
            );
        }
    }
    if v.arrows && v.mode != Mode::Coverage && big > 0.0 {
        draw_arrows(&disc, &inv, m, v.mode, big, inner, theme, buf);
    }
    draw_probe(v, &disc, inner, buf);
}

#[allow(clippy::too_many_arguments)]
fn shade_cell(
    disc: &Disc,
    inv: &Rotation3<f64>,
    (m, mode): (&Model, Mode),
    (lo, span): (f64, f64),
    (col, row): (u16, u16),
    inner: Rect,
    theme: Theme,
    buf: &mut Buffer,
) {
    let (x0, y0) = (f64::from(col) * 2.0, f64::from(row) * 4.0);
    let Some(centre) = disc.point(x0 + 0.5, y0 + 1.5) else {
        return outline_cell(disc, (x0, y0), (inner.x + col, inner.y + row), buf);
    };
    let (val, _) = sample(m, mode, &(inv * centre));
    let t = ((val - lo) / span).clamp(0.0, 1.0);
    let fill = 0.1 + 0.9 * t;
    let mut bits = 0u32;
    for (dy, (thr, dots)) in BAYER.iter().zip(DOTS).enumerate() {
        for dx in 0..2 {
            let inside = disc.point(x0 + dx as f64, y0 + dy as f64).is_some();
            let th = (thr.get(dx).copied().unwrap_or(0.0) + 0.5) / 8.0;
            if inside && fill > th {
                bits |= dots.get(dx).copied().unwrap_or(0);
            }
        }
    }
    if let Some(cell) = buf.cell_mut((inner.x + col, inner.y + row)) {
        cell.set_char(char::from_u32(0x2800 + bits).unwrap_or(' '));
        cell.set_style(theme.ramp(t));
    }
}

/// Dots of the silhouette in a cell outside the disc's sample centre.
fn outline_cell(disc: &Disc, (x0, y0): (f64, f64), pos: (u16, u16), buf: &mut Buffer) {
    let mut bits = 0u32;
    for (dy, dots) in DOTS.iter().enumerate() {
        for (dx, bit) in dots.iter().enumerate() {
            let (x, y) = (
                x0 + dx as f64 + 0.5 - disc.cx,
                y0 + dy as f64 + 0.5 - disc.cy,
            );
            let d = (x * x + y * y).sqrt();
            if (disc.r - 1.0..=disc.r).contains(&d) {
                bits |= bit;
            }
        }
    }
    if bits != 0 {
        if let Some(cell) = buf.cell_mut(pos) {
            cell.set_char(char::from_u32(0x2800 + bits).unwrap_or(' '));
        }
    }
}

/// One-cell arrow glyph for a screen-plane vector (x right, y up).
pub fn arrow_glyph(x: f64, y: f64) -> char {
    const G: [char; 8] = ['→', '↗', '↑', '↖', '←', '↙', '↓', '↘'];
    let oct = ((y.atan2(x) / std::f64::consts::FRAC_PI_4).round() as i64).rem_euclid(8);
    G.get(oct as usize).copied().unwrap_or('·')
}

#[allow(clippy::too_many_arguments)]
fn draw_arrows(
    disc: &Disc,
    inv: &Rotation3<f64>,
    m: &Model,
    mode: Mode,
    big: f64,
    inner: Rect,
    theme: Theme,
    buf: &mut Buffer,
) {
    let cam = inv.inverse();
    for row in (1..inner.height).step_by(3) {
        for col in (2..inner.width).step_by(5) {
            let Some(c) = disc.point(f64::from(col) * 2.0 + 0.5, f64::from(row) * 4.0 + 1.5) else {
                continue;
            };
            if c.z < 0.25 {
                continue;
            }
            let (_, a) = sample(m, mode, &(inv * c));
            let s = cam * a;
            if (s.x * s.x + s.y * s.y).sqrt() < 0.2 * big {
                continue;
            }
            if let Some(cell) = buf.cell_mut((inner.x + col, inner.y + row)) {
                cell.set_char(arrow_glyph(s.x, s.y));
                cell.set_style(theme.arrow());
            }
        }
    }
}

/// The probe marker `◆` where the probe direction faces the viewer.
fn draw_probe(v: &SphereView, disc: &Disc, inner: Rect, buf: &mut Buffer) {
    let c = v.camera() * v.probe();
    if c.z < 0.0 {
        return;
    }
    let x = (disc.cx + c.x * disc.r) / 2.0;
    let y = (disc.cy - c.y * disc.r) / 4.0;
    let (col, row) = (x.floor().max(0.0) as u16, y.floor().max(0.0) as u16);
    if col < inner.width && row < inner.height {
        if let Some(cell) = buf.cell_mut((inner.x + col, inner.y + row)) {
            cell.set_char('◆');
        }
    }
}

/// Three decimals; a value that rounds to zero prints as `+0.000` (its
/// sign is rounding noise and would flicker between evaluation paths).
fn fmt_vec(v: &Vector3<f64>) -> String {
    let c = |x: f64| if x.abs() < 5e-4 { 0.0 } else { x };
    format!("({:+.3} {:+.3} {:+.3})", c(v.x), c(v.y), c(v.z))
}

/// Model summary and probe values.
fn render_readout(v: &SphereView, m: &Model, theme: Theme, area: Rect, buf: &mut Buffer) {
    let c = &m.coefficients;
    let e = v.probe();
    let dc = c.at_direction(&e);
    let (lo, hi, _) = value_range(m, v.mode);
    let mut lines = vec![
        Line::from(vec![
            Span::styled("N ", theme.dim()),
            Span::raw(format!("{}  ", c.degree())),
            Span::styled("N_T ", theme.dim()),
            Span::raw(format!("{}  ", c.torque_degree())),
            Span::styled("L ", theme.dim()),
            Span::raw(format!("{:.3} m  ", c.reference_length())),
            Span::styled("mode ", theme.dim()),
            Span::styled(v.mode.name(), theme.title()),
        ]),
        Line::raw(format!(
            "probe ◆ lon {:+.0}° lat {:+.0}°",
            v.probe_lon, v.probe_lat
        )),
        Line::raw(format!("E   {}", fmt_vec(&e))),
    ];
    if let Some(dc) = dc {
        let drag = -dc.force.dot(&e);
        let lift = (dc.force + e * drag).norm();
        lines.push(Line::raw(format!("C_F {}", fmt_vec(&dc.force))));
        lines.push(Line::raw(format!("C_T {}", fmt_vec(&dc.torque))));
        lines.push(Line::raw(format!(
            "drag {drag:.3} lift {lift:.3} |C_T| {:.3}",
            dc.torque.norm()
        )));
    }
    lines.push(legend(
        v.mode,
        lo,
        hi,
        c.provenance.coverage.is_empty(),
        theme,
    ));
    let arrows = match (v.arrows, v.mode) {
        (false, _) | (_, Mode::Coverage) => "off",
        (true, Mode::Force) => "lift",
        (true, Mode::Torque) => "C_T",
    };
    let view = format!("yaw {:.0}° pitch {:.0}° arrows {arrows}", v.yaw, v.pitch);
    lines.push(Line::styled(view, theme.dim()));
    Paragraph::new(lines)
        .wrap(Wrap { trim: true })
        .render(area, buf);
}

fn legend(mode: Mode, lo: f64, hi: f64, no_coverage: bool, theme: Theme) -> Line<'static> {
    let what = match mode {
        Mode::Force => "drag",
        Mode::Torque => "|C_T|",
        Mode::Coverage if no_coverage => "none recorded",
        Mode::Coverage => "frames",
    };
    Line::from(vec![
        Span::styled("shade ", theme.dim()),
        Span::raw(format!("{what} {lo:.2} ")),
        Span::styled("⡀", theme.ramp(0.0)),
        Span::styled("⣤", theme.ramp(0.5)),
        Span::styled("⣿", theme.ramp(1.0)),
        Span::raw(format!(" {hi:.2}")),
    ])
}
