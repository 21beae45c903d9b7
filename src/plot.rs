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
//! Files are written through [`crate::output::write_atomic`].

use std::path::Path;
use std::sync::OnceLock;

use plotters::chart::DualCoordChartContext;
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, TRANSPARENT};

use crate::output::write_atomic;
use crate::{Error, Result};

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
    /// Solid line on the right axis (requires [`Axes::y2_label`]).
    LineOnSecondaryAxis,
    /// Grey dashed line for reference curves (ideal joint, nominal profile), left axis.
    Reference,
}

/// One data series: `x[i]`, `y[i]` pairs (equal lengths).
#[derive(Clone, Debug)]
pub struct Series<'a> {
    pub label: String,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub style: Style,
}

impl<'a> Series<'a> {
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
    pub title: String,
    /// Axis labels with units, e.g. `"time (s)"`.
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series<'a>>,
    /// Label of the right axis; required when a series uses [`Style::LineOnSecondaryAxis`].
    pub y2_label: Option<String>,
    /// Fixed ranges instead of the automatic ones (with `equal_aspect` they may be widened).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// Same scale on both axes (trajectories, profiles).
    pub equal_aspect: bool,
    /// Circle outlines `(cx, cy, r)` in data units, e.g. the clearance circle.
    pub circles: Vec<(f64, f64, f64)>,
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

impl<'a> Axes<'a> {
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
    if panels.is_empty() {
        return Err(plot_error(path, "a figure needs at least one panel"));
    }
    let tagged = panels.len() > 1;
    let prepared = panels
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
        .map_err(|message| plot_error(path, message))?;
    draw_figure(path, &prepared)
}

/// Renders closed profiles `r(theta)` (theta in degrees, counter-clockwise from +x) as a polar
/// picture around the dashed reference circle of radius `r_ref`. The deviation `r - r_ref` is
/// scaled by `magnify` (noted on the figure) so that micrometre wear shows on a millimetre radius.
pub fn render_polar(
    path: &Path,
    title: &str,
    theta_deg: &[f64],
    profiles: &[(String, Vec<f64>, Style)],
    r_ref: f64,
    magnify: f64,
) -> Result<()> {
    let fail = |message: String| plot_error(path, message);
    if !(r_ref.is_finite() && r_ref > 0.0 && magnify.is_finite() && magnify > 0.0) {
        return Err(fail(format!(
            "reference radius ({r_ref}) and magnification ({magnify}) must be positive and finite"
        )));
    }
    if theta_deg.is_empty() || profiles.is_empty() {
        return Err(fail(
            "a polar figure needs angles and at least one profile".to_owned(),
        ));
    }
    if let Some((name, r, _)) = profiles.iter().find(|(_, r, _)| r.len() != theta_deg.len()) {
        return Err(fail(format!(
            "profile `{name}` has {} radii for {} angles",
            r.len(),
            theta_deg.len()
        )));
    }
    // Closed curve (x, y) through the magnified radii `radius(i)` at `theta_deg[i]`.
    let closed = |radius: &dyn Fn(usize) -> f64| -> (Vec<f64>, Vec<f64>) {
        (0..=theta_deg.len())
            .map(|k| {
                let i = k % theta_deg.len();
                let rho = (r_ref + magnify * (radius(i) - r_ref)).max(0.0);
                let t = theta_deg[i].to_radians();
                (rho * t.cos(), rho * t.sin())
            })
            .unzip()
    };
    // The reference circle first, so that the profiles are drawn over it.
    let reference = (
        "reference circle".to_owned(),
        closed(&|_| r_ref),
        Style::Reference,
    );
    let curves: Vec<_> = std::iter::once(reference)
        .chain(
            profiles
                .iter()
                .map(|(name, r, style)| (name.clone(), closed(&|i| r[i]), *style)),
        )
        .collect();
    let extent = curves
        .iter()
        .flat_map(|(_, (x, y), _)| x.iter().zip(y).map(|(x, y)| x.hypot(*y)))
        .filter(|r| r.is_finite())
        .fold(r_ref, f64::max)
        * 1.15;
    let axes = Axes {
        title: title.to_owned(),
        series: curves
            .iter()
            .map(|(label, (x, y), style)| Series::new(label.clone(), x, y, *style))
            .collect(),
        x_range: Some((-extent, extent)),
        y_range: Some((-extent, extent)),
        equal_aspect: true,
        ..Default::default()
    };
    let note = format!("radial deviation magnified ×{magnify}");
    let panel = Panel::new(&axes, axes.title.clone(), Some(note)).map_err(fail)?;
    draw_figure(path, &[panel])
}

// ---------------------------------------------------------------------------------------------
// Layout and style constants (pixels).

const PANEL_SIZE: (u32, u32) = (1200, 800);
const TITLE_BAND: u32 = 50;
/// Margins around the chart: top leaves room for a "×10ⁿ" factor above the y axis.
const MARGIN: (u32, u32, u32, u32) = (30, 10, 15, 35); // top, bottom, left, right
const X_LABEL_AREA: u32 = 80;
const TITLE_PX: u32 = 32;
const DESC_PX: u32 = 26;
const TICK_PX: u32 = 22;
const LEGEND_PX: u32 = 22;
/// Approximate advance of a tick-label character (DejaVu Sans digits are 0.636 em wide).
const TICK_CHAR_PX: u32 = 14;
const LEGEND_CHAR_PX: u32 = 13;
const X_TICKS: usize = 10;
const Y_TICKS: usize = 8;
const LINE_WIDTH: u32 = 3;
const FONT: &str = "sans-serif";

/// matplotlib's "tab10" without its grey, which is kept for reference curves and circles.
const PALETTE: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const GREY: RGBColor = RGBColor(100, 100, 100);

fn plot_error(path: &Path, message: impl ToString) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Registers the embedded DejaVu Sans once per process.
fn ensure_font() -> std::result::Result<(), String> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        let bytes = include_bytes!("../assets/fonts/DejaVuSans.ttf");
        plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| "embedded DejaVu Sans could not be loaded".to_owned())
}

fn text(px: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, px).into_font()).color(&BLACK)
}

// ---------------------------------------------------------------------------------------------
// Data preparation: everything that can fail on bad input happens before a file is created.

/// An axis range with its tick-label format: labels show `v / 10^exp` with `decimals` digits.
struct Axis {
    lo: f64,
    hi: f64,
    exp: i32,
    decimals: usize,
    ticks: usize,
}

impl Axis {
    fn new((lo, hi): (f64, f64), ticks: usize) -> Self {
        let max_abs = lo.abs().max(hi.abs());
        let exp = if !(1e-3..1e5).contains(&max_abs) {
            max_abs.log10().floor() as i32
        } else {
            0
        };
        let points = RangedCoordf64::from(lo..hi).key_points(ticks);
        let step = points
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(hi - lo, f64::min);
        let scaled = step / 10f64.powi(exp);
        let decimals = (-scaled.log10() - 1e-6).ceil().clamp(0.0, 12.0) as usize;
        Axis {
            lo,
            hi,
            exp,
            decimals,
            ticks,
        }
    }

    fn label(&self, v: f64) -> String {
        let s = format!("{:.*}", self.decimals, v / 10f64.powi(self.exp));
        match s.strip_prefix('-') {
            Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_owned(),
            Some(rest) => format!("\u{2212}{rest}"),
            None => s,
        }
    }

    /// Common factor shown at the end of the axis, e.g. "×10⁻⁹".
    fn factor(&self) -> Option<String> {
        const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
        (self.exp != 0).then(|| {
            let digits = self.exp.to_string();
            let sup = digits
                .chars()
                .map(|c| c.to_digit(10).map_or('⁻', |d| SUP[d as usize]));
            "×10".chars().chain(sup).collect()
        })
    }

    /// Width of the label area needed by the tick labels plus the rotated axis description.
    fn label_area(&self) -> u32 {
        let widest = RangedCoordf64::from(self.lo..self.hi)
            .key_points(self.ticks)
            .into_iter()
            .map(|v| self.label(v).chars().count())
            .max()
            .unwrap_or(1) as u32;
        widest * TICK_CHAR_PX + DESC_PX + 22
    }

    fn span(&self) -> f64 {
        self.hi - self.lo
    }
}

struct Curve {
    label: String,
    style: Style,
    color: RGBColor,
    /// Runs of finite points; a non-finite sample ends a run.
    segments: Vec<Vec<(f64, f64)>>,
}

/// A panel ready to draw.
struct Panel {
    title: String,
    x_label: String,
    y_label: String,
    y2_label: Option<String>,
    curves: Vec<Curve>,
    circles: Vec<Vec<(f64, f64)>>,
    /// Closed outlines of the bands, with their colours.
    shades: Vec<(RGBColor, Vec<(f64, f64)>)>,
    x: Axis,
    y: Axis,
    y2: Option<Axis>,
    legend: Option<SeriesLabelPosition>,
    /// Polar pictures have no axes, only this note.
    polar_note: Option<String>,
}

fn finite_runs(x: &[f64], y: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let pairs: Vec<(f64, f64)> = x.iter().copied().zip(y.iter().copied()).collect();
    pairs
        .split(|(x, y)| !(x.is_finite() && y.is_finite()))
        .filter(|run| !run.is_empty())
        .map(<[_]>::to_vec)
        .collect()
}

fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// Widens `(lo, hi)` by `frac` of its span on each side; a degenerate range gets a unit span
/// (or 5 % of its value).
fn pad((lo, hi): (f64, f64), frac: f64) -> (f64, f64) {
    let span = hi - lo;
    if span > 1e-12 * lo.abs().max(hi.abs()) {
        (lo - frac * span, hi + frac * span)
    } else {
        let d = if lo == 0.0 { 0.5 } else { 0.05 * lo.abs() };
        (lo - d, hi + d)
    }
}

fn check_range(name: &str, r: Option<(f64, f64)>) -> std::result::Result<(), String> {
    match r {
        Some((lo, hi)) if !(lo.is_finite() && hi.is_finite() && lo < hi) => {
            Err(format!("{name} ({lo}, {hi}) must be finite and increasing"))
        }
        _ => Ok(()),
    }
}

/// Plotting-area size in pixels for given left/right label areas (mirrors [`draw_panel`]).
fn plot_size(left: u32, right: u32, polar: bool) -> (f64, f64) {
    let (top, bottom, l, r) = MARGIN;
    let x_area = if polar { 0 } else { X_LABEL_AREA };
    (
        f64::from(PANEL_SIZE.0 - l - r - left - right),
        f64::from(PANEL_SIZE.1 - TITLE_BAND - top - bottom - x_area),
    )
}

/// Widens the ranges around their centres so that one data unit has the same length on both axes.
fn equalize(x: (f64, f64), y: (f64, f64), (w, h): (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let scale = ((x.1 - x.0) / w).max((y.1 - y.0) / h);
    let around = |(lo, hi): (f64, f64), px: f64| {
        let (c, half) = (0.5 * (lo + hi), 0.5 * scale * px);
        (c - half, c + half)
    };
    (around(x, w), around(y, h))
}

impl Panel {
    fn new(
        axes: &Axes,
        title: String,
        polar_note: Option<String>,
    ) -> std::result::Result<Self, String> {
        let polar = polar_note.is_some();
        let name = &axes.title;
        if axes.series.is_empty() {
            return Err(format!("panel `{name}` has no series"));
        }
        if let Some(s) = axes.series.iter().find(|s| s.x.len() != s.y.len()) {
            return Err(format!(
                "series `{}` of panel `{name}` has {} x values but {} y values",
                s.label,
                s.x.len(),
                s.y.len()
            ));
        }
        check_range("x range", axes.x_range)?;
        check_range("y range", axes.y_range)?;
        let has_y2 = axes
            .series
            .iter()
            .any(|s| s.style == Style::LineOnSecondaryAxis);
        if has_y2 && axes.y2_label.is_none() {
            return Err(format!(
                "panel `{name}` has a right-axis series but no y2_label"
            ));
        }

        let mut palette = PALETTE.iter().cycle();
        let curves: Vec<Curve> = axes
            .series
            .iter()
            .map(|s| Curve {
                label: s.label.clone(),
                style: s.style,
                color: if s.style == Style::Reference {
                    GREY
                } else {
                    *palette.next().expect("cycle")
                },
                segments: finite_runs(s.x, s.y),
            })
            .collect();
        let circles: Vec<Vec<(f64, f64)>> = axes
            .circles
            .iter()
            .filter(|(cx, cy, r)| cx.is_finite() && cy.is_finite() && r.is_finite())
            .map(|&(cx, cy, r)| {
                (0..=360)
                    .map(|d| f64::from(d).to_radians())
                    .map(|t| (cx + r * t.cos(), cy + r * t.sin()))
                    .collect()
            })
            .collect();

        let mut shades = Vec::new();
        for sh in &axes.shades {
            let (Some(s), Some(c)) = (axes.series.get(sh.series), curves.get(sh.series)) else {
                return Err(format!("a band of panel `{name}` names no series"));
            };
            if sh.lo.len() != s.x.len() || sh.hi.len() != s.x.len() {
                return Err(format!(
                    "the band of series `{}` has the wrong length",
                    s.label
                ));
            }
            let lower = s.x.iter().zip(sh.lo);
            let upper = s.x.iter().zip(sh.hi).rev();
            let outline: Vec<(f64, f64)> = lower
                .chain(upper)
                .map(|(x, y)| (*x, *y))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            shades.push((c.color, outline));
        }

        let points = |on_y2: bool| {
            let curve_points = curves
                .iter()
                .filter(move |c| (c.style == Style::LineOnSecondaryAxis) == on_y2)
                .flat_map(|c| c.segments.iter().flatten());
            let circle_points = circles.iter().flatten().filter(move |_| !on_y2);
            let shade_points = shades.iter().flat_map(|(_, o)| o).filter(move |_| !on_y2);
            curve_points
                .chain(circle_points)
                .chain(shade_points)
                .copied()
        };
        let data_x = extent(points(false).chain(points(true)).map(|p| p.0))
            .ok_or_else(|| format!("panel `{name}` has no finite data point"))?;
        let x_auto = if axes.equal_aspect {
            pad(data_x, 0.05)
        } else {
            pad(data_x, 0.0)
        };
        let mut x_range = axes.x_range.unwrap_or(x_auto);
        let mut y_range = match axes.y_range {
            Some(r) => r,
            None => pad(
                extent(points(false).map(|p| p.1)).unwrap_or((0.0, 1.0)),
                0.05,
            ),
        };
        let y2 = has_y2.then(|| {
            let r = extent(points(true).map(|p| p.1)).unwrap_or((0.0, 1.0));
            Axis::new(pad(r, 0.05), Y_TICKS)
        });
        let right_area = y2.as_ref().map_or(0, Axis::label_area);
        let left_area = |y: &Axis| left_label_area(y, polar);

        let mut y = Axis::new(y_range, Y_TICKS);
        if axes.equal_aspect {
            // The label area depends on the tick labels, which depend on the range: iterate.
            let requested = (x_range, y_range);
            for _ in 0..3 {
                let size = plot_size(left_area(&y), right_area, polar);
                (x_range, y_range) = equalize(requested.0, requested.1, size);
                let widened = Axis::new(y_range, Y_TICKS);
                let stable = left_area(&widened) == left_area(&y);
                y = widened;
                if stable {
                    break;
                }
            }
        }
        let x = Axis::new(x_range, X_TICKS);
        let size = plot_size(left_area(&y), right_area, polar);
        let labelled: Vec<&Curve> = curves.iter().filter(|c| !c.label.is_empty()).collect();
        let legend = (labelled.len() > 1).then(|| {
            let widest = labelled
                .iter()
                .map(|c| c.label.chars().count())
                .max()
                .unwrap_or(0) as u32
                + if has_y2 { 13 } else { 0 }; // " (right axis)"
            let w = f64::from(widest * LEGEND_CHAR_PX + 90) / size.0;
            let h = f64::from(labelled.len() as u32 * (LEGEND_PX + 12) + 40) / size.1;
            let normalized = |(px, py): (f64, f64), on_y2: bool| {
                let ya = if on_y2 { y2.as_ref().unwrap_or(&y) } else { &y };
                ((px - x.lo) / x.span(), (py - ya.lo) / ya.span())
            };
            let uv: Vec<(f64, f64)> = points(false)
                .map(|p| normalized(p, false))
                .chain(points(true).map(|p| normalized(p, true)))
                .collect();
            least_crowded_corner(&uv, w, h)
        });

        Ok(Panel {
            title,
            x_label: axes.x_label.clone(),
            y_label: axes.y_label.clone(),
            y2_label: axes.y2_label.clone().filter(|_| has_y2),
            curves,
            circles,
            shades,
            x,
            y,
            y2,
            legend,
            polar_note,
        })
    }
}

/// Polar pictures have no y axis.
fn left_label_area(y: &Axis, polar: bool) -> u32 {
    if polar {
        0
    } else {
        y.label_area()
    }
}

/// The corner whose `w` x `h` box (in plot-normalised units) covers the fewest points.
fn least_crowded_corner(uv: &[(f64, f64)], w: f64, h: f64) -> SeriesLabelPosition {
    use SeriesLabelPosition::*;
    let corners = [
        (UpperRight, true, true),
        (UpperLeft, false, true),
        (LowerRight, true, false),
        (LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        uv.iter()
            .filter(|(u, v)| {
                (if right { *u >= 1.0 - w } else { *u <= w })
                    && (if upper { *v >= 1.0 - h } else { *v <= h })
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|&(_, right, upper)| count(right, upper))
        .map(|(pos, _, _)| pos)
        .unwrap_or(UpperRight)
}

// ---------------------------------------------------------------------------------------------
// Drawing.

type DrawResult<'b> = std::result::Result<(), Box<dyn std::error::Error + 'b>>;

fn draw_figure(path: &Path, panels: &[Panel]) -> Result<()> {
    ensure_font().map_err(|m| plot_error(path, m))?;
    let n = panels.len() as u32;
    let cols = if n == 4 { 2 } else { n.min(3) };
    let rows = n.div_ceil(cols);
    write_atomic(path, |tmp| {
        let size = (cols * PANEL_SIZE.0, rows * PANEL_SIZE.1);
        let root = BitMapBackend::new(tmp, size).into_drawing_area();
        let drawn: DrawResult = (|| {
            root.fill(&WHITE)?;
            let areas = root.split_evenly((rows as usize, cols as usize));
            for (area, panel) in areas.iter().zip(panels) {
                draw_panel(area, panel)?;
            }
            root.present()?;
            Ok(())
        })();
        drawn.map_err(|e| plot_error(path, e))
    })
}

fn draw_panel<'b>(area: &DrawingArea<BitMapBackend<'b>, Shift>, p: &Panel) -> DrawResult<'b> {
    let polar = p.polar_note.is_some();
    let (title_area, body) = area.split_vertically(TITLE_BAND);
    let centre = Pos::new(HPos::Center, VPos::Center);
    title_area.draw_text(
        &p.title,
        &text(TITLE_PX).pos(centre),
        ((PANEL_SIZE.0 / 2) as i32, (TITLE_BAND / 2) as i32),
    )?;

    let (top, bottom, left, right) = MARGIN;
    let y2 = p.y2.as_ref().unwrap_or(&p.y);
    let mut chart = ChartBuilder::on(&body)
        .margin_top(top)
        .margin_bottom(bottom)
        .margin_left(left)
        .margin_right(right)
        .x_label_area_size(if polar { 0 } else { X_LABEL_AREA })
        .y_label_area_size(left_label_area(&p.y, polar))
        .right_y_label_area_size(p.y2.as_ref().map_or(0, Axis::label_area))
        .build_cartesian_2d(p.x.lo..p.x.hi, p.y.lo..p.y.hi)?
        .set_secondary_coord(p.x.lo..p.x.hi, y2.lo..y2.hi);

    let x_fmt = |v: &f64| p.x.label(*v);
    let y_fmt = |v: &f64| p.y.label(*v);
    let y2_fmt = |v: &f64| y2.label(*v);
    if polar {
        draw_polar_grid(&mut chart, p)?;
    } else {
        chart
            .configure_mesh()
            .x_desc(p.x_label.as_str())
            .y_desc(p.y_label.as_str())
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .label_style(text(TICK_PX))
            .axis_desc_style(text(DESC_PX))
            .bold_line_style(BLACK.mix(0.1))
            .light_line_style(TRANSPARENT)
            .draw()?;
        if let Some(label) = &p.y2_label {
            chart
                .configure_secondary_axes()
                .y_desc(label.as_str())
                .y_labels(Y_TICKS)
                .y_label_formatter(&y2_fmt)
                .label_style(text(TICK_PX))
                .axis_desc_style(text(DESC_PX))
                .draw()?;
        }
    }

    for circle in &p.circles {
        chart.draw_series(LineSeries::new(
            circle.iter().copied(),
            GREY.stroke_width(2),
        ))?;
    }
    for (color, outline) in &p.shades {
        chart.draw_series(std::iter::once(Polygon::new(
            outline.clone(),
            color.mix(0.22).filled(),
        )))?;
    }
    let dual = p.y2.is_some();
    for c in &p.curves {
        let line = c.color.stroke_width(LINE_WIDTH);
        for (k, run) in c.segments.iter().enumerate() {
            let points = run.iter().copied();
            let anno = match c.style {
                Style::Line => chart.draw_series(LineSeries::new(points, line))?,
                Style::Dashed | Style::Reference => {
                    chart.draw_series(DashedLineSeries::new(points, 14, 8, line))?
                }
                Style::Points => {
                    chart.draw_series(points.map(|q| Circle::new(q, 4, c.color.filled())))?
                }
                Style::LineOnSecondaryAxis => {
                    chart.draw_secondary_series(LineSeries::new(points, line))?
                }
            };
            if k == 0 && p.legend.is_some() && !c.label.is_empty() {
                let (line, marker, gap) = legend_parts(c.style, c.color);
                let side = match (dual, c.style) {
                    (false, _) => "",
                    (true, Style::LineOnSecondaryAxis) => " (right axis)",
                    (true, _) => " (left axis)",
                };
                anno.label(format!("{}{side}", c.label)).legend(move |at| {
                    EmptyElement::at(at)
                        + PathElement::new([(0, 0), (15 - gap, 0)], line)
                        + PathElement::new([(15 + gap, 0), (30, 0)], line)
                        + Circle::new((15, 0), 5, marker)
                });
            }
        }
    }

    if !polar {
        // Closed frame around the plotting area.
        chart.draw_series(std::iter::once(Rectangle::new(
            [(p.x.lo, p.y.lo), (p.x.hi, p.y.hi)],
            BLACK.stroke_width(1),
        )))?;
    }
    if let Some(pos) = &p.legend {
        chart
            .configure_series_labels()
            .position(pos.clone())
            .margin(15)
            .legend_area_size(45)
            .label_font(text(LEGEND_PX))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK.mix(0.5))
            .draw()?;
    }

    // Common "×10ⁿ" factors at the ends of the axes, and the polar note, in pixel coordinates.
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let (bx, by) = area.get_base_pixel();
    let note = |s: &str, (x, y): (i32, i32), h: HPos, v: VPos| {
        area.draw_text(s, &text(TICK_PX).pos(Pos::new(h, v)), (x - bx, y - by))
    };
    if let Some(f) = p.y.factor().filter(|_| !polar) {
        note(&f, (xs.start, ys.start - 8), HPos::Left, VPos::Bottom)?;
    }
    if let Some(f) = p.y2.as_ref().and_then(Axis::factor) {
        note(&f, (xs.end, ys.start - 8), HPos::Right, VPos::Bottom)?;
    }
    if let Some(f) = p.x.factor().filter(|_| !polar) {
        note(&f, (xs.end, ys.end + 40), HPos::Right, VPos::Top)?;
    }
    if let Some(s) = &p.polar_note {
        note(s, (xs.start + 10, ys.end - 10), HPos::Left, VPos::Bottom)?;
    }
    Ok(())
}

type Chart<'a, 'b> = DualCoordChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
>;

/// Spokes every 45° with angle labels, in place of Cartesian axes.
fn draw_polar_grid<'b>(chart: &mut Chart<'_, 'b>, p: &Panel) -> DrawResult<'b> {
    let reach = 0.5 * p.x.span().min(p.y.span()) / 1.15;
    for k in 0..8 {
        let t = f64::from(k * 45).to_radians();
        let (c, s) = (t.cos(), t.sin());
        chart.draw_series(LineSeries::new(
            [(0.0, 0.0), (reach * c, reach * s)],
            BLACK.mix(0.15),
        ))?;
        let label = Text::new(
            format!("{}°", k * 45),
            (1.07 * reach * c, 1.07 * reach * s),
            text(TICK_PX).pos(Pos::new(HPos::Center, VPos::Center)),
        );
        chart.draw_series(std::iter::once(label))?;
    }
    Ok(())
}

/// Legend sample matching how the series is drawn: (line style, marker style, half dash gap).
/// One element shape serves every style; the unused parts are transparent.
fn legend_parts(style: Style, color: RGBColor) -> (ShapeStyle, ShapeStyle, i32) {
    let (line, hidden) = (color.stroke_width(LINE_WIDTH), TRANSPARENT.into());
    match style {
        Style::Points => (hidden, color.filled(), 0),
        Style::Dashed | Style::Reference => (line, hidden, 3),
        Style::Line | Style::LineOnSecondaryAxis => (line, hidden, 0),
    }
}
