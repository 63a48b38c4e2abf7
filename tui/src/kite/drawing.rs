//! The kite drawn in braille: side (world x-z, wind from the left) and
//! top (world x-y) projections of every panel, the string from the
//! attachment point, and the selected primitive's name.

use super::KiteView;
use crate::theme::Theme;
use nalgebra::Vector3;
use omniad_kite::check::CheckReport;
use omniad_kite::geometry::{panels, rotation_from_degrees};
use omniad_kite::KiteSpec;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};
use ratatui::widgets::{Block, Widget};

/// Which projection.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// World x (downwind) right, z up.
    Side,
    /// World x right, y up.
    Top,
}

fn project(p: &Vector3<f64>, proj: Projection) -> (f64, f64) {
    match proj {
        Projection::Side => (p.x, p.z),
        Projection::Top => (p.x, p.y),
    }
}

/// Draws one projection of the kite into `area`.
pub fn render_drawing(v: &KiteView, proj: Projection, theme: Theme, area: Rect, buf: &mut Buffer) {
    let title = match proj {
        Projection::Side => " side x-z, wind → ",
        Projection::Top => " top x-y ",
    };
    let block = Block::bordered().title(Line::styled(title, theme.title()));
    let inner = block.inner(area);
    if inner.width < 2 || inner.height < 2 {
        return block.render(area, buf);
    }
    let r = rotation_from_degrees(&v.spec.orientation);
    let center = v
        .design
        .as_ref()
        .map_or(Vector3::zeros(), |d| d.mass.center);
    let shapes: Vec<(usize, [Vector3<f64>; 4])> = outlines(&v.spec, &center)
        .into_iter()
        .map(|(i, c)| (i, c.map(|p| r * p)))
        .collect();
    let ext = shapes
        .iter()
        .flat_map(|(_, c)| c.iter())
        .map(|p| p.amax())
        .fold(0.1, f64::max)
        * 1.3;
    let aspect = f64::from(inner.width) * 2.0 / (f64::from(inner.height) * 4.0);
    let (xe, ye) = if aspect >= 1.0 {
        (ext * aspect, ext)
    } else {
        (ext, ext / aspect)
    };
    let (hi, lo) = (
        theme.series(1).fg.unwrap_or_default(),
        theme.dim().fg.unwrap_or_default(),
    );
    Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([-xe, xe])
        .y_bounds([-ye, ye])
        .paint(|ctx| {
            for (i, corners) in &shapes {
                let colour = if *i == v.selected { hi } else { Color::Reset };
                draw_outline(ctx, corners, proj, colour);
            }
            if let Ok(a) = &v.analysis {
                draw_string(ctx, a, &r, proj, ext, lo);
            }
            if let Some((_, c)) = shapes.iter().find(|(i, _)| *i == v.selected) {
                let (x, y) = project(&((c[0] + c[2]) / 2.0), proj);
                ctx.print(x, y, Line::styled("◆", theme.series(1)));
            }
        })
        .render(area, buf);
}

/// Every covered face of the kite crate's geometry: the index of its
/// primitive and four corners, body frame, relative to `center` (the
/// centre of mass), m.
fn outlines(spec: &KiteSpec, center: &Vector3<f64>) -> Vec<(usize, [Vector3<f64>; 4])> {
    let mut out = Vec::new();
    for (i, p) in spec.primitives.iter().enumerate() {
        for f in panels(p) {
            let c = f.center - center;
            out.push((
                i,
                [c - f.u - f.v, c + f.u - f.v, c + f.u + f.v, c - f.u + f.v],
            ));
        }
    }
    out
}

fn draw_outline(ctx: &mut Context<'_>, c: &[Vector3<f64>; 4], proj: Projection, color: Color) {
    for k in 0..4 {
        let (x1, y1) = project(&c[k], proj);
        let (x2, y2) = project(&c[(k + 1) % 4], proj);
        ctx.draw(&CLine::new(x1, y1, x2, y2, color));
    }
}

/// The string: from the attachment point towards the anchor (along the
/// tension the string exerts on the kite).
fn draw_string(
    ctx: &mut Context<'_>,
    a: &CheckReport,
    r: &nalgebra::Matrix3<f64>,
    proj: Projection,
    ext: f64,
    color: Color,
) {
    let tension = Vector3::from(a.tension_world);
    let n = tension.norm();
    if n <= 0.0 {
        return;
    }
    let p = r * Vector3::from(a.attachment);
    let q = p + tension / n * ext * 2.0;
    let ((x1, y1), (x2, y2)) = (project(&p, proj), project(&q, proj));
    ctx.draw(&CLine::new(x1, y1, x2, y2, color));
    ctx.print(x1, y1, "o");
}
