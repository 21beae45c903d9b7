//! A panel prepared for drawing: everything that can fail on bad input (lengths, ranges, a
//! band naming no series) is checked here, before a file is created; then the curves are cut at
//! non-finite samples (on a logarithmic axis, values ≤ 0 too), the ranges chosen (padded, fixed
//! or of equal aspect) and the legend put in the corner with the least data; when every corner
//! holds data, the y range grows at the top so that the legend covers none.

use plotters::prelude::*;

use super::axis::Axis;
use super::theme::{
    GREY, LEGEND_CHAR_PX, LEGEND_PX, MARGIN, PALETTE, PANEL_SIZE, TITLE_BAND, X_LABEL_AREA,
    X_TICKS, Y_TICKS,
};
use super::{Axes, Style};

/// A series ready to draw.
pub(super) struct Curve {
    /// Legend label.
    pub(super) label: String,
    /// How it is drawn.
    pub(super) style: Style,
    /// Its palette colour (grey for reference curves).
    pub(super) color: RGBColor,
    /// Runs of finite points; a non-finite sample ends a run.
    pub(super) segments: Vec<Vec<(f64, f64)>>,
}

/// A panel ready to draw.
pub(super) struct Panel {
    /// Title, tagged "(a)", "(b)", ... in a figure of several panels.
    pub(super) title: String,
    /// Label of the x axis.
    pub(super) x_label: String,
    /// Label of the left y axis.
    pub(super) y_label: String,
    /// Label of the right y axis, if a series uses it.
    pub(super) y2_label: Option<String>,
    /// The series.
    pub(super) curves: Vec<Curve>,
    /// Circle outlines as closed polylines.
    pub(super) circles: Vec<Vec<(f64, f64)>>,
    /// Closed outlines of the bands, with their colours.
    pub(super) shades: Vec<(RGBColor, Vec<(f64, f64)>)>,
    /// The x axis.
    pub(super) x: Axis,
    /// The left y axis.
    pub(super) y: Axis,
    /// The right y axis, if a series uses it.
    pub(super) y2: Option<Axis>,
    /// Corner of the legend, when there is one.
    pub(super) legend: Option<SeriesLabelPosition>,
    /// Legend entry of the circles (empty: none).
    pub(super) circle_label: String,
    /// Text beside data points, at drawing coordinates (log10 on a logarithmic axis), and
    /// whether it goes to the left of its point ([`Axes::point_labels_left`]).
    pub(super) point_labels: Vec<(f64, f64, String, bool)>,
    /// A polar picture: no axes, spokes instead.
    pub(super) polar: bool,
    /// The note: under the x axis, or in the lower right corner of a polar picture (its
    /// magnification).
    pub(super) note: Option<String>,
    /// The magnified view, at drawing coordinates.
    pub(super) inset: Option<InsetView>,
}

/// A magnified view laid out: its axes and its box in the plotting area (fractions).
pub(super) struct InsetView {
    /// The x axis of the view.
    pub(super) x: Axis,
    /// The y axis of the view.
    pub(super) y: Axis,
    /// `(left, bottom, right, top)` in fractions of the plotting area.
    pub(super) at: (f64, f64, f64, f64),
    /// Title above the view.
    pub(super) title: String,
    /// Whether the title gets the magnifications as drawn ([`super::Inset::magnification`]).
    pub(super) magnification: bool,
}

/// log10 of `v` on a logarithmic axis (NaN, so not drawn, for v ≤ 0), `v` itself otherwise.
fn scaled(log: bool) -> impl Fn(f64) -> f64 {
    move |v| match (log, v > 0.0) {
        (false, _) => v,
        (true, true) => v.log10(),
        (true, false) => f64::NAN,
    }
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

/// Plotting-area size in pixels for given left/right label areas (mirrors `draw::draw_panel`).
pub(super) fn plot_size(left: u32, right: u32, polar: bool) -> (f64, f64) {
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
    /// Checks and lays out `axes` under `title`; `polar_note` makes it a polar picture (no
    /// axes, the note in a corner). The error says what is wrong with the panel.
    pub(super) fn new(
        axes: &Axes,
        title: String,
        polar_note: Option<String>,
    ) -> std::result::Result<Self, String> {
        let polar = polar_note.is_some();
        let name = &axes.title;
        let (fx, fy) = (scaled(axes.x_log), scaled(axes.y_log));
        let map_range =
            |r: Option<(f64, f64)>, f: &dyn Fn(f64) -> f64| r.map(|(a, b)| (f(a), f(b)));
        let fixed_x = map_range(axes.x_range, &fx);
        let fixed_y = map_range(axes.y_range, &fy);
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
        check_range("x range", fixed_x)?;
        check_range("y range", fixed_y)?;
        let has_y2 = axes
            .series
            .iter()
            .any(|s| s.style == Style::LineOnSecondaryAxis);
        if has_y2 && axes.y2_label.is_none() {
            return Err(format!(
                "panel `{name}` has a right-axis series but no y2_label"
            ));
        }
        if has_y2 && axes.y_log {
            return Err(format!(
                "panel `{name}` has a logarithmic y axis and a right axis"
            ));
        }
        if let Some(inset) = &axes.inset {
            let (l, b, r, t) = inset.at;
            let inside = (0.0..=1.0).contains(&l) && (0.0..=1.0).contains(&t);
            if !(inside && l < r && r <= 1.0 && 0.0 <= b && b < t) {
                return Err(format!(
                    "the inset of panel `{name}` must lie in the plotting area, (left, bottom, right, top) increasing in [0, 1], not {:?}",
                    inset.at
                ));
            }
            check_range("inset x range", map_range(Some(inset.x_range), &fx))?;
            check_range("inset y range", map_range(Some(inset.y_range), &fy))?;
        }

        let mut palette = PALETTE.iter().cycle();
        let mut previous = None;
        let curves: Vec<Curve> = axes
            .series
            .iter()
            .map(|s| Curve {
                label: s.label.clone(),
                style: s.style,
                color: match (s.style, previous) {
                    (Style::Reference, _) => GREY,
                    (Style::ErrorBars, Some(c)) => c,
                    _ => *previous.insert(*palette.next().expect("cycle")),
                },
                segments: finite_runs(
                    &s.x.iter().map(|&v| fx(v)).collect::<Vec<_>>(),
                    &s.y.iter().map(|&v| fy(v)).collect::<Vec<_>>(),
                ),
            })
            .collect();
        let circles: Vec<Vec<(f64, f64)>> = axes
            .circles
            .iter()
            .filter(|(cx, cy, r)| cx.is_finite() && cy.is_finite() && r.is_finite())
            .map(|&(cx, cy, r)| circle_points((cx, cy), r, 1.0))
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
                .map(|(x, y)| (fx(*x), fy(*y)))
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
        let mut x_range = fixed_x.unwrap_or(x_auto);
        let mut y_range = match fixed_y {
            Some(r) => r,
            None => pad(
                extent(points(false).map(|p| p.1)).unwrap_or((0.0, 1.0)),
                0.05,
            ),
        };
        let axis = |r: (f64, f64), ticks: usize, log: bool| {
            if log {
                Axis::log(r)
            } else {
                Axis::new(r, ticks)
            }
        };
        let y2_data = extent(points(true).map(|p| p.1)).map(|r| pad(r, 0.05));
        let mut y2 = has_y2.then(|| Axis::new(y2_data.unwrap_or((0.0, 1.0)), Y_TICKS));
        let right_area = y2.as_ref().map_or(0, Axis::label_area);
        let left_area = |y: &Axis| left_label_area(y, polar);

        let mut y = axis(y_range, Y_TICKS, axes.y_log);
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
        let mut x = axis(x_range, X_TICKS, axes.x_log);
        let size = plot_size(left_area(&y), right_area, polar);
        let labelled = curves.iter().filter(|c| !c.label.is_empty()).count()
            + usize::from(!axes.circle_label.is_empty() && !circles.is_empty());
        let mut legend = None;
        if labelled > 1 {
            let widest = curves
                .iter()
                .map(|c| c.label.chars().count())
                .chain([axes.circle_label.chars().count()])
                .max()
                .unwrap_or(0) as u32
                + if has_y2 { 13 } else { 0 }; // " (right axis)"
            let w = f64::from(widest * LEGEND_CHAR_PX + 90) / size.0;
            let h = legend_height_px(labelled) / size.1;
            let uv = |y: &Axis, y2: Option<&Axis>| -> Vec<(f64, f64)> {
                let normalized = |(px, py): (f64, f64), ya: &Axis| {
                    ((px - x.lo) / x.span(), (py - ya.lo) / ya.span())
                };
                points(false)
                    .map(|p| normalized(p, y))
                    .chain(points(true).map(|p| normalized(p, y2.unwrap_or(y))))
                    .collect()
            };
            let (corner, covered) = least_crowded_corner(&uv(&y, y2.as_ref()), w, h);
            // Every corner holds data and the ranges are free: grow them at the top so that
            // the legend's height stays clear of the data (with a small gap).
            let grow = covered > 0 && fixed_y.is_none() && !axes.equal_aspect && !axes.y_log;
            // A polar picture (its profiles run through every corner) grows to the right
            // instead, keeping its aspect, so that the legend stands beside the data.
            let beside = covered > 0 && polar;
            legend = Some(if grow {
                let top = |a: &Axis| (a.lo, a.hi + a.span() * (h + 0.03) / (1.0 - h - 0.03));
                y = Axis::new(top(&y), Y_TICKS);
                y2 = y2.map(|a| Axis::new(top(&a), Y_TICKS));
                least_crowded_corner(&uv(&y, y2.as_ref()), w, h).0
            } else if beside {
                // the data at the left, the legend's width (and a gap) free on the right
                let (d0, d1) = data_x;
                let lo = d0 - 0.12 * (d1 - d0);
                let wider = (lo, lo + x.span().max((d1 - lo) / (1.0 - w - 0.03)));
                let (xr, yr) = equalize(wider, (y.lo, y.hi), size);
                let shift = wider.0 - xr.0;
                x = Axis::new((xr.0 + shift, xr.1 + shift), X_TICKS);
                y = Axis::new(yr, Y_TICKS);
                SeriesLabelPosition::UpperRight
            } else {
                corner
            });
        }
        let inset = axes.inset.as_ref().map(|i| InsetView {
            x: Axis::new((fx(i.x_range.0), fx(i.x_range.1)), 4),
            y: Axis::new((fy(i.y_range.0), fy(i.y_range.1)), 4),
            at: i.at,
            title: i.title.clone(),
            magnification: i.magnification,
        });
        let sides = [(&axes.point_labels, false), (&axes.point_labels_left, true)];
        let point_labels = (sides.iter())
            .flat_map(|(labels, left)| {
                (labels.iter()).map(|(px, py, t)| (fx(*px), fy(*py), t.clone(), *left))
            })
            .filter(|(px, py, ..)| px.is_finite() && py.is_finite())
            .collect();

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
            circle_label: axes.circle_label.clone(),
            point_labels,
            polar,
            note: polar_note.or_else(|| axes.note.clone()),
            inset,
        })
    }
}

/// Polar pictures have no y axis.
pub(super) fn left_label_area(y: &Axis, polar: bool) -> u32 {
    if polar {
        0
    } else {
        y.label_area()
    }
}

/// The corner whose `w` x `h` box (in plot-normalised units) covers the fewest points, and how
/// many it covers.
fn least_crowded_corner(uv: &[(f64, f64)], w: f64, h: f64) -> (SeriesLabelPosition, usize) {
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
        .map(|(pos, right, upper)| (pos, count(right, upper)))
        .min_by_key(|&(_, n)| n)
        .unwrap_or((UpperRight, 0))
}

/// A closed polyline around the circle of radius `r` about `c`, a point every `step_deg`
/// degrees (which must divide 360).
pub(super) fn circle_points(c: (f64, f64), r: f64, step_deg: f64) -> Vec<(f64, f64)> {
    let step = step_deg.to_radians();
    (0..=(360.0 / step_deg).round() as u32)
        .map(|k| f64::from(k) * step)
        .map(|t| (c.0 + r * t.cos(), c.1 + r * t.sin()))
        .collect()
}

/// The height (px) of a legend of `rows` entries.
pub(super) fn legend_height_px(rows: usize) -> f64 {
    f64::from(rows as u32 * (LEGEND_PX + 12) + 40)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::plot::Series;

    #[test]
    fn error_bars_take_the_colour_of_the_markers_before_them() {
        // seen to fail when ErrorBars took the next palette colour like any other series
        let (x, y) = ([1.0, 2.0], [1.0, 2.0]);
        let axes = Axes::new(
            "t",
            "x",
            "y",
            vec![
                Series::new("a", &x, &y, Style::Points),
                Series::new("", &x, &y, Style::ErrorBars),
                Series::new("b", &x, &y, Style::Points),
                Series::new("", &x, &y, Style::ErrorBars),
            ],
        );
        let colors: Vec<RGBColor> = (Panel::new(&axes, "t".into(), None).unwrap().curves)
            .iter()
            .map(|c| c.color)
            .collect();
        assert_eq!(colors, [PALETTE[0], PALETTE[0], PALETTE[1], PALETTE[1]]);
    }
}
