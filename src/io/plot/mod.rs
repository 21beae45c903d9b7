//! Shared plotting helpers. Every figure of the crate is drawn through [`render`] or
//! [`render_polar`]; no binary contains plotting code of its own, so all figures share one look:
//!
//! - white background, 1200x800 px per panel (panels side by side, four as 2x2);
//! - DejaVu Sans, embedded in the binary (no fontconfig/freetype needed);
//! - a title per panel (prefixed "(a)", "(b)", ... when there are several), axis labels as given
//!   by the caller (with units), a legend when a panel has more than one labelled series, placed
//!   in the corner with the least data;
//! - a tight x-range and a y-range padded by 5 %, unless the caller fixes them; very small or
//!   large values get a common "×10ⁿ" factor at the end of the axis instead of long tick labels;
//! - non-finite samples are skipped and break the line they belong to;
//! - ensemble bands ([`Shade`]) are filled in a light tint of their series' colour, under the
//!   lines.
//!
//! Files (PNG, and the GIF of an animation) are written through
//! [`crate::io::output::write_atomic`].
//!
//! The code, by what it does:
//!
//! - this file: the public description of a figure ([`Axes`], [`Series`], [`Shade`], [`Style`])
//!   and [`render`];
//! - `theme`: the shared look (sizes, margins, font, text styles, palette);
//! - `axis`: axis ranges, tick labels and "×10ⁿ" factors;
//! - `panel`: a panel checked and laid out (ranges, equal aspect, legend corner) before any file
//!   is created;
//! - `draw`: drawing laid-out panels on Cartesian axes into the PNG;
//! - `clip`: lines and bands cut to the visible ranges (plotters draws outside them);
//! - `mechanism`: pictures of a mechanism's pose ([`render_mechanism`]) and animated GIFs of
//!   its motion ([`render_animation`]), with the journal's orbit magnified in an inset;
//! - `polar`: closed profiles as polar pictures ([`render_polar`]);
//! - `text`: the drawing backend that places glyphs correctly (plotters 0.3.7 drops each
//!   glyph's left side bearing; see its module documentation).

mod axis;
mod clip;
mod draw;
mod mechanism;
mod panel;
mod polar;
mod text;
mod theme;

pub use axis::superscript;
pub use mechanism::{
    render_animation, render_mechanism, BodyShape, ClearanceShape, Guide, MechanismPicture, Point,
};
pub use polar::render_polar;

use std::path::Path;

use crate::{Error, Result};
use draw::{draw_figure, draw_figure_in};
use panel::Panel;

/// How a series is drawn. Colours come from a fixed colour-blind-friendly palette, in the order
/// of the series in the panel (reference curves are grey and take no palette colour).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// Solid line, left axis.
    #[default]
    Line,
    /// Dashed line, left axis.
    Dashed,
    /// Markers only, left axis.
    Points,
    /// Solid line through markers, left axis (a sweep of settings: each marker one setting).
    LinePoints,
    /// Solid line on the right axis (requires [`Axes::y2_label`]).
    LineOnSecondaryAxis,
    /// Grey dashed line for reference curves (ideal joint, nominal profile), left axis.
    Reference,
    /// Solid line in the colour of the series before it, left axis: the error bars of that
    /// series' markers (NaN-separated segments). It takes no palette colour of its own.
    ErrorBars,
}

/// One data series: `x[i]`, `y[i]` pairs (equal lengths).
#[derive(Clone, Debug)]
pub struct Series<'a> {
    /// Legend label (an empty label keeps the series out of the legend).
    pub label: String,
    /// The x values.
    pub x: &'a [f64],
    /// The y values, one per x value.
    pub y: &'a [f64],
    /// How the series is drawn.
    pub style: Style,
}

impl<'a> Series<'a> {
    /// A series labelled `label` through the points `(x[i], y[i])`, drawn as `style`.
    pub fn new(label: impl Into<String>, x: &'a [f64], y: &'a [f64], style: Style) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style,
        }
    }
}

/// One panel. Start from `Axes::new(..)` or `Axes { .., ..Default::default() }`.
#[derive(Clone, Debug, Default)]
pub struct Axes<'a> {
    /// Panel title (prefixed "(a)", "(b)", ... in a figure of several panels).
    pub title: String,
    /// Label of the x axis with units, e.g. `"time (s)"`.
    pub x_label: String,
    /// Label of the (left) y axis with units.
    pub y_label: String,
    /// The series, drawn in order (palette colours in order).
    pub series: Vec<Series<'a>>,
    /// Label of the right axis; required when a series uses [`Style::LineOnSecondaryAxis`].
    pub y2_label: Option<String>,
    /// Fixed x range instead of the automatic one (with `equal_aspect` it may be widened).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range instead of the automatic one (with `equal_aspect` it may be widened).
    pub y_range: Option<(f64, f64)>,
    /// Same scale on both axes (trajectories, profiles).
    pub equal_aspect: bool,
    /// Circle outlines `(cx, cy, r)` in data units, e.g. the clearance circle.
    pub circles: Vec<(f64, f64, f64)>,
    /// Legend entry of the circles (e.g. `"clearance circle"`); empty: none.
    pub circle_label: String,
    /// Logarithmic x axis: log10 of x is drawn, ticks at decades labelled 10ⁿ; values ≤ 0 are
    /// not drawn (they break their line).
    pub x_log: bool,
    /// Logarithmic y axis (as [`Axes::x_log`]); not with a right axis.
    pub y_log: bool,
    /// Text beside single data points, e.g. the setting of a run: `(x, y, text)`.
    pub point_labels: Vec<(f64, f64, String)>,
    /// Text to the left of single data points, where the right is taken (the first point of a
    /// line running rightwards): `(x, y, text)`.
    pub point_labels_left: Vec<(f64, f64, String)>,
    /// A note under the x axis, e.g. what is not drawn and why (lines split at
    /// `\n`).
    pub note: Option<String>,
    /// A magnified view of part of the panel, drawn inside it.
    pub inset: Option<Inset>,
    /// Filled bands around series (e.g. the 5-95 % range of an ensemble).
    pub shades: Vec<Shade<'a>>,
}

/// The band between `lo` and `hi` at the x values of series `series` of the same panel.
#[derive(Clone, Debug)]
pub struct Shade<'a> {
    /// Index of the series whose x values and colour the band takes.
    pub series: usize,
    /// Lower edge, one value per x.
    pub lo: &'a [f64],
    /// Upper edge, one value per x.
    pub hi: &'a [f64],
}

/// A magnified view drawn inside a panel: the panel's left-axis curves, bands and circles over
/// `x_range` × `y_range` (data units), in the box `at` = `(left, bottom, right, top)` of the
/// panel's plotting area in fractions of its width and height (0 = left/bottom, 1 =
/// right/top). The zoomed region is outlined on the panel.
#[derive(Clone, Debug, PartialEq)]
pub struct Inset {
    /// The x range shown (data units).
    pub x_range: (f64, f64),
    /// The y range shown (data units).
    pub y_range: (f64, f64),
    /// Where the inset sits in the plotting area (fractions, see the type's documentation).
    pub at: (f64, f64, f64, f64),
    /// A short title above the inset, e.g. `"magnified"`.
    pub title: String,
    /// Whether the title ends with the view's magnification against the panel on each axis,
    /// measured from the pixels drawn (as `x ×N, y ×M`, or `×N` where they agree): the view's
    /// box loses its own title and axes, so no fraction of the panel gives it in advance.
    pub magnification: bool,
}

/// `title` followed by the magnifications `x` and `y` (an inset's pixels per data unit over
/// its panel's), each to two significant digits: one `×N` where they agree to 2 %.
pub(super) fn magnified_title(title: &str, x: f64, y: f64) -> String {
    if (x / y - 1.0).abs() < 0.02 {
        format!("{title}, ×{}", round2(x))
    } else {
        format!("{title}, x ×{}, y ×{}", round2(x), round2(y))
    }
}

/// `v` rounded to two significant digits.
pub(super) fn round2(v: f64) -> f64 {
    let scale = 10f64.powi(v.abs().log10().floor() as i32 - 1);
    (v / scale).round() * scale
}

impl<'a> Axes<'a> {
    /// A panel titled `title` with axis labels and `series`; the other settings at their
    /// defaults (automatic ranges, no right axis, circles or bands).
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series<'a>>,
    ) -> Self {
        Axes {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
            ..Default::default()
        }
    }
}

/// Renders one figure of 1-3 panels side by side (4 panels as 2x2, more in rows of 3) as PNG.
/// Panel titles get "(a)", "(b)", ... prefixes when there is more than one panel.
pub fn render(path: &Path, panels: &[Axes]) -> Result<()> {
    let prepared = prepare(path, panels)?;
    draw_figure(path, &prepared)
}

/// Renders one figure with its panels one under another, each at the width of a single
/// panel: a figure of several panels that stays readable when scaled to a page's width.
/// Titles are tagged as by [`render`].
pub fn render_column(path: &Path, panels: &[Axes]) -> Result<()> {
    let prepared = prepare(path, panels)?;
    draw_figure_in(path, &prepared, (1, prepared.len() as u32))
}

/// The panels of a figure at `path` ready to draw, titles tagged "(a)", "(b)", ... when there
/// is more than one.
fn prepare(path: &Path, panels: &[Axes]) -> Result<Vec<Panel>> {
    if panels.is_empty() {
        return Err(plot_error(path, "a figure needs at least one panel"));
    }
    let tagged = panels.len() > 1;
    panels
        .iter()
        .enumerate()
        .map(|(i, axes)| {
            let title = if tagged {
                format!("({}) {}", char::from(b'a' + (i % 26) as u8), axes.title)
            } else {
                axes.title.clone()
            };
            Panel::new(axes, title, None)
        })
        .collect::<std::result::Result<Vec<_>, String>>()
        .map_err(|message| plot_error(path, message))
}

/// The error of the figure at `path` that cannot be drawn, saying why.
fn plot_error(path: &Path, message: impl ToString) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_inset_title_gives_each_axis_magnification_unless_they_agree() {
        assert_eq!(magnified_title("zoom", 61.3, 14.04), "zoom, x ×61, y ×14");
        assert_eq!(magnified_title("zoom", 133.0, 131.0), "zoom, ×130");
        assert_eq!(round2(0.0456), 0.046);
    }
}
