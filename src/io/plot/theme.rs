//! The one look of every figure: panel size, margins and label areas (pixels), line width and
//! tick counts, the embedded font and its text styles, and the colour palette.

use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::FontStyle;

pub(super) const PANEL_SIZE: (u32, u32) = (1200, 800);
pub(super) const TITLE_BAND: u32 = 50;
/// Margins around the chart: top leaves room for a "×10ⁿ" factor above the y axis.
pub(super) const MARGIN: (u32, u32, u32, u32) = (30, 10, 15, 35); // top, bottom, left, right
pub(super) const X_LABEL_AREA: u32 = 80;
pub(super) const TITLE_PX: u32 = 32;
pub(super) const DESC_PX: u32 = 26;
pub(super) const TICK_PX: u32 = 22;
pub(super) const LEGEND_PX: u32 = 22;
/// Text beside single data points.
pub(super) const POINT_LABEL_PX: u32 = 18;
/// Tick labels and title of an inset.
pub(super) const INSET_TICK_PX: u32 = 18;
/// Distance of the first line of a note from the x axis (under its tick labels).
pub(super) const NOTE_TOP_PX: u32 = 38;
/// Height of a line of a note under the x axis.
pub(super) const NOTE_LINE_PX: u32 = 30;
/// Radius of a marker.
pub(super) const MARKER_PX: u32 = 5;
/// Approximate advance of a tick-label character (DejaVu Sans digits are 0.636 em wide).
pub(super) const TICK_CHAR_PX: u32 = 14;
pub(super) const LEGEND_CHAR_PX: u32 = 13;
pub(super) const X_TICKS: usize = 10;
pub(super) const Y_TICKS: usize = 8;
pub(super) const LINE_WIDTH: u32 = 3;
pub(super) const FONT: &str = "sans-serif";
/// DejaVu Sans (`assets/fonts/`), embedded in the binary.
pub(super) const FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// matplotlib's "tab10" without its grey, which is kept for reference curves and circles.
pub(super) const PALETTE: [RGBColor; 9] = [
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
pub(super) const GREY: RGBColor = RGBColor(100, 100, 100);

/// Registers the embedded DejaVu Sans once per process.
pub(super) fn ensure_font() -> std::result::Result<(), String> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| "embedded DejaVu Sans could not be loaded".to_owned())
}

/// Black text of `px` pixels in the embedded font.
pub(super) fn text(px: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, px).into_font()).color(&BLACK)
}
