//! Drawing laid-out panels into a PNG: the figure's grid of panels, Cartesian axes with the
//! grid, tick labels and "×10ⁿ" factors, bands, circles, series and legend. The file is written
//! through [`crate::io::output::write_atomic`].

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::TRANSPARENT;

use super::axis::Axis;
use super::panel::{left_label_area, Panel};
use super::plot_error;
use super::polar::draw_polar_grid;
use super::theme::{
    ensure_font, text, DESC_PX, GREY, LEGEND_PX, LINE_WIDTH, MARGIN, PANEL_SIZE, TICK_PX,
    TITLE_BAND, TITLE_PX, X_LABEL_AREA, X_TICKS, Y_TICKS,
};
use super::Style;
use crate::io::output::write_atomic;
use crate::Result;

/// What drawing returns: plotters' errors, boxed.
pub(super) type DrawResult<'b> = std::result::Result<(), Box<dyn std::error::Error + 'b>>;

/// Draws `panels` into the PNG at `path` (1-3 side by side, 4 as 2x2, more in rows of 3),
/// atomically.
pub(super) fn draw_figure(path: &Path, panels: &[Panel]) -> Result<()> {
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
