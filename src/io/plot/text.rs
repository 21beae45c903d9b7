//! Text with correct glyph placement: a drawing backend that wraps plotters' bitmap backend
//! and lays out and rasterises every string itself with `ab_glyph`.
//!
//! Why: plotters 0.3.7 draws each glyph of its `ab_glyph` font path at the pen position with
//! the glyph's *ink box* starting there (`q.draw` gives pixels relative to `px_bounds().min`,
//! and that offset, the glyph's left side bearing, is dropped). Every glyph is thus shifted left
//! by its own side bearing, so gaps open after glyphs with a wide bearing and close after
//! glyphs with a narrow or negative one ("traje ctory", "rela tive"). The advance widths used
//! for layout are right, so only the drawing is wrong; it cannot be fixed through plotters'
//! font API (its `FontData` is chosen at compile time). This backend delegates every shape
//! to the bitmap backend and places each glyph at pen position + kerning with its bearing, at
//! sub-pixel precision. The vertical layout keeps plotters' box (width = sum of advances and
//! kerning, height = size / 1.24, as `estimate_text_size` reports it to the chart layout) and
//! centres the capital height in it, so a label anchored at its vertical centre sits on its
//! tick.

use std::sync::OnceLock;

use ab_glyph::{point, Font, FontRef, GlyphId, PxScale, ScaleFont};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};

use super::theme::FONT_BYTES;

/// The embedded DejaVu Sans, parsed once.
fn font() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Glyphs of `text` at `size` px with their pen positions (px), and the total advance.
fn layout(font: &FontRef<'static>, size: f64, text: &str) -> (Vec<(GlyphId, f32)>, f32) {
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let mut pen = 0f32;
    let mut prev: Option<GlyphId> = None;
    let mut glyphs = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        glyphs.push((id, pen));
        pen += scaled.h_advance(id);
        prev = Some(id);
    }
    (glyphs, pen)
}

/// The layout box of `text` as plotters reports it: (width, height) in pixels.
fn box_size(width: f32, size: f64) -> (i32, i32) {
    (width.ceil() as i32, (size / 1.24) as i32)
}

/// Rasterises `text` into `(x, y, coverage)` pixels relative to the top-left corner of its
/// layout box (before anchoring and rotation).
fn rasterise(font: &FontRef<'static>, size: f64, text: &str) -> (Vec<(i32, i32, f32)>, f32) {
    let scale = PxScale::from(size as f32);
    let scaled = font.as_scaled(scale);
    let (glyphs, width) = layout(font, size, text);
    let (_, height) = box_size(width, size);
    // Capital height, from the outline of "H"; centred in the box.
    let cap = font
        .outline_glyph(scaled.scaled_glyph('H'))
        .map_or(0.7 * size as f32, |g| {
            let b = g.px_bounds();
            b.max.y - b.min.y
        });
    let baseline = 0.5 * (height as f32 + cap);
    let mut pixels = Vec::new();
    for (id, pen) in glyphs {
        let glyph = id.with_scale_and_position(scale, point(pen, baseline));
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            let (x0, y0) = (b.min.x as i32, b.min.y as i32);
            outline.draw(|x, y, c| {
                if c > 0.0 {
                    pixels.push((x0 + x as i32, y0 + y as i32, c));
                }
            });
        }
    }
    (pixels, width)
}

/// The bitmap backend with this module's text rendering (module documentation).
pub(super) struct GlyphBackend<'a> {
    inner: BitMapBackend<'a>,
}

impl<'a> GlyphBackend<'a> {
    /// Wraps `inner`; shapes go to it unchanged, text is drawn here.
    pub(super) fn new(inner: BitMapBackend<'a>) -> Self {
        GlyphBackend { inner }
    }
}

/// The error type of the wrapped bitmap backend.
type BitmapError<'a> = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

impl<'a> DrawingBackend for GlyphBackend<'a> {
    type ErrorType = BitmapError<'a>;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let Some(font) = font() else {
            return self.inner.estimate_text_size(text, style);
        };
        let (_, width) = layout(font, style.size(), text);
        let (w, h) = box_size(width, style.size());
        Ok((w.max(0) as u32, h.max(0) as u32))
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let Some(font) = font() else {
            return self.inner.draw_text(text, style, pos);
        };
        let (pixels, width) = rasterise(font, style.size(), text);
        let (width, height) = box_size(width, style.size());
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let transform = style.transform();
        let (w, h) = self.get_size();
        for (x, y, coverage) in pixels {
            let (x, y) = transform.transform(x + dx, y + dy);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                let alpha = color.alpha * f64::from(coverage.min(1.0));
                self.inner.draw_pixel(
                    (x, y),
                    BackendColor {
                        alpha,
                        rgb: color.rgb,
                    },
                )?;
            }
        }
        Ok(())
    }
}
