//! Drawing laid-out panels into a PNG: the figure's grid of panels, Cartesian axes with the
//! grid, tick labels and "×10ⁿ" factors (decades on logarithmic axes), bands, circles, series,
//! point labels, legend, note and inset. The file is written
//! through [`crate::io::output::write_atomic`].

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::TRANSPARENT;

use super::axis::Axis;
use super::clip::{clip_polygon, clip_polyline, inside, split_at_sharp_turns, Rect};
use super::panel::{left_label_area, InsetView, Panel};
use super::polar::{draw_polar_grid, Chart};
use super::text::GlyphBackend;
use super::theme::{
    ensure_font, text, DESC_PX, GREY, INSET_TICK_PX, LEGEND_PX, LINE_WIDTH, MARGIN, MARKER_PX,
    NOTE_LINE_PX, NOTE_TOP_PX, PANEL_SIZE, POINT_LABEL_PX, TICK_PX, TITLE_BAND, TITLE_PX,
    X_LABEL_AREA,
};
use super::Style;
use super::{magnified_title, plot_error};
use crate::io::output::{write_atomic, write_bytes};
use crate::Result;

/// What drawing returns: plotters' errors, boxed.
pub(super) type DrawResult<'b> = std::result::Result<(), Box<dyn std::error::Error + 'b>>;

/// Draws `panels` into the PNG at `path` (1-3 side by side, 4 as 2x2, more in rows of 3),
/// atomically.
pub(super) fn draw_figure(path: &Path, panels: &[Panel]) -> Result<()> {
    draw_figure_in(path, panels, grid(panels.len() as u32))
}

/// [`draw_figure`] with the panels in a grid of `(columns, rows)`, filled row by row. The
/// picture is drawn in memory, starting white, and encoded by [`encode_png`].
pub(super) fn draw_figure_in(path: &Path, panels: &[Panel], layout: (u32, u32)) -> Result<()> {
    let (w, h) = figure_size(layout);
    let mut rgb = vec![u8::MAX; 3 * w as usize * h as usize];
    let backend = BitMapBackend::with_buffer(&mut rgb, (w, h));
    draw_frames(path, backend, std::slice::from_ref(&panels), layout, true)?;
    let png = encode_png(&rgb, (w, h)).map_err(|e| plot_error(path, e))?;
    write_bytes(path, &png)
}

/// The PNG of the 8-bit RGB picture `rgb` of `(width, height)` pixels. Each row is stored as
/// PNG's "Paeth" prediction from its neighbours and compressed by the fast deflate coder.
/// Measured on a run's wear figure (1200x800 px), against the encoder plotters uses (choosing
/// one of four filters per row): 13.9 M instead of 28.6 M instructions at 81 kB instead of
/// 76 kB. The "Up" filter (each row against the row above) was cheaper still, 7.8 M, but
/// doubled the files (151 kB; the committed figures 5.3 MB -> 8.6 MB), which every
/// regeneration would add to the repository.
fn encode_png(rgb: &[u8], (width, height): (u32, u32)) -> std::result::Result<Vec<u8>, String> {
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::FilterType::Paeth);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::NonAdaptive);
    let written = encoder.write_header().and_then(|mut writer| {
        writer.write_image_data(rgb)?;
        writer.finish()
    });
    written.map_err(|e| e.to_string())?;
    Ok(png)
}

/// Draws each element of `frames` (the panels of one frame, laid out as [`draw_figure`]
/// does) as a frame of the looping GIF at `path`, `delay_ms` apart, atomically. plotters'
/// GIF backend writes only to a path: it writes the temporary file of
/// [`write_atomic`], which renames it into place when the last frame is in.
pub(super) fn draw_animation<P: AsRef<[Panel]>>(
    path: &Path,
    frames: &[P],
    delay_ms: u32,
) -> Result<()> {
    let first = frames
        .first()
        .ok_or_else(|| plot_error(path, "an animation needs at least one frame"))?;
    let layout = grid(first.as_ref().len() as u32);
    write_atomic(path, |tmp| {
        let backend = BitMapBackend::gif(tmp, figure_size(layout), delay_ms)
            .map_err(|e| plot_error(path, e))?;
        draw_frames(path, backend, frames, layout, false)
    })
}

/// The grid of a figure of `n` panels: (columns, rows).
fn grid(n: u32) -> (u32, u32) {
    let cols = if n == 4 { 2 } else { n.min(3) };
    (cols, n.div_ceil(cols))
}

/// The size (px) of a figure whose panels are laid out in `(columns, rows)`.
fn figure_size((cols, rows): (u32, u32)) -> (u32, u32) {
    (cols * PANEL_SIZE.0, rows * PANEL_SIZE.1)
}

/// Draws every frame onto `backend`, each presented once (a PNG has one frame, a GIF many),
/// on white: the first frame is not cleared if the backend `starts_white`. Notes of Cartesian
/// panels go under the x axis; every panel of every frame keeps the same plot height, so that
/// frames of an animation line up.
fn draw_frames<P: AsRef<[Panel]>>(
    path: &Path,
    backend: BitMapBackend<'_>,
    frames: &[P],
    (cols, rows): (u32, u32),
    starts_white: bool,
) -> Result<()> {
    ensure_font().map_err(|m| plot_error(path, m))?;
    let note_lines = frames
        .iter()
        .flat_map(|f| f.as_ref())
        .filter(|p| !p.polar)
        .filter_map(|p| p.note.as_ref())
        .map(|s| s.lines().count() as u32)
        .max()
        .unwrap_or(0);
    let root = GlyphBackend::new(backend).into_drawing_area();
    let drawn: DrawResult = (|| {
        for (k, panels) in frames.iter().enumerate() {
            let panels = panels.as_ref();
            if k > 0 || !starts_white {
                root.fill(&WHITE)?;
            }
            let areas = root.split_evenly((rows as usize, cols as usize));
            for (area, panel) in areas.iter().zip(panels) {
                draw_panel(area, panel, note_lines)?;
            }
            root.present()?;
        }
        Ok(())
    })();
    drawn.map_err(|e| plot_error(path, e))
}

/// Draws one panel; Cartesian panels leave `note_lines` lines under the x axis for notes.
fn draw_panel<'b>(
    area: &DrawingArea<GlyphBackend<'b>, Shift>,
    p: &Panel,
    note_lines: u32,
) -> DrawResult<'b> {
    let polar = p.polar;
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
        .x_label_area_size(if polar {
            0
        } else {
            X_LABEL_AREA + note_lines * NOTE_LINE_PX
        })
        .y_label_area_size(left_label_area(&p.y, polar))
        .right_y_label_area_size(p.y2.as_ref().map_or(0, Axis::label_area))
        .build_cartesian_2d(p.x.lo..p.x.hi, p.y.lo..p.y.hi)?
        .set_secondary_coord(p.x.lo..p.x.hi, y2.lo..y2.hi);

    if polar {
        draw_polar_grid(&mut chart, p)?;
    } else {
        draw_axes(&mut chart, p, (&p.x, &p.y), (TICK_PX, DESC_PX), true)?;
    }
    let view = (p.x.lo, p.x.hi, p.y.lo, p.y.hi);
    let view2 = (p.x.lo, p.x.hi, y2.lo, y2.hi);
    draw_data(&mut chart, p, p.legend.is_some(), view, Some(view2))?;
    for (x, y, label, left) in p.point_labels.iter().filter(|l| inside((l.0, l.1), view)) {
        // an en space keeps the text clear of the marker it names
        let (label, anchor) = if *left {
            (format!("{label}\u{2002}"), HPos::Right)
        } else {
            (format!("\u{2002}{label}"), HPos::Left)
        };
        chart.draw_series(std::iter::once(Text::new(
            label,
            (*x, *y),
            text(POINT_LABEL_PX).pos(Pos::new(anchor, VPos::Center)),
        )))?;
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

    // Common "×10ⁿ" factors at the ends of the axes, and the note, in pixel coordinates.
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
    if let Some(s) = &p.note {
        for (k, line) in s.lines().enumerate() {
            if polar {
                // no axes: the note sits in the lower right corner of the picture
                let y = ys.end - 10 - (s.lines().count() - 1 - k) as i32 * NOTE_LINE_PX as i32;
                note(line, (xs.end - 10, y), HPos::Right, VPos::Bottom)?;
            } else {
                // between the tick labels and the axis description (at the area's bottom)
                let y = ys.end + NOTE_TOP_PX as i32 + k as i32 * NOTE_LINE_PX as i32;
                note(line, (xs.start, y), HPos::Left, VPos::Top)?;
            }
        }
    }
    if let Some(inset) = &p.inset {
        draw_inset(area, &mut chart, p, inset)?;
    }
    Ok(())
}

/// The grid and tick labels of Cartesian axes `(x, y)` with tick labels and descriptions of
/// the given sizes (px); minor grid lines at 2..9 × 10ⁿ on logarithmic axes. The `main` axes of
/// a panel also get the axis descriptions and the right axis, if any (an inset gets neither).
fn draw_axes<'b>(
    chart: &mut Chart<'_, 'b>,
    p: &Panel,
    (x, y): (&Axis, &Axis),
    (tick_px, desc_px): (u32, u32),
    main: bool,
) -> DrawResult<'b> {
    let x_fmt = |v: &f64| x.label(*v);
    let y_fmt = |v: &f64| y.label(*v);
    let y2 = p.y2.as_ref().unwrap_or(&p.y);
    let y2_fmt = |v: &f64| y2.label(*v);
    let minor = BLACK.mix(0.05);
    for v in x.minor() {
        chart.draw_series(LineSeries::new([(v, y.lo), (v, y.hi)], minor))?;
    }
    for v in y.minor() {
        chart.draw_series(LineSeries::new([(x.lo, v), (x.hi, v)], minor))?;
    }
    chart
        .configure_mesh()
        .x_desc(if main { p.x_label.as_str() } else { "" })
        .y_desc(if main { p.y_label.as_str() } else { "" })
        .x_labels(x.ticks())
        .y_labels(y.ticks())
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(text(tick_px))
        .axis_desc_style(text(desc_px))
        .bold_line_style(BLACK.mix(0.1))
        .light_line_style(TRANSPARENT)
        .draw()?;
    if let (Some(label), true) = (&p.y2_label, main) {
        chart
            .configure_secondary_axes()
            .y_desc(label.as_str())
            .y_labels(y2.ticks())
            .y_label_formatter(&y2_fmt)
            .label_style(text(tick_px))
            .axis_desc_style(text(desc_px))
            .draw()?;
    }
    Ok(())
}

/// The circles, bands and series of a panel cut to `view` (and right-axis series to `view2`;
/// without it they are left out, as in an inset), with their legend entries when `legend`.
fn draw_data<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    p: &Panel,
    legend: bool,
    view: Rect,
    view2: Option<Rect>,
) -> DrawResult<'b> {
    let mut circle_labelled = !legend || p.circle_label.is_empty();
    for circle in &p.circles {
        for run in clip_polyline(circle, view) {
            let anno = chart.draw_series(LineSeries::new(run, GREY.stroke_width(2)))?;
            if !circle_labelled {
                circle_labelled = true;
                let line = GREY.stroke_width(LINE_WIDTH);
                anno.label(p.circle_label.as_str())
                    .legend(move |at| PathElement::new([(at.0, at.1), (at.0 + 30, at.1)], line));
            }
        }
    }
    for (color, outline) in &p.shades {
        let cut = clip_polygon(outline, view);
        if cut.len() > 2 {
            chart.draw_series(std::iter::once(Polygon::new(cut, color.mix(0.22).filled())))?;
        }
    }
    let dual = p.y2.is_some();
    for c in &p.curves {
        let secondary = c.style == Style::LineOnSecondaryAxis;
        let Some(clip) = (if secondary { view2 } else { Some(view) }) else {
            continue;
        };
        let line = c.color.stroke_width(LINE_WIDTH);
        let marker = |q| Circle::new(q, MARKER_PX, c.color.filled());
        let mut labelled = !legend || c.label.is_empty();
        // Dashes are drawn piece by piece already: only joined lines are cut at sharp turns.
        let joined = !matches!(c.style, Style::Dashed | Style::Reference | Style::Points);
        let px = |q: (f64, f64)| {
            if secondary {
                chart.borrow_secondary().as_coord_spec().translate(&q)
            } else {
                chart.as_coord_spec().translate(&q)
            }
        };
        let runs: Vec<Vec<(f64, f64)>> = c
            .segments
            .iter()
            .flat_map(|run| clip_polyline(run, clip))
            .flat_map(|run| {
                if joined {
                    split_at_sharp_turns(&run, px)
                } else {
                    vec![run]
                }
            })
            .chain(std::iter::once(Vec::new())) // an empty run carries the legend entry
            .collect();
        for run in runs {
            if run.is_empty() && labelled {
                continue;
            }
            let points = run.iter().copied();
            let anno = match c.style {
                Style::Line | Style::ErrorBars => {
                    chart.draw_series(LineSeries::new(points, line))?
                }
                Style::Dashed | Style::Reference => {
                    chart.draw_series(DashedLineSeries::new(points, 14, 8, line))?
                }
                Style::Points => {
                    chart.draw_series(points.filter(|&q| inside(q, clip)).map(marker))?
                }
                Style::LinePoints => {
                    chart.draw_series(LineSeries::new(points.clone(), line))?;
                    chart.draw_series(points.filter(|&q| inside(q, clip)).map(marker))?
                }
                Style::LineOnSecondaryAxis => {
                    chart.draw_secondary_series(LineSeries::new(points, line))?
                }
            };
            if !labelled {
                labelled = true;
                let (line, marker, gap) = legend_parts(c.style, c.color);
                let side = match (dual, secondary) {
                    (false, _) => "",
                    (true, true) => " (right axis)",
                    (true, false) => " (left axis)",
                };
                anno.label(format!("{}{side}", c.label)).legend(move |at| {
                    EmptyElement::at(at)
                        + PathElement::new([(0, 0), (15 - gap, 0)], line)
                        + PathElement::new([(15 + gap, 0), (30, 0)], line)
                        + Circle::new((15, 0), MARKER_PX + 1, marker)
                });
            }
        }
    }
    Ok(())
}

/// The magnified view of a panel: a white box in the plotting area with its own axes, the
/// panel's left-axis data over the view's ranges, and the zoomed region outlined on the panel.
fn draw_inset<'b>(
    area: &DrawingArea<GlyphBackend<'b>, Shift>,
    chart: &mut Chart<'_, 'b>,
    p: &Panel,
    inset: &InsetView,
) -> DrawResult<'b> {
    let (x, y) = (&inset.x, &inset.y);
    chart.draw_series(std::iter::once(Rectangle::new(
        [(x.lo, y.lo), (x.hi, y.hi)],
        BLACK.stroke_width(1),
    )))?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let (bx, by) = area.get_base_pixel();
    let (w, h) = (f64::from(xs.end - xs.start), f64::from(ys.end - ys.start));
    let (l, b, r, t) = inset.at;
    let left = xs.start - bx + (l * w) as i32;
    let top = ys.start - by + ((1.0 - t) * h) as i32;
    let size = (((r - l) * w) as u32, ((t - b) * h) as u32);
    let view = area.clone().shrink((left, top), size);
    view.fill(&WHITE)?;
    let (title_area, body) = view.split_vertically(INSET_TICK_PX + 12);
    let y_area = y.label_area() * INSET_TICK_PX / TICK_PX;
    let mut zoom = ChartBuilder::on(&body)
        .margin(6)
        .x_label_area_size(INSET_TICK_PX + 14)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x.lo..x.hi, y.lo..y.hi)?
        .set_secondary_coord(x.lo..x.hi, y.lo..y.hi);
    let title = if inset.magnification {
        // pixels per data unit of the view's chart over the panel's, on each axis
        let (zx, zy) = zoom.plotting_area().get_pixel_range();
        let per =
            |px: &std::ops::Range<i32>, a: &Axis| f64::from(px.end - px.start) / (a.hi - a.lo);
        let magnify = |z, zoomed, main, axis| per(z, zoomed) / per(main, axis);
        magnified_title(
            &inset.title,
            magnify(&zx, x, &xs, &p.x),
            magnify(&zy, y, &ys, &p.y),
        )
    } else {
        inset.title.clone()
    };
    title_area.draw_text(
        &title,
        &text(INSET_TICK_PX).pos(Pos::new(HPos::Center, VPos::Center)),
        ((size.0 / 2) as i32, ((INSET_TICK_PX + 12) / 2) as i32),
    )?;
    draw_axes(&mut zoom, p, (x, y), (INSET_TICK_PX, INSET_TICK_PX), false)?;
    draw_data(&mut zoom, p, false, (x.lo, x.hi, y.lo, y.hi), None)?;
    view.draw(&Rectangle::new(
        [(0, 0), (size.0 as i32 - 1, size.1 as i32 - 1)],
        BLACK.stroke_width(1),
    ))?;
    Ok(())
}

/// Legend sample matching how the series is drawn: (line style, marker style, half dash gap).
/// One element shape serves every style; the unused parts are transparent.
fn legend_parts(style: Style, color: RGBColor) -> (ShapeStyle, ShapeStyle, i32) {
    let (line, hidden) = (color.stroke_width(LINE_WIDTH), TRANSPARENT.into());
    match style {
        Style::Points => (hidden, color.filled(), 0),
        Style::LinePoints => (line, color.filled(), 0),
        Style::Dashed | Style::Reference => (line, hidden, 3),
        Style::Line | Style::LineOnSecondaryAxis | Style::ErrorBars => (line, hidden, 0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The PNG decodes to the pixels drawn, every byte. Would fail on a wrong colour type, bit
    /// depth or row length, or a filter applied without its type byte (checked: encoding with
    /// `set_color(png::ColorType::Rgba)` fails here).
    #[test]
    fn png_decodes_to_the_pixels_drawn() {
        let (w, h) = (7u32, 5u32);
        // varied bytes, so that every row differs from the row above
        let rgb: Vec<u8> = (0..3 * w * h).map(|i| (i * 37 % 251) as u8).collect();
        let png = encode_png(&rgb, (w, h)).unwrap();
        let mut reader = png::Decoder::new(png.as_slice()).read_info().unwrap();
        let mut decoded = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut decoded).unwrap();
        assert_eq!(
            (info.width, info.height, info.color_type, info.bit_depth),
            (w, h, png::ColorType::Rgb, png::BitDepth::Eight)
        );
        assert_eq!(&decoded[..info.buffer_size()], &rgb[..]);
    }
}
