//! Pictures of a planar mechanism: one pose as a PNG ([`render_mechanism`]) or a sequence of
//! poses as an animated GIF ([`render_animation`]), drawn through the same panels, theme and
//! text path as every other figure.
//!
//! A [`MechanismPicture`] is plain geometry in millimetres, so that this layer knows nothing of
//! the mechanism's types (`simulation::picture` builds it from a pose). Bodies are lines in
//! palette colours (the legend names them), ideal revolute joints small grey circles, ground
//! points markers, translational guides grey dashed lines across the view, and each clearance
//! joint its bearing circle (radius R) with the journal dashed inside it and a label with its
//! name and clearance. When the first clearance joint carries an orbit, an inset magnifies the
//! journal centre's path in its clearance circle around the current bearing centre, so that the
//! micrometre motion shows beside a mechanism of centimetres.
//!
//! Layout: a mechanism wider than the plotting area fills the lower part of an equal-aspect
//! view, keeping the upper part free for the inset (upper left) and the legend (upper right,
//! the empty corner it prefers); a taller one fills the left part, with the legend at the upper
//! right and the inset below it.
//! Every frame of an animation shares the view of the union of its poses, so nothing jumps.

use std::path::Path;

use super::axis::Axis;
use super::draw::{draw_animation, draw_figure};
use super::panel::{circle_points, legend_height_px, plot_size, Panel};
use super::theme::{INSET_TICK_PX, NOTE_LINE_PX, TICK_PX, Y_TICKS};
use super::{plot_error, round2, Axes, Inset, Series, Style};
use crate::Result;

/// A point in the plane (mm).
pub type Point = (f64, f64);

/// One pose of a mechanism to draw, in millimetres in the ground frame.
#[derive(Clone, Debug, Default)]
pub struct MechanismPicture {
    /// Title above the picture (the scene's title).
    pub title: String,
    /// Lines under the x axis (the instant drawn, how the pose was assembled).
    pub note: String,
    /// The moving bodies, in the scene's order.
    pub bodies: Vec<BodyShape>,
    /// Points of the ground that joints use.
    pub ground: Vec<Point>,
    /// Centres of the ideal revolute joints.
    pub pins: Vec<Point>,
    /// Guide lines of the translational joints.
    pub guides: Vec<Guide>,
    /// The clearance joints.
    pub clearance: Vec<ClearanceShape>,
}

/// A body as a polyline through its points.
#[derive(Clone, Debug, Default)]
pub struct BodyShape {
    /// Legend entry, e.g. `"crank (driver, 2000 r/min)"`.
    pub label: String,
    /// The polyline (closed by repeating its first point when it outlines an area).
    pub outline: Vec<Point>,
}

/// The guide line of a translational joint: through `through`, along `direction`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Guide {
    /// A point of the line (mm).
    pub through: Point,
    /// Its direction (any length but zero).
    pub direction: Point,
}

/// A clearance revolute joint at one instant.
#[derive(Clone, Debug, Default)]
pub struct ClearanceShape {
    /// The joint's name, as the scene writes it.
    pub name: String,
    /// Bearing centre (mm).
    pub bearing: Point,
    /// Journal centre (mm).
    pub journal: Point,
    /// Bearing radius R (mm).
    pub r_bearing: f64,
    /// Journal radius (mm); the radial clearance is `r_bearing - r_journal`.
    pub r_journal: f64,
    /// The path of the journal centre relative to the bearing centre up to this instant (mm),
    /// ending at the current `journal - bearing`; empty: no inset (a pose at rest).
    pub orbit: Vec<Point>,
}

impl ClearanceShape {
    /// The radial clearance (mm).
    fn clearance(&self) -> f64 {
        self.r_bearing - self.r_journal
    }
}

/// How much of the view's width a tall mechanism fills, from the left; the rest is free for
/// the legend (upper right) and the inset (lower right).
const SIDE_SHARE: f64 = 0.52;
/// Plotting area of a panel (px), about: equal aspect and tick labels change it a little.
const PLOT_PX: (f64, f64) = (1100.0, 620.0);
/// Advance of a character of a point label (px, 18 px DejaVu Sans averages about 10).
const LABEL_CHAR_PX: f64 = 10.5;
/// Radius of an ideal revolute joint's circle, as a fraction of the view's width.
const PIN_FRACTION: f64 = 0.012;
/// Inset half-height in clearances: the clearance circle and a margin.
const INSET_REACH: f64 = 1.3;

/// Renders `picture` as a PNG at `path` (written atomically).
pub fn render_mechanism(path: &Path, picture: &MechanismPicture) -> Result<()> {
    let view = view(std::slice::from_ref(picture)).ok_or_else(|| no_points(path))?;
    let panel = panel(picture, view).map_err(|m| plot_error(path, m))?;
    draw_figure(path, &[panel])
}

/// Renders `frames` as an animated GIF at `path` that loops forever, `delay_ms` per frame,
/// all in one view (written atomically). Every frame is checked before the file is created.
pub fn render_animation(path: &Path, frames: &[MechanismPicture], delay_ms: u32) -> Result<()> {
    let view = view(frames).ok_or_else(|| no_points(path))?;
    let panels = frames
        .iter()
        .map(|f| panel(f, view).map(|p| vec![p]))
        .collect::<std::result::Result<Vec<_>, String>>()
        .map_err(|m| plot_error(path, m))?;
    draw_animation(path, &panels, delay_ms)
}

fn no_points(path: &Path) -> crate::Error {
    plot_error(path, "a mechanism picture needs at least one finite point")
}

/// The ranges of a view (mm) and where its inset goes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct View {
    x: (f64, f64),
    y: (f64, f64),
    /// The inset's box in the plotting area (fractions: left, bottom, right, top).
    inset_at: (f64, f64, f64, f64),
}

/// The points a picture must show: outlines, pins, ground points and bearing circles.
fn points(p: &MechanismPicture) -> impl Iterator<Item = Point> + '_ {
    let bodies = p.bodies.iter().flat_map(|b| b.outline.iter().copied());
    let bearings = p.clearance.iter().flat_map(|c| {
        let (x, y, r) = (c.bearing.0, c.bearing.1, c.r_bearing);
        [(x - r, y - r), (x + r, y + r)]
    });
    bodies
        .chain(p.pins.iter().copied())
        .chain(p.ground.iter().copied())
        .chain(bearings)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
}

/// The view of `frames`: their bounding box padded, with free room above or beside it
/// (module doc).
fn view(frames: &[MechanismPicture]) -> Option<View> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in frames.iter().flat_map(points) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 > x1 {
        return None;
    }
    // a margin of 6 % of the larger side (at least 1 mm for a mechanism of one point)
    let pad = (0.06 * (x1 - x0).max(y1 - y0)).max(1.0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let (w, h) = (x1 - x0, y1 - y0);
    // Above a wide mechanism: the legend's height (and a gap); the inset shares that band.
    let top_share = 1.0 - legend_height(&frames[0]) - 0.04;
    let aspect = PLOT_PX.0 / PLOT_PX.1;
    // the height of the view (mm) each layout needs at equal aspect: the smaller draws larger
    let top = (w / aspect).max(h / top_share);
    let side = (w / SIDE_SHARE / aspect).max(h);
    Some(if top <= side {
        View {
            x: (x0, x1),
            y: (y0, y0 + h / top_share),
            inset_at: (0.01, top_share + 0.02, 0.38, 0.99),
        }
    } else {
        View {
            x: (x0, x0 + w / SIDE_SHARE),
            y: (y0, y1),
            inset_at: (0.58, 0.01, 0.99, 0.47),
        }
    })
}

/// The legend's height as a fraction of the plotting area's (as `panel` sizes it): one row
/// per body, bearing, orbit and the ideal revolute joints.
fn legend_height(p: &MechanismPicture) -> f64 {
    let orbits = p.clearance.iter().filter(|c| !c.orbit.is_empty()).count();
    let rows = p.bodies.len() + p.clearance.len() + orbits + usize::from(!p.pins.is_empty());
    legend_height_px(rows) / PLOT_PX.1
}

/// A closed polyline approximating the circle of radius `r` around `c`, every 3°.
fn circle(c: Point, r: f64) -> Vec<Point> {
    circle_points(c, r, 3.0)
}

/// The segment of `g` across the view `((x0, x1), (y0, y1))`: its line between the
/// projections of the view's corners.
fn guide_segment(g: &Guide, ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64))) -> Vec<Point> {
    let (px, py) = g.through;
    let norm = g.direction.0.hypot(g.direction.1);
    let (dx, dy) = (g.direction.0 / norm, g.direction.1 / norm);
    let along =
        [(x0, y0), (x0, y1), (x1, y0), (x1, y1)].map(|(x, y)| (x - px) * dx + (y - py) * dy);
    let lo = along.iter().copied().fold(f64::MAX, f64::min);
    let hi = along.iter().copied().fold(f64::MIN, f64::max);
    vec![(px + lo * dx, py + lo * dy), (px + hi * dx, py + hi * dy)]
}

/// The view's box grown to three times its size around its centre: equal aspect may widen
/// the view, and a guide must still cross it (lines are cut at the view's edges).
fn around(view: View) -> ((f64, f64), (f64, f64)) {
    let grow = |(lo, hi): (f64, f64)| (2.0 * lo - hi, 2.0 * hi - lo);
    (grow(view.x), grow(view.y))
}

/// A series' points as owned columns, with its label and style.
struct Owned {
    label: String,
    x: Vec<f64>,
    y: Vec<f64>,
    style: Style,
}

fn owned(label: impl Into<String>, pts: impl IntoIterator<Item = Point>, style: Style) -> Owned {
    let (x, y) = pts.into_iter().unzip();
    Owned {
        label: label.into(),
        x,
        y,
        style,
    }
}

/// A length in mm as the scene would write it (shortest form, no trailing zeros).
fn mm(v: f64) -> String {
    format!("{}", (v * 1e6).round() / 1e6)
}

/// The series of a picture: bodies, guides, ground points, clearance joints (bearing circle,
/// journal, and for an orbit its path in absolute coordinates, the current centre and the
/// clearance circle, which the inset magnifies).
fn series(p: &MechanismPicture, view: View) -> Vec<Owned> {
    // Guides first: the bodies sliding along them are drawn over them.
    // The guides' dashed grey lines speak for themselves and the ground points sit in their
    // joints' circles: the legend keeps its room for the bodies.
    let mut out: Vec<Owned> = p
        .guides
        .iter()
        .map(|g| owned("", guide_segment(g, around(view)), Style::Reference))
        .collect();
    out.extend(
        p.bodies
            .iter()
            .map(|b| owned(&b.label, b.outline.iter().copied(), Style::Line)),
    );
    if !p.ground.is_empty() {
        out.push(owned("", p.ground.iter().copied(), Style::Points));
    }
    for c in &p.clearance {
        let bearing = format!("{} bearing, R = {} mm", c.name, mm(c.r_bearing));
        out.push(owned(bearing, circle(c.bearing, c.r_bearing), Style::Line));
        out.push(owned("", circle(c.journal, c.r_journal), Style::Dashed));
        if !c.orbit.is_empty() {
            let at = |(ex, ey): Point| (c.bearing.0 + ex, c.bearing.1 + ey);
            let path = format!("{} journal centre path", c.name);
            out.push(owned(path, c.orbit.iter().copied().map(at), Style::Line));
            out.push(owned("", [c.journal], Style::Points));
            out.push(owned(
                "",
                circle(c.bearing, c.clearance()),
                Style::Reference,
            ));
        }
    }
    out
}

/// The inset of the first clearance joint with an orbit: its clearance circle around the
/// current bearing centre, at the same scale on both axes, titled with its magnification; or,
/// where the orbit reaches farther (a joint without clearance, whose journal moves by its
/// penetration), the orbit. None if neither has a size.
fn inset(p: &MechanismPicture, view: View, (w, h): (f64, f64)) -> Option<Inset> {
    let c = p.clearance.iter().find(|c| !c.orbit.is_empty())?;
    let farthest = (c.orbit.iter()).fold(c.clearance(), |r, &(ex, ey)| r.max(ex.hypot(ey)));
    let reach = INSET_REACH * farthest;
    if !(reach > 0.0 && reach.is_finite()) {
        return None;
    }
    let y_range = (c.bearing.1 - reach, c.bearing.1 + reach);
    // The pixel box of the inset's chart, as `draw::draw_inset` lays it out in the plotting
    // area (w, h) (approximately: the main view's label area may change by a character when
    // equal aspect widens it).
    // the note's lines under the x axis take from the plot's height
    let h = h - f64::from(NOTE_LINE_PX) * p.note.lines().count() as f64;
    let (l, b, r, t) = view.inset_at;
    let y_area = f64::from(Axis::new(y_range, 4).label_area() * INSET_TICK_PX / TICK_PX);
    let chart_w = (r - l) * w - 12.0 - y_area;
    let chart_h = (t - b) * h - f64::from(2 * INSET_TICK_PX + 38);
    let half_x = reach * chart_w / chart_h;
    // equal aspect widens one range of the view: the larger scale is the one drawn
    let mm_per_px = ((view.x.1 - view.x.0) / w).max((view.y.1 - view.y.0) / h);
    let magnify = mm_per_px / (2.0 * half_x / chart_w);
    Some(Inset {
        x_range: (c.bearing.0 - half_x, c.bearing.0 + half_x),
        y_range,
        at: view.inset_at,
        title: format!("{}: journal in its clearance, ×{}", c.name, round2(magnify)),
        // equal on both axes by construction, and laid out before drawing
        magnification: false,
    })
}

/// The label of each clearance joint (name and clearance), above its bearing circle and
/// inside the view: its width estimated from the view's scale.
fn joint_labels(p: &MechanismPicture, view: View, w: f64) -> Vec<(f64, f64, String)> {
    let mm_per_px = (view.x.1 - view.x.0) / w;
    p.clearance
        .iter()
        .map(|c| {
            let text = format!("{}: c = {} mm", c.name, mm(c.clearance()));
            let width = (text.chars().count() + 2) as f64 * LABEL_CHAR_PX * mm_per_px;
            let x = (c.bearing.0 - c.r_bearing).min(view.x.1 - width);
            (x, c.bearing.1 + 1.3 * c.r_bearing + 8.0 * mm_per_px, text)
        })
        .collect()
}

/// The panel of one picture in `view`: the error says what cannot be drawn.
fn panel(p: &MechanismPicture, view: View) -> std::result::Result<Panel, String> {
    let owned = series(p, view);
    let pin = PIN_FRACTION * (view.x.1 - view.x.0);
    // the plotting area (px) of the view, which places the labels and sizes the inset
    let plot_px = plot_size(Axis::new(view.y, Y_TICKS).label_area(), 0, false);
    let axes = Axes {
        title: p.title.clone(),
        x_label: "x (mm)".into(),
        y_label: "y (mm)".into(),
        series: owned
            .iter()
            .map(|o| Series::new(o.label.clone(), &o.x, &o.y, o.style))
            .collect(),
        x_range: Some(view.x),
        y_range: Some(view.y),
        equal_aspect: true,
        circles: p.pins.iter().map(|&(x, y)| (x, y, pin)).collect(),
        circle_label: "ideal revolute joint".into(),
        point_labels: joint_labels(p, view, plot_px.0),
        note: Some(p.note.clone()).filter(|n| !n.is_empty()),
        inset: inset(p, view, plot_px),
        ..Default::default()
    };
    Panel::new(&axes, axes.title.clone(), None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_leaves_room_above_the_mechanism() {
        let p = MechanismPicture {
            pins: vec![(0.0, 0.0), (100.0, 50.0)],
            ..Default::default()
        };
        let View { x, y, .. } = view(std::slice::from_ref(&p)).unwrap();
        assert!(x.0 < 0.0 && x.1 > 100.0);
        // wide: the legend's rows (one: the revolute joints) stay clear above the data
        let top = (56.0 - y.0) / (y.1 - y.0);
        assert!((top - (1.0 - legend_height(&p) - 0.04)).abs() < 1e-9);
    }

    #[test]
    fn guide_spans_the_view() {
        let g = Guide {
            through: (10.0, 0.0),
            direction: (2.0, 0.0),
        };
        let s = guide_segment(&g, ((-5.0, 50.0), (-1.0, 1.0)));
        assert_eq!(s, vec![(-5.0, 0.0), (50.0, 0.0)]);
    }
}
