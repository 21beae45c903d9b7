//! The wear-profile figures: the bearing's wear depth around its circumference after the
//! coupled wear runs (section 5 of the paper, eqs. 6-9), drawn as the ensemble mean with the
//! 5-95 % band of the members.
//!
//! Figure 5 (polar picture of the worn bearing) and figure 6 (profiles after 10-40
//! rotations) of the standard case (section 6.1); figures 10 and 14 (the same at the larger
//! clearances and lower speeds, sections 6.2 and 6.3); figures 11 and 15 (final profiles of
//! the three clearances and the three speeds in one panel). Also the mean-profile curves,
//! panels and CSV columns that figure 7 ([`super::wear_history`]) draws with.

use super::{output_path, standard_panel, CasePanel, Varied};
use crate::analysis::regions::{wear_regions, Region};
use crate::analysis::states::States;
use crate::analysis::statistics::Band;
use crate::io::output::write_csv;
use crate::io::plot::{render, render_polar, Axes, Series, Shade, Style};
use crate::laws::wear::sector_angles_deg;
use crate::paper::cases::{Runs, WearEnsemble, CASES};
use crate::paper::format::sci;
use crate::{Error, Result};

/// The line a wear ensemble's figure prints.
fn wear_line(name: &str, e: &WearEnsemble) -> String {
    let n = e.members.len();
    let mean_regions: Vec<String> = mean_profile_regions(e)
        .iter()
        .take(3)
        .map(|p| format!("{:.1} deg ({:.3} µm)", p.angle_deg, p.depth * 1e6))
        .collect();
    let states = deepest_wear_states(e);
    let states = if states.split() {
        format!(" (states: {} µm)", states.describe(1e6, 3))
    } else {
        String::new()
    };
    format!(
        "{name} ({n} members): after {} rotations max wear {} µm{states} (5-95 %: {}), mean {} µm; \
         regions of the mean profile at {}",
        e.scene.run.rotations,
        e.stat(|m| m.max_depth()).mean_sd(1e6, 3),
        {
            let (lo, hi) = e.stat(|m| m.max_depth()).band90();
            format!("{:.3}-{:.3}", lo * 1e6, hi * 1e6)
        },
        e.stat(|m| m.mean_depth()).mean_sd(1e6, 3),
        mean_regions.join(", ")
    )
}

/// States ([`States`]) of the members' deepest final wear (m).
pub fn deepest_wear_states(e: &WearEnsemble) -> States {
    e.states(|m| m.max_depth())
}

/// Mean and 5-95 % band of the final profiles of each state of the deepest wear, when the
/// members split into two ([`deepest_wear_states`]): tagged `<tag>_low` and `<tag>_high`.
fn state_curves(e: &WearEnsemble, label: &str, tag: &str) -> Vec<BandCurve> {
    let states = deepest_wear_states(e);
    let Some((low, high)) = states.low_high() else {
        return Vec::new();
    };
    [("low", low), ("high", high)]
        .iter()
        .map(|(which, s)| {
            let band = Band::of(
                s.members
                    .iter()
                    .map(|&i| e.members[i].final_wear.as_slice()),
            );
            BandCurve::new(
                format!("{label}, {which}-wear state"),
                format!("{tag}_{which}"),
                &band,
                1e6,
            )
        })
        .collect()
}

/// Wear regions of the ensemble-mean final profile, most prominent first.
pub fn mean_profile_regions(e: &WearEnsemble) -> Vec<Region> {
    wear_regions(&e.band().mean())
}

/// A curve drawn as its mean line with the 5-95 % band shaded.
pub(crate) struct BandCurve {
    /// Legend label.
    pub label: String,
    /// CSV column tag (before `_mean_mm`, `_q05_mm`, `_q95_mm`).
    pub tag: String,
    /// Mean over the members.
    pub mean: Vec<f64>,
    /// 5 % quantile.
    pub lo: Vec<f64>,
    /// 95 % quantile.
    pub hi: Vec<f64>,
}

impl BandCurve {
    /// The mean and 5-95 % band of `band`, scaled by `scale`.
    pub fn new(label: String, tag: String, band: &Band, scale: f64) -> BandCurve {
        let scaled = |v: Vec<f64>| v.iter().map(|x| x * scale).collect();
        BandCurve {
            label,
            tag,
            mean: scaled(band.mean()),
            lo: scaled(band.quantile(0)),
            hi: scaled(band.quantile(4)),
        }
    }
}

const WEAR_AXIS: &str = "bearing radius increase = wear depth (µm)";

/// A panel of mean curves over `x` with their bands shaded.
pub(crate) fn band_axes<'a>(
    title: String,
    x_label: &str,
    x: &'a [f64],
    curves: &'a [BandCurve],
    y_label: &str,
) -> Axes<'a> {
    Axes {
        shades: curves
            .iter()
            .enumerate()
            .map(|(i, c)| Shade {
                series: i,
                lo: &c.lo,
                hi: &c.hi,
            })
            .collect(),
        ..Axes::new(
            title,
            x_label,
            y_label,
            curves
                .iter()
                .map(|c| Series::new(c.label.clone(), x, &c.mean, Style::Line))
                .collect(),
        )
    }
}

/// A panel of mean profiles around the circumference with their bands.
fn band_panel<'a>(title: String, x: &'a [f64], curves: &'a [BandCurve], y: &str) -> Axes<'a> {
    Axes {
        x_range: Some((0.0, 360.0)),
        ..band_axes(title, "circumferential angle (deg)", x, curves, y)
    }
}

/// Writes mean and 5-95 % band columns of several curves, each times `to_mm` (so in mm),
/// after the column `x_name` holding `x`.
pub(crate) fn write_band_csv(
    name: &str,
    x_name: &str,
    x: &[f64],
    curves: &[(String, &BandCurve)],
    to_mm: f64,
) -> Result<()> {
    let mut header = vec![x_name.to_string()];
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for (tag, c) in curves {
        for (what, v) in [("mean", &c.mean), ("q05", &c.lo), ("q95", &c.hi)] {
            header.push(format!("{tag}_{what}_mm"));
            cols.push(v.iter().map(|v| v * to_mm).collect());
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut refs: Vec<&[f64]> = vec![x];
    refs.extend(cols.iter().map(Vec::as_slice));
    write_csv(&output_path("data", &format!("{name}.csv")), &header, &refs)
}

/// Mean profiles after each snapshot with their bands, one panel per case (figures 6, 10, 14).
fn profile_figure(runs: &Runs, name: &str, cases: &[CasePanel]) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut panels = Vec::new();
    let mut state_columns = Vec::new();
    for CasePanel { case, key, title } in cases {
        let e = runs.wear(case.scene)?;
        lines.push(wear_line(&case.label(), e));
        let curves: Vec<BandCurve> = (0..e.members[0].snapshots.len())
            .map(|i| {
                let (rot, band) = e.snapshot_band(i);
                BandCurve::new(format!("{rot} rotations"), format!("rot{rot}"), &band, 1e6)
            })
            .collect();
        let n = e.members.len();
        // per-state final profiles go to the CSV only: the figure draws the pooled bands
        let last = e.scene.run.rotations;
        state_columns.push((*key, state_curves(e, &case.label(), &format!("rot{last}"))));
        panels.push((*key, format!("{title}, mean of {n}, 5-95 % shaded"), curves));
    }
    let sectors = panels
        .iter()
        .flat_map(|p| p.2.first())
        .map(|c| c.mean.len())
        .next();
    let angles = sector_angles_deg(sectors.ok_or_else(|| {
        Error::invalid("run.wear_snapshots", "[]", "the snapshots the figure draws")
    })?);
    let axes: Vec<Axes> = panels
        .iter()
        .map(|(_, t, c)| band_panel(t.clone(), &angles, c, WEAR_AXIS))
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &axes)?;
    let tagged = cases.len() > 1;
    let columns: Vec<(String, &BandCurve)> = panels
        .iter()
        .map(|(key, _, curves)| (key, curves))
        .chain(state_columns.iter().map(|(key, curves)| (key, curves)))
        .flat_map(|(key, curves)| {
            curves.iter().map(move |c| {
                let tag = if tagged {
                    format!("case{key}_{}", c.tag)
                } else {
                    c.tag.clone()
                };
                (tag, c)
            })
        })
        .collect();
    write_band_csv(name, "angle_deg", &angles, &columns, 1e-3)?;
    Ok(lines)
}

/// Figure 6: wear profile of the standard case after 10-40 rotations (section 6.1).
pub fn fig06(runs: &Runs) -> Result<Vec<String>> {
    let title = "Wear with crank rotation (0.02 mm, 2000 r/min)";
    profile_figure(runs, "fig06", &standard_panel(title))
}

/// Figure 10: wear profiles at 0.2 and 0.5 mm (section 6.2).
pub fn fig10(runs: &Runs) -> Result<Vec<String>> {
    profile_figure(runs, "fig10", &Varied::Clearance.panels("Bearing wear"))
}

/// Figure 14: wear profiles at 30 and 600 r/min (section 6.3).
pub fn fig14(runs: &Runs) -> Result<Vec<String>> {
    profile_figure(runs, "fig14", &Varied::Speed.panels("Bearing wear"))
}

/// Final mean profiles of the three cases of `varied` with their bands in one panel
/// (figures 11, 15).
fn comparison_figure(runs: &Runs, name: &str, title: &str, varied: Varied) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut curves = Vec::new();
    // per-state profiles go to the CSV only: the figure draws the pooled band
    let mut state_columns = Vec::new();
    for case in varied.cases() {
        let e = runs.wear(case.scene)?;
        lines.push(wear_line(&case.label(), e));
        let spread = e.stat(|m| m.region_spread().unwrap_or(f64::NAN));
        lines.push(format!(
            "{}: (deepest − third most prominent region) / deepest {}",
            case.label(),
            spread.mean_sd(1.0, 2)
        ));
        let (label, tag) = (varied.label(&case), varied.tag(&case));
        state_columns.extend(state_curves(e, &label, &tag));
        curves.push(BandCurve::new(label, tag, &e.band(), 1e6));
    }
    let angles = sector_angles_deg(curves[0].mean.len());
    let n = runs.ensemble.members;
    let axis = "accumulated wear depth after 40 rotations (µm)";
    let mut panel = band_panel(
        format!("{title}, mean of {n}, 5-95 % shaded"),
        &angles,
        &curves,
        axis,
    );
    // A case whose deepest wear is below a tenth of the deepest case's would be a flat line
    // at zero on a linear axis (30 r/min): draw four decades below the deepest wear instead.
    let peaks: Vec<f64> = curves
        .iter()
        .map(|c| c.mean.iter().copied().fold(0.0, f64::max))
        .collect();
    let deepest = peaks.iter().copied().fold(0.0, f64::max);
    if peaks.iter().any(|&p| p < 0.1 * deepest) && deepest > 0.0 {
        let floor = 10f64.powf(deepest.log10().floor() - 4.0);
        panel.y_log = true;
        panel.y_range = Some((floor, deepest));
        panel.note = Some(format!(
            "Logarithmic depth axis: a curve is drawn only where its case wears more than {} µm.",
            sci(floor)
        ));
    }
    render(&output_path("figures", &format!("{name}.png")), &[panel])?;
    let columns: Vec<(String, &BandCurve)> = curves
        .iter()
        .chain(&state_columns)
        .map(|c| (c.tag.clone(), c))
        .collect();
    write_band_csv(name, "angle_deg", &angles, &columns, 1e-3)?;
    Ok(lines)
}

/// Figure 11: final wear profiles of the three clearances (section 6.2).
pub fn fig11(runs: &Runs) -> Result<Vec<String>> {
    let title = "Wear for different clearances (2000 r/min)";
    comparison_figure(runs, "fig11", title, Varied::Clearance)
}

/// Figure 15: final wear profiles of the three speeds (section 6.3).
pub fn fig15(runs: &Runs) -> Result<Vec<String>> {
    let title = "Wear at different crank speeds (c = 0.02 mm)";
    comparison_figure(runs, "fig15", title, Varied::Speed)
}

/// Figure 5: polar picture of the worn bearing (standard case, section 6.1): the
/// ensemble-mean radius at each snapshot, and the 5 % and 95 % quantiles after the last.
pub fn fig05(runs: &Runs) -> Result<Vec<String>> {
    let e = runs.wear(CASES.standard.scene)?;
    let r = e.scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let snapshots = e.members[0].snapshots.len();
    let bands: Vec<(u32, Band)> = (0..snapshots).map(|i| e.snapshot_band(i)).collect();
    let radius = |d: Vec<f64>| -> Vec<f64> { d.iter().map(|d| r + d * 1e3).collect() };
    let mut profiles: Vec<(String, Vec<f64>, Style)> = bands
        .iter()
        .map(|(rot, b)| {
            (
                format!("{rot} rotations, mean"),
                radius(b.mean()),
                Style::Line,
            )
        })
        .collect();
    let (last_rot, last) = bands.last().ok_or_else(|| {
        Error::invalid("run.wear_snapshots", "[]", "the snapshots figure 5 draws")
    })?;
    for (q, what) in [(0, "5 %"), (4, "95 %")] {
        profiles.push((
            format!("{last_rot} rotations, {what} of members"),
            radius(last.quantile(q)),
            Style::Dashed,
        ));
    }
    let angles = sector_angles_deg(last.sectors.len());
    let deepest = last.quantile(4).iter().cloned().fold(0.0, f64::max) * 1e3;
    // magnify so the deepest wear shows as a quarter of the radius, rounded to 1, 2 or 5 × 10ⁿ
    let raw = 0.25 * r / deepest.max(1e-12);
    let decade = 10f64.powf(raw.log10().floor());
    let magnify = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|m| *m <= raw)
        .unwrap_or(decade);
    render_polar(
        &output_path("figures", "fig05.png"),
        &format!(
            "Worn bearing profile, 40 rotations (c = 0.02 mm, 2000 r/min), mean of {}",
            e.members.len()
        ),
        &angles,
        &profiles,
        r,
        magnify,
    )?;
    let names: Vec<String> = profiles
        .iter()
        .map(|(l, _, _)| format!("radius_mm_{}", l.replace([' ', ',', '%'], "")))
        .collect();
    let mut header = vec!["angle_deg"];
    header.extend(names.iter().map(String::as_str));
    let mut cols: Vec<&[f64]> = vec![&angles];
    cols.extend(profiles.iter().map(|(_, r, _)| r.as_slice()));
    write_csv(&output_path("data", "fig05.csv"), &header, &cols)?;
    Ok(vec![
        wear_line(&CASES.standard.label(), e),
        format!("radial deviation magnified x{magnify}"),
    ])
}
