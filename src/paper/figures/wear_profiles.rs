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
use crate::paper::cases::{Runs, WearEnsemble, WearMember, CASES};
use crate::paper::format::{sci, sig};
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
        "{name} ({n} members): after {} rotations each member's deepest sector depth (of {} sectors, \
         each its width's mean) {} µm (mean ± sd over members){states} (5-95 %: {}; section 5 gives \
         how it depends on the sector count), mean depth {} µm; each member's deepest sector at \
         {} deg; regions of the mean profile at {}",
        e.scene.run.rotations,
        e.members.first().map_or(0, |m| m.final_wear.len()),
        e.stat(|m| m.max_depth()).mean_sd(1e6, 3),
        {
            let (lo, hi) = e.stat(|m| m.max_depth()).band90();
            format!("{:.3}-{:.3}", lo * 1e6, hi * 1e6)
        },
        e.stat(|m| m.mean_depth()).mean_sd(1e6, 3),
        e.angle_states(|m| m.deepest_angle().unwrap_or(f64::NAN))
            .mean_sd_with_states(1.0, 1),
        mean_regions.join(", ")
    )
}

/// States ([`States`]) of the members' deepest final wear (m).
pub fn deepest_wear_states(e: &WearEnsemble) -> States {
    e.states(|m| m.max_depth())
}

/// Mean and 5-95 % band of the final profiles of each state of the deepest wear, when the
/// members split into two ([`deepest_wear_states`]): labelled with the state and its member
/// count, tagged `<tag>_low` and `<tag>_high`; empty when they do not split.
fn state_curves(e: &WearEnsemble, label: &str, tag: &str) -> Vec<BandCurve> {
    let states = deepest_wear_states(e);
    let Some((low, high)) = states.low_high() else {
        return Vec::new();
    };
    let n = e.members.len();
    [("low", low), ("high", high)]
        .iter()
        .map(|(which, s)| {
            let band = Band::of(
                s.members
                    .iter()
                    .map(|&i| e.members[i].final_wear.as_slice()),
            );
            BandCurve::new(
                format!("{label}, {which}-wear state ({} of {n})", s.members.len()),
                format!("{tag}_{which}"),
                &band,
                1e6,
            )
        })
        .collect()
}

/// What a panel of final profiles draws of one ensemble: its pooled curve, or, where the
/// members split into wear states, each state's curve instead (the pooled mean of two states
/// is a profile no member has).
fn drawn_curves(pooled: BandCurve, states: &[BandCurve]) -> Vec<BandCurve> {
    if states.is_empty() {
        vec![pooled]
    } else {
        states.to_vec()
    }
}

/// The note of a panel that draws an ensemble per wear state.
fn states_note(split: bool) -> Option<String> {
    split.then(|| {
        "An ensemble split into two wear states (largest-gap rule) is drawn per state.".to_string()
    })
}

/// Wear regions of the ensemble-mean final profile, most prominent first.
pub fn mean_profile_regions(e: &WearEnsemble) -> Vec<Region> {
    wear_regions(&e.band().mean())
}

/// A curve drawn as its mean line with the 5-95 % band shaded.
#[derive(Clone, Debug)]
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

/// The CSV tag of a curve of a case's panel: after the case's tag (`c0.2mm_rot10`,
/// `30rpm_rot10`, as figures 11 and 15 tag theirs) when the figure draws several cases.
fn case_curve_tag(case: &str, curve: &str, several: bool) -> String {
    if several {
        format!("{case}_{curve}")
    } else {
        curve.to_string()
    }
}

/// Mean profiles after each snapshot with their bands, one panel per case (figures 6, 10, 14).
fn profile_figure(runs: &Runs, name: &str, cases: &[CasePanel]) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut panels = Vec::new();
    let mut state_columns = Vec::new();
    for CasePanel {
        case,
        varied,
        title,
    } in cases
    {
        let e = runs.wear(case.scene)?;
        lines.push(wear_line(&case.label(), e));
        // the case's columns are told apart by its value with the unit, as figures 11 and 15's
        let tag = varied.tag(case);
        let curves: Vec<BandCurve> = (0..e.members[0].snapshots.len())
            .map(|i| {
                let (rot, band) = e.snapshot_band(i);
                BandCurve::new(format!("{rot} rotations"), format!("rot{rot}"), &band, 1e6)
            })
            .collect();
        let n = e.members.len();
        let last = e.scene.run.rotations;
        let states = state_curves(e, &format!("{last} rotations"), &format!("rot{last}"));
        // the final snapshot is the final profile: drawn per state where the members split
        let mut drawn = curves.clone();
        if let Some(final_profile) = drawn.pop() {
            drawn.extend(drawn_curves(final_profile, &states));
        }
        let note = states_note(!states.is_empty());
        state_columns.push((tag.clone(), states));
        panels.push((
            tag,
            (format!("{title}, mean of {n}, 5-95 % shaded"), note),
            curves,
            drawn,
        ));
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
        .map(|(_, (title, note), _, drawn)| Axes {
            note: note.clone(),
            ..band_panel(title.clone(), &angles, drawn, WEAR_AXIS)
        })
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &axes)?;
    let tagged = cases.len() > 1;
    let columns: Vec<(String, &BandCurve)> = panels
        .iter()
        .map(|(key, _, curves, _)| (key, curves))
        .chain(state_columns.iter().map(|(key, curves)| (key, curves)))
        .flat_map(|(key, curves)| {
            curves
                .iter()
                .map(move |c| (case_curve_tag(key, &c.tag, tagged), c))
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

/// The line of a case's (deepest − third most prominent region) / deepest
/// ([`WearMember::region_spread`]): mean ± sd with its states, and over how many members it is
/// taken. A member with fewer than three regions has no such ratio, and those that have one
/// may be a few of the ensemble (2 of 32 at 600 r/min): a mean that hid its count would read
/// as the ensemble's.
fn spread_line(label: &str, members: &[WearMember]) -> String {
    let n = members.len();
    let values: Vec<f64> = (members.iter())
        .map(|m| m.region_spread().unwrap_or(f64::NAN))
        .collect();
    let states = States::of(&values);
    let k = states.pooled.n;
    let ratio = if k == 0 {
        "n/a".to_string()
    } else {
        states.mean_sd_with_states(1.0, 2)
    };
    format!(
        "{label}: (deepest − third most prominent region) / deepest {ratio}, over the {k} of {n} \
         members with three regions"
    )
}

/// Final mean profiles of the three cases of `varied` with their bands in one panel
/// (figures 11, 15).
fn comparison_figure(runs: &Runs, name: &str, title: &str, varied: Varied) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut curves = Vec::new();
    let mut state_columns = Vec::new();
    let mut drawn = Vec::new();
    for case in varied.cases() {
        let e = runs.wear(case.scene)?;
        lines.push(wear_line(&case.label(), e));
        lines.push(spread_line(&case.label(), &e.members));
        let (label, tag) = (varied.label(&case), varied.tag(&case));
        let states = state_curves(e, &label, &tag);
        let pooled = BandCurve::new(label, tag, &e.band(), 1e6);
        drawn.extend(drawn_curves(pooled.clone(), &states));
        state_columns.extend(states);
        curves.push(pooled);
    }
    let angles = sector_angles_deg(curves[0].mean.len());
    let n = runs.ensemble.members;
    let rotations = runs.wear(varied.cases()[0].scene)?.scene.run.rotations;
    let axis = format!("accumulated wear depth after {rotations} rotations (µm)");
    let mut panel = Axes {
        note: states_note(drawn.len() > curves.len()),
        ..band_panel(
            format!("{title}, mean of {n}, 5-95 % shaded"),
            &angles,
            &drawn,
            &axis,
        )
    };
    // A case whose deepest wear is below a tenth of the deepest case's would be a flat line
    // at zero on a linear axis (30 r/min): draw four decades below the deepest wear instead.
    let peaks: Vec<f64> = drawn
        .iter()
        .map(|c| c.mean.iter().copied().fold(0.0, f64::max))
        .collect();
    let deepest = peaks.iter().copied().fold(0.0, f64::max);
    if peaks.iter().any(|&p| p < 0.1 * deepest) && deepest > 0.0 {
        let floor = 10f64.powf(deepest.log10().floor() - 4.0);
        panel.y_log = true;
        panel.y_range = Some((floor, deepest));
        let log = format!(
            "Logarithmic depth axis: a curve is drawn only where its case wears more than {} µm.",
            sci(floor)
        );
        panel.note = Some(match panel.note {
            Some(states) => format!("{log}\n{states}"),
            None => log,
        });
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

/// Wear depths (µm) at which figure 5 draws its depth rings: 1, 2 or 5 × 10ⁿ steps, at most
/// four up to `deepest` (µm).
fn depth_rings(deepest: f64) -> Vec<f64> {
    if !(deepest.is_finite() && deepest > 0.0) {
        return Vec::new();
    }
    let decade = 10f64.powf((deepest / 4.0).log10().ceil() - 1.0);
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|step| deepest / step <= 4.0)
        .unwrap_or(10.0 * decade);
    (1..)
        .map(|k| k as f64 * step)
        .take_while(|d| *d <= deepest * (1.0 + 1e-9))
        .collect()
}

/// The 5 % and 95 % quantile profiles of `band` after `rotations`: (CSV column, legend label,
/// depth per sector in m). Each sector's quantile is taken on its own, so the curve is a
/// composite no member has, and its name says so.
fn quantile_profiles(rotations: u32, band: &Band) -> [(String, String, Vec<f64>); 2] {
    [(0, 5), (4, 95)].map(|(q, percent)| {
        (
            format!("{rotations}rotationsq{percent:02}"),
            format!("{rotations} rotations, per-sector {percent} % quantile"),
            band.quantile(q),
        )
    })
}

/// Figure 5: polar picture of the worn bearing (standard case, section 6.1): the
/// ensemble-mean radius at each snapshot, and after the last either each wear state's mean
/// (where the members split; the pooled mean, between them, is then left to the CSV) or the
/// per-sector 5 % and 95 % quantiles (composites no member has), with rings of wear depth as
/// its radial scale.
pub fn fig05(runs: &Runs) -> Result<Vec<String>> {
    let e = runs.wear(CASES.standard.scene)?;
    let r = e.scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let snapshots = e.members[0].snapshots.len();
    let bands: Vec<(u32, Band)> = (0..snapshots).map(|i| e.snapshot_band(i)).collect();
    let radius = |d: &[f64], to_mm: f64| -> Vec<f64> { d.iter().map(|d| r + d * to_mm).collect() };
    // (CSV column, legend label, radii, style) of every profile; drawn: all but the quantiles
    // where the states are drawn instead
    let mut profiles: Vec<(String, String, Vec<f64>, Style)> = bands
        .iter()
        .map(|(rot, b)| {
            (
                format!("{rot}rotationsmean"),
                format!("{rot} rotations, mean"),
                radius(&b.mean(), 1e3),
                Style::Line,
            )
        })
        .collect();
    let (last_rot, last) = bands.last().ok_or_else(|| {
        Error::invalid("run.wear_snapshots", "[]", "the snapshots figure 5 draws")
    })?;
    profiles.extend(
        quantile_profiles(*last_rot, last)
            .into_iter()
            .map(|(column, label, depth)| (column, label, radius(&depth, 1e3), Style::Dashed)),
    );
    let states = state_curves(e, &format!("{last_rot} rotations"), "");
    // the state curves are in µm
    // the last state solid, the others dashed: a few pixels apart, they differ by their lines
    profiles.extend(states.iter().enumerate().map(|(i, c)| {
        (
            format!(
                "{last_rot}rotations{}statemean",
                c.tag.trim_start_matches('_')
            ),
            c.label.clone(),
            radius(&c.mean, 1e-3),
            if i + 1 == states.len() {
                Style::Line
            } else {
                Style::Dashed
            },
        )
    }));
    // where the states are drawn, the last snapshot's pooled mean (between them) and its
    // quantiles are left to the CSV
    let hidden = snapshots - 1..snapshots + 2;
    let drawn: Vec<(String, Vec<f64>, Style)> = profiles
        .iter()
        .enumerate()
        .filter(|(i, _)| states.is_empty() || !hidden.contains(i))
        .map(|(_, (_, label, radii, style))| (label.clone(), radii.clone(), *style))
        .collect();
    let angles = sector_angles_deg(last.sectors.len());
    let deepest = drawn
        .iter()
        .flat_map(|(_, radii, _)| radii.iter().map(|x| x - r))
        .fold(0.0, f64::max);
    // magnify so the deepest wear shows as the radius itself, rounded down to 1, 2 or 5 ×
    // 10ⁿ: curves a tenth of the depth apart (the wear states) stay apart
    let raw = r / deepest.max(1e-12);
    let decade = 10f64.powf(raw.log10().floor());
    let magnify = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|m| *m <= raw)
        .unwrap_or(decade);
    let rings: Vec<(f64, String)> = depth_rings(deepest * 1e3)
        .into_iter()
        .map(|d| (d * 1e-3, format!("{} µm", sig(d))))
        .collect();
    render_polar(
        &output_path("figures", "fig05.png"),
        &format!(
            "Worn bearing profile, {last_rot} rotations (c = {} mm, {} r/min), mean of {}",
            CASES.standard.clearance_mm,
            CASES.standard.speed_rpm,
            e.members.len()
        ),
        &angles,
        &drawn,
        (r, magnify),
        &rings,
    )?;
    let names: Vec<String> = profiles
        .iter()
        .map(|(column, ..)| format!("radius_mm_{column}"))
        .collect();
    let mut header = vec!["angle_deg"];
    header.extend(names.iter().map(String::as_str));
    let mut cols: Vec<&[f64]> = vec![&angles];
    cols.extend(profiles.iter().map(|(_, _, r, _)| r.as_slice()));
    write_csv(&output_path("data", "fig05.csv"), &header, &cols)?;
    Ok(vec![
        wear_line(&CASES.standard.label(), e),
        format!("radial deviation magnified x{magnify}"),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Members whose deepest wear lies in two regions are two states of its place, and the
    /// line says so beside the mean profile's regions, where the two regions' depths blend.
    /// Failed on the line as it was: the 0.5 mm case's "regions of the mean profile at 184.5
    /// deg (0.407 µm), 48.5 deg (0.406 µm)" said nothing of its members' deepest sectors, 9 of
    /// 32 near 45 deg and 23 near 174 deg (`jointwear run data/scenes/clearance_0.5mm.toml
    /// --ensemble 32`).
    #[test]
    fn the_wear_line_gives_the_states_of_the_deepest_sector() {
        let scene = crate::simulation::Scene::load(crate::scene::scene_path("standard")).unwrap();
        let member = |deepest: usize| {
            let final_wear: Vec<f64> = (0..360)
                .map(|i| if i == deepest { 2e-7 } else { 1e-7 })
                .collect();
            WearMember {
                regions: wear_regions(&final_wear),
                final_wear,
                snapshots: Vec::new(),
                history: Vec::new(),
            }
        };
        let e = WearEnsemble {
            scene,
            members: [40, 40, 40, 174, 174, 174, 174, 174].map(member).to_vec(),
            period: 0.03,
        };
        let line = wear_line("case", &e);
        assert!(
            line.contains(
                "each member's deepest sector at 124.2 ± 69.4 (pooled over two states: low 3/8 \
                 40.5 ± 0.0, high 5/8 174.5 ± 0.0) deg; regions of the mean profile"
            ),
            "{line}"
        );
    }

    // Fails on the tags as they were: fig10's and fig14's columns read `case0.2_rot10_mean_mm`
    // and `case30_rot10_mean_mm`, a clearance and a speed under one name without their unit.
    #[test]
    fn the_profile_columns_of_several_cases_name_each_case_with_its_unit() {
        let tag = |v: Varied, case: &crate::paper::cases::Case| {
            case_curve_tag(&v.tag(case), "rot10", true)
        };
        assert_eq!(
            tag(Varied::Clearance, &CASES.clearance_0_2mm),
            "c0.2mm_rot10"
        );
        assert_eq!(tag(Varied::Speed, &CASES.speed_30rpm), "30rpm_rot10");
        assert_eq!(case_curve_tag("c0.02mm", "rot10", false), "rot10");
    }

    #[test]
    fn the_quantile_profiles_are_named_per_sector_quantiles() {
        // two members, each deepest in another sector: the 5 % curve takes each sector's
        // shallower member, a profile neither has
        let band = Band::of([&[1.0, 0.0][..], &[0.0, 1.0][..]]);
        let [lo, hi] = quantile_profiles(40, &band);
        assert_eq!(
            (lo.0.as_str(), lo.1.as_str()),
            ("40rotationsq05", "40 rotations, per-sector 5 % quantile")
        );
        assert_eq!(
            (hi.0.as_str(), hi.1.as_str()),
            ("40rotationsq95", "40 rotations, per-sector 95 % quantile")
        );
        assert!(lo.2.iter().all(|&d| (d - 0.05).abs() < 1e-12), "{:?}", lo.2);
    }

    /// A member whose final profile has `regions` regions, the first `depth` deep, the
    /// others `1 − spread` of it.
    fn member(regions: usize, spread: f64) -> WearMember {
        let region = |i: usize| Region {
            sector: i,
            angle_deg: i as f64,
            depth: if i == 0 { 1.0 } else { 1.0 - spread },
            prominence: 1.0,
            width_deg: 1.0,
        };
        WearMember {
            final_wear: vec![1.0; 4],
            snapshots: Vec::new(),
            regions: (0..regions).map(region).collect(),
            history: Vec::new(),
        }
    }

    #[test]
    fn the_region_spread_line_says_over_how_many_members_and_their_states() {
        // two of four members have three regions (as 2 of 32 at 600 r/min): the line said
        // "0.61 ± 0.01" as if of every member
        let few = [
            member(3, 0.6),
            member(2, 0.0),
            member(3, 0.62),
            member(2, 0.0),
        ];
        assert_eq!(
            spread_line("case", &few),
            "case: (deepest − third most prominent region) / deepest 0.61 ± 0.01, over the 2 of \
             4 members with three regions"
        );
        // members in two states: both given beside the pooled mean
        let split: Vec<WearMember> = [0.02, 0.03, 0.30, 0.31, 0.29, 0.30]
            .iter()
            .map(|&s| member(3, s))
            .collect();
        let line = spread_line("case", &split);
        assert!(
            line.contains("(pooled over two states: low 2/6 0.03 ± 0.01, high 4/6 0.30 ± 0.01)"),
            "{line}"
        );
        assert!(
            line.ends_with("over the 6 of 6 members with three regions"),
            "{line}"
        );
        assert_eq!(
            spread_line("case", &[member(2, 0.0)]),
            "case: (deepest − third most prominent region) / deepest n/a, over the 0 of 1 members \
             with three regions"
        );
    }

    #[test]
    fn depth_rings_are_round_steps_up_to_the_deepest_wear() {
        // checked: stepping by the decade alone gives 0.1 ... 0.6 µm, six rings, for 0.68 µm
        let close = |a: Vec<f64>, b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
        };
        assert!(close(depth_rings(0.68), &[0.2, 0.4, 0.6]));
        assert!(close(depth_rings(4.0), &[1.0, 2.0, 3.0, 4.0]));
        assert!(close(depth_rings(0.011), &[0.005, 0.01]));
        assert!(depth_rings(0.0).is_empty() && depth_rings(f64::NAN).is_empty());
    }
}
