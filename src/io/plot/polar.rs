//! Polar pictures of closed profiles `r(theta)` (worn bearings): the magnified deviation from a
//! reference circle, drawn on spokes with angle labels instead of Cartesian axes.

use std::path::Path;

use plotters::chart::DualCoordChartContext;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::draw::{draw_figure, DrawResult};
use super::panel::Panel;
use super::text::GlyphBackend;
use super::theme::{text, TICK_PX};
use super::{plot_error, Axes, Series, Style};
use crate::Result;

/// Angle at which the depth scale's rings are labelled (deg): between two spokes.
const SCALE_LABEL_DEG: f64 = 112.5;

/// Half-width of the picture over its largest radius: room outside the curves for the spokes'
/// angle labels (at 1.07 of it), wide enough that the widest label, `180°`, is not clipped.
const MARGIN: f64 = 1.35;

/// Renders closed profiles `r(theta)` (theta in degrees, counter-clockwise from +x) as a polar
/// picture around the dashed reference circle of radius `r_ref`. The deviation `r - r_ref` is
/// scaled by `magnify` (noted on the figure) so that micrometre wear shows on a millimetre
/// radius; `scale` gives deviations (the radii's unit) at which rings are drawn like the
/// reference circle, each labelled with its text, so that a deviation can be read off.
pub fn render_polar(
    path: &Path,
    title: &str,
    theta_deg: &[f64],
    profiles: &[(String, Vec<f64>, Style)],
    (r_ref, magnify): (f64, f64),
    scale: &[(f64, String)],
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
    // The reference circle and the scale's rings first, so that the profiles are drawn over
    // them; one legend entry stands for them all.
    let reference = if scale.is_empty() {
        "reference circle"
    } else {
        "reference circle and depth rings"
    };
    let rings = scale.iter().map(|(d, _)| {
        let ring = closed(&|_| r_ref + d);
        (String::new(), ring, Style::Reference)
    });
    let curves: Vec<_> =
        std::iter::once((reference.to_owned(), closed(&|_| r_ref), Style::Reference))
            .chain(rings)
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
        * MARGIN;
    let ring = |deviation: f64| r_ref + magnify * deviation;
    let (sin, cos) = SCALE_LABEL_DEG.to_radians().sin_cos();
    let axes = Axes {
        title: title.to_owned(),
        series: curves
            .iter()
            .map(|(label, (x, y), style)| Series::new(label.clone(), x, y, *style))
            .collect(),
        x_range: Some((-extent, extent)),
        y_range: Some((-extent, extent)),
        equal_aspect: true,
        point_labels: scale
            .iter()
            .map(|(d, label)| (ring(*d) * cos, ring(*d) * sin, label.clone()))
            .collect(),
        ..Default::default()
    };
    let note = format!("radial deviation magnified ×{magnify}");
    let panel = Panel::new(&axes, axes.title.clone(), Some(note)).map_err(fail)?;
    draw_figure(path, &[panel])
}

/// The chart a panel is drawn on (left and right y axes).
pub(super) type Chart<'a, 'b> = DualCoordChartContext<
    'a,
    GlyphBackend<'b>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
>;

/// Spokes every 45° with angle labels, in place of Cartesian axes.
pub(super) fn draw_polar_grid<'b>(chart: &mut Chart<'_, 'b>, p: &Panel) -> DrawResult<'b> {
    let reach = 0.5 * p.x.span().min(p.y.span()) / MARGIN;
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
