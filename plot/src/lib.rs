//! SVG figures for reports (`omniad flight fit --plots`, `omniad residual
//! --plots`): line and scatter series on linear axes with "nice" ticks.
//!
//! Why our own: the figures are simple, must work on an SSH-only laptop and
//! in CI without fonts or a browser, and a few hundred lines of text output
//! are easier to keep deterministic (golden-testable) than a plotting stack.

mod axis;
mod svg;

pub use axis::{nice_ticks, Range};

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Points joined in order.
    Line,
    /// Small circles.
    Points,
}

/// One named series of `(x, y)` points; non-finite points are skipped.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

impl Series {
    /// A line series.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            style: Style::Line,
        }
    }

    /// A scatter series.
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            style: Style::Points,
        }
    }
}

/// A figure: title, axis labels (with units), series.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Figure {
    /// Title above the plot.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// The series, drawn in order with a fixed palette.
    pub series: Vec<Series>,
}

impl Figure {
    /// A figure with a title and axis labels and no series yet.
    pub fn new(title: impl Into<String>, x: impl Into<String>, y: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x.into(),
            y_label: y.into(),
            series: Vec::new(),
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// The SVG document, 720 x 420 px.
    pub fn to_svg(&self) -> String {
        svg::render(self, 720.0, 420.0)
    }
}
