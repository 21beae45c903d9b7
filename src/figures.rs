//! The paper's figures as library functions, drawn from ensembles ([`crate::runs`]).
//!
//! Each [`Figure`] names the ensembles it needs, and draws `figures/<name>.png` and writes
//! `data/<name>.csv` atomically from them. Wear figures draw the ensemble mean with the band
//! that holds 90 % of the members (5 %–95 % quantiles, shaded); time-series figures draw the
//! first member (a trajectory cannot be averaged) and their summary lines give mean ± sd over
//! all members. The `src/bin/` programs only call [`figure_main`]; the report computes every
//! ensemble once and draws every figure from it.

use crate::analysis::Peak;
use crate::ensemble::EnsembleSettings;
use crate::golden::Golden;
use crate::output::{write_csv, write_rows};
use crate::plot::{render, render_polar, Axes, Series, Shade, Style};
use crate::runs::{clearance, Need, Runs, SteadyEnsemble, Traces, WearEnsemble, CASES};
use crate::statistics::{fractions, Band, Distribution};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// Where generated outputs go: `figures/` and `data/` under the crate root.
pub fn output_path(dir: &str, file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(dir).join(file)
}

/// Sector centre angles (deg) of a profile with `n` sectors.
pub fn sector_angles_deg(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (i as f64 + 0.5) * 360.0 / n as f64)
        .collect()
}

/// A figure of the paper (or Table 3): the ensembles it reads and how it draws them.
pub struct Figure {
    /// Program and file name, `fig06`.
    pub name: &'static str,
    /// What the paper says it shows.
    pub caption: &'static str,
    /// The ensembles it reads.
    pub needs: &'static [Need],
    /// Draws the PNG and writes the CSV; returns the lines its program prints.
    pub draw: fn(&Runs) -> Result<Vec<String>>,
}

const CLEARANCE_STEADY: &[Need] = &[
    Need::Steady("clearance_0.2mm"),
    Need::Steady("clearance_0.5mm"),
];
const SPEED_STEADY: &[Need] = &[Need::Steady("speed_30rpm"), Need::Steady("speed_600rpm")];

/// Every figure of the paper, in order, then Table 3.
pub const FIGURES: [Figure; 14] = [
    Figure {
        name: "fig03",
        caption: "Slider acceleration versus wear rate (0.02 mm, 2000 r/min)",
        needs: &[Need::Steady("standard")],
        draw: fig03,
    },
    Figure {
        name: "fig04",
        caption: "Journal trajectory (0.02 mm, 2000 r/min)",
        needs: &[Need::Steady("standard")],
        draw: fig04,
    },
    Figure {
        name: "fig05",
        caption: "Variation of bearing radius for 40 cycles (caption: 0.002 mm; text: 0.02 mm, 2000 r/min)",
        needs: &[Need::Wear("standard")],
        draw: fig05,
    },
    Figure {
        name: "fig06",
        caption: "Variation of bearing radius with crank rotation, 10-40 rotations (0.02 mm, 2000 r/min)",
        needs: &[Need::Wear("standard")],
        draw: fig06,
    },
    Figure {
        name: "fig07",
        caption: "Variation of bearing radius in the three severe regions (0.02 mm, 2000 r/min)",
        needs: &[Need::WearHistory("standard")],
        draw: fig07,
    },
    Figure {
        name: "fig08",
        caption: "Journal trajectory for radial clearances 0.2 mm and 0.5 mm",
        needs: CLEARANCE_STEADY,
        draw: fig08,
    },
    Figure {
        name: "fig09",
        caption: "Slider acceleration versus wear rate for 0.2 mm and 0.5 mm",
        needs: CLEARANCE_STEADY,
        draw: fig09,
    },
    Figure {
        name: "fig10",
        caption: "Variation of bearing radius for 0.2 mm and 0.5 mm",
        needs: &[Need::Wear("clearance_0.2mm"), Need::Wear("clearance_0.5mm")],
        draw: fig10,
    },
    Figure {
        name: "fig11",
        caption: "Wear depth accumulated for different clearance sizes",
        needs: &[
            Need::Wear("standard"),
            Need::Wear("clearance_0.2mm"),
            Need::Wear("clearance_0.5mm"),
        ],
        draw: fig11,
    },
    Figure {
        name: "fig12",
        caption: "Journal trajectory at 30 and 600 r/min",
        needs: SPEED_STEADY,
        draw: fig12,
    },
    Figure {
        name: "fig13",
        caption: "Slider acceleration versus wear rate at 30 and 600 r/min",
        needs: SPEED_STEADY,
        draw: fig13,
    },
    Figure {
        name: "fig14",
        caption: "Variation of bearing radius at 30 and 600 r/min",
        needs: &[Need::Wear("speed_30rpm"), Need::Wear("speed_600rpm")],
        draw: fig14,
    },
    Figure {
        name: "fig15",
        caption: "Wear depth accumulated for different crank speeds",
        needs: &[
            Need::Wear("speed_30rpm"),
            Need::Wear("speed_600rpm"),
            Need::Wear("standard"),
        ],
        draw: fig15,
    },
    Figure {
        name: "table3",
        caption: "Table 3: motion state and concordance of the wear-rate drivers",
        needs: &[
            Need::Steady("speed_30rpm"),
            Need::Steady("speed_600rpm"),
            Need::Steady("standard"),
            Need::Steady("clearance_0.2mm"),
            Need::Steady("clearance_0.5mm"),
        ],
        draw: table3,
    },
];

/// Every ensemble any figure needs.
pub fn all_needs() -> Vec<Need> {
    FIGURES
        .iter()
        .flat_map(|f| f.needs.iter().copied())
        .collect()
}

/// `member 1 of N` for titles of figures that draw one member.
fn first_of(n: usize) -> String {
    format!("member 1 of {n}")
}

fn acceleration_panel<'a>(title: String, t: &'a Traces) -> Axes<'a> {
    Axes {
        y2_label: Some("wear rate (µm/s)".into()),
        ..Axes::new(
            title,
            "crank angle over the two recorded rotations (deg)",
            "slider acceleration (m/s²)",
            vec![
                Series::new(
                    "slider acceleration",
                    &t.crank_deg,
                    &t.slider_acc,
                    Style::Line,
                ),
                Series::new(
                    "wear rate",
                    &t.crank_deg,
                    &t.wear_rate_um_s,
                    Style::LineOnSecondaryAxis,
                ),
            ],
        )
    }
}

fn trajectory_panel<'a>(title: String, t: &'a Traces, c: f64) -> Axes<'a> {
    Axes {
        equal_aspect: true,
        circles: vec![(0.0, 0.0, c * 1e6)],
        ..Axes::new(
            title,
            "journal centre x relative to bearing (µm)",
            "journal centre y relative to bearing (µm)",
            vec![Series::new(
                "journal centre",
                &t.ex_um,
                &t.ey_um,
                Style::Line,
            )],
        )
    }
}

/// The lines a steady ensemble's figure prints: mean ± sd over the members.
fn steady_lines(name: &str, e: &SteadyEnsemble) -> String {
    let n = e.members.len();
    let modes: Vec<String> = fractions(e.members.iter().map(|m| m.motion.mode()))
        .iter()
        .map(|(mode, k)| format!("{mode} in {k} of {n}"))
        .collect();
    let unsteady = e.members.iter().filter(|m| !m.settling.steady).count();
    format!(
        "{name} ({n} members): {}; in contact {} %, {} impacts/rotation; max |slider acc| {} m/s², \
         max force {} N, max penetration {} µm; CMF P-w {}, s-w {}{}",
        modes.join(", "),
        e.stat(|m| m.motion.contact_fraction).mean_sd(100.0, 1),
        e.stat(|m| m.motion.impacts_per_rotation).mean_sd(1.0, 1),
        e.stat(|m| m.max_slider_acc).mean_sd(1.0, 0),
        e.stat(|m| m.max_normal_force).mean_sd(1.0, 0),
        e.stat(|m| m.max_penetration).mean_sd(1e6, 2),
        e.stat(|m| m.concordance.pressure_wear).mean_sd(1.0, 4),
        e.stat(|m| m.concordance.sliding_wear).mean_sd(1.0, 4),
        if unsteady > 0 {
            format!("; the orbit of {unsteady} members never repeated (chaotic; recorded anyway)")
        } else {
            String::new()
        }
    )
}

/// The first member's traces of a steady ensemble.
fn first_traces(e: &SteadyEnsemble) -> Result<&Traces> {
    e.members
        .first()
        .and_then(|m| m.traces.as_ref())
        .ok_or_else(|| Error::invalid("ensemble", "no traces", "a first member with traces"))
}

/// Writes the first member's time series of steady runs in long format, one block per case.
fn write_steady_csv(name: &str, cases: &[(f64, &Traces)]) -> Result<()> {
    let mut cols: [Vec<f64>; 6] = Default::default();
    for (case, t) in cases {
        cols[0].extend(std::iter::repeat_n(*case, t.crank_deg.len()));
        cols[1].extend(&t.crank_deg);
        cols[2].extend(&t.slider_acc);
        cols[3].extend(&t.wear_rate_um_s);
        cols[4].extend(&t.ex_um);
        cols[5].extend(&t.ey_um);
    }
    let header = [
        "case",
        "crank_deg",
        "slider_acc_m_s2",
        "wear_rate_um_s",
        "journal_x_um",
        "journal_y_um",
    ];
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    write_csv(&output_path("data", &format!("{name}.csv")), &header, &refs)
}

/// A time-series figure of one or two steady cases: `panel` draws each case's first member.
fn steady_figure(
    runs: &Runs,
    name: &str,
    cases: &[(&str, f64, String)],
    panel: impl for<'a> Fn(String, &'a Traces, f64) -> Axes<'a>,
) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut drawn = Vec::new();
    for (scene_name, case, title) in cases {
        let e = runs.steady(scene_name)?;
        lines.push(steady_lines(scene_name, e));
        let title = format!("{title} ({})", first_of(e.members.len()));
        drawn.push((*case, title, first_traces(e)?, clearance(&e.scene)));
    }
    let panels: Vec<Axes> = drawn
        .iter()
        .map(|(_, title, t, c)| panel(title.clone(), t, *c))
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &panels)?;
    let csv: Vec<(f64, &Traces)> = drawn.iter().map(|(case, _, t, _)| (*case, *t)).collect();
    write_steady_csv(name, &csv)?;
    Ok(lines)
}

fn fig03(runs: &Runs) -> Result<Vec<String>> {
    let title = "Slider acceleration and wear rate (0.02 mm, 2000 r/min)".to_string();
    steady_figure(runs, "fig03", &[("standard", 0.02, title)], |t, tr, _| {
        acceleration_panel(t, tr)
    })
}

fn fig04(runs: &Runs) -> Result<Vec<String>> {
    let title = "Journal trajectory (0.02 mm, 2000 r/min)".to_string();
    steady_figure(
        runs,
        "fig04",
        &[("standard", 0.02, title)],
        trajectory_panel,
    )
}

fn clearance_cases(what: &str) -> [(&'static str, f64, String); 2] {
    [
        ("clearance_0.2mm", 0.2, format!("{what}, c = 0.2 mm")),
        ("clearance_0.5mm", 0.5, format!("{what}, c = 0.5 mm")),
    ]
}

fn speed_cases(what: &str) -> [(&'static str, f64, String); 2] {
    [
        ("speed_30rpm", 30.0, format!("{what}, 30 r/min")),
        ("speed_600rpm", 600.0, format!("{what}, 600 r/min")),
    ]
}

fn fig08(runs: &Runs) -> Result<Vec<String>> {
    steady_figure(
        runs,
        "fig08",
        &clearance_cases("Journal trajectory"),
        trajectory_panel,
    )
}

fn fig09(runs: &Runs) -> Result<Vec<String>> {
    steady_figure(
        runs,
        "fig09",
        &clearance_cases("Slider acceleration and wear rate"),
        |t, tr, _| acceleration_panel(t, tr),
    )
}

fn fig12(runs: &Runs) -> Result<Vec<String>> {
    steady_figure(
        runs,
        "fig12",
        &speed_cases("Journal trajectory"),
        trajectory_panel,
    )
}

fn fig13(runs: &Runs) -> Result<Vec<String>> {
    steady_figure(
        runs,
        "fig13",
        &speed_cases("Slider acceleration and wear rate"),
        |t, tr, _| acceleration_panel(t, tr),
    )
}

/// The line a wear ensemble's figure prints.
fn wear_line(name: &str, e: &WearEnsemble) -> String {
    let n = e.members.len();
    let mean_peaks: Vec<String> = mean_profile_peaks(e)
        .iter()
        .take(3)
        .map(|p| format!("{:.1} deg ({:.3} µm)", p.angle_deg, p.depth * 1e6))
        .collect();
    format!(
        "{name} ({n} members): after {} rotations max wear {} µm (5-95 %: {}), mean {} µm; \
         regions of the mean profile at {}",
        e.scene.run.rotations,
        e.stat(|m| m.max_depth()).mean_sd(1e6, 3),
        {
            let (lo, hi) = e.stat(|m| m.max_depth()).band90();
            format!("{:.3}-{:.3}", lo * 1e6, hi * 1e6)
        },
        e.stat(|m| m.mean_depth()).mean_sd(1e6, 3),
        mean_peaks.join(", ")
    )
}

/// Wear regions of the ensemble-mean final profile, deepest first.
pub fn mean_profile_peaks(e: &WearEnsemble) -> Vec<Peak> {
    crate::analysis::peaks(&e.band().mean(), crate::runs::PEAK_PROMINENCE)
}

/// A profile drawn as its mean line with the 5-95 % band, in µm.
struct BandCurve {
    label: String,
    mean: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl BandCurve {
    fn new(label: String, band: &Band, scale: f64) -> BandCurve {
        let scaled = |v: Vec<f64>| v.iter().map(|x| x * scale).collect();
        BandCurve {
            label,
            mean: scaled(band.mean()),
            lo: scaled(band.quantile(0)),
            hi: scaled(band.quantile(4)),
        }
    }
}

const WEAR_AXIS: &str = "bearing radius increase = wear depth (µm)";

/// A panel of mean profiles with their bands.
fn band_panel<'a>(title: String, x: &'a [f64], curves: &'a [BandCurve], y: &str) -> Axes<'a> {
    Axes {
        x_range: Some((0.0, 360.0)),
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
            "circumferential angle (deg)",
            y,
            curves
                .iter()
                .map(|c| Series::new(c.label.clone(), x, &c.mean, Style::Line))
                .collect(),
        )
    }
}

/// Writes mean and 5-95 % band columns (mm) of several profiles after `angle_deg`.
fn write_band_csv(name: &str, angles: &[f64], curves: &[(String, &BandCurve)]) -> Result<()> {
    let mut header = vec!["angle_deg".to_string()];
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for (tag, c) in curves {
        for (what, v) in [("mean", &c.mean), ("q05", &c.lo), ("q95", &c.hi)] {
            header.push(format!("{tag}_{what}_mm"));
            cols.push(v.iter().map(|um| um * 1e-3).collect());
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut refs: Vec<&[f64]> = vec![angles];
    refs.extend(cols.iter().map(Vec::as_slice));
    write_csv(&output_path("data", &format!("{name}.csv")), &header, &refs)
}

/// Mean profiles after each snapshot with their bands, one panel per case (figures 6, 10, 14).
fn profile_figure(runs: &Runs, name: &str, cases: &[(&str, f64, String)]) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut panels = Vec::new();
    for (scene_name, case, title) in cases {
        let e = runs.wear(scene_name)?;
        lines.push(wear_line(scene_name, e));
        let curves: Vec<BandCurve> = (0..e.members[0].snapshots.len())
            .map(|i| {
                let (rot, band) = e.snapshot_band(i);
                BandCurve::new(format!("{rot} rotations"), &band, 1e6)
            })
            .collect();
        let n = e.members.len();
        panels.push((
            *case,
            format!("{title}, mean of {n}, 5-95 % shaded"),
            curves,
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
        .map(|(_, t, c)| band_panel(t.clone(), &angles, c, WEAR_AXIS))
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &axes)?;
    let tagged = cases.len() > 1;
    let columns: Vec<(String, &BandCurve)> = panels
        .iter()
        .flat_map(|(case, _, curves)| {
            curves.iter().map(move |c| {
                let rot = format!("rot{}", c.label.split(' ').next().unwrap_or(""));
                let tag = if tagged {
                    format!("case{case}_{rot}")
                } else {
                    rot
                };
                (tag, c)
            })
        })
        .collect();
    write_band_csv(name, &angles, &columns)?;
    Ok(lines)
}

fn fig06(runs: &Runs) -> Result<Vec<String>> {
    let title = "Wear with crank rotation (0.02 mm, 2000 r/min)".to_string();
    profile_figure(runs, "fig06", &[("standard", 0.02, title)])
}

fn fig10(runs: &Runs) -> Result<Vec<String>> {
    profile_figure(runs, "fig10", &clearance_cases("Bearing wear"))
}

fn fig14(runs: &Runs) -> Result<Vec<String>> {
    profile_figure(runs, "fig14", &speed_cases("Bearing wear"))
}

/// Final mean profiles of several cases with their bands in one panel (figures 11, 15).
fn comparison_figure(
    runs: &Runs,
    name: &str,
    title: &str,
    cases: &[(&str, &str)],
) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut curves = Vec::new();
    for (scene_name, label) in cases {
        let e = runs.wear(scene_name)?;
        lines.push(wear_line(scene_name, e));
        let spread = e.stat(|m| m.region_spread().unwrap_or(f64::NAN));
        lines.push(format!(
            "{scene_name}: (deepest - third region) / deepest {}",
            spread.mean_sd(1.0, 2)
        ));
        curves.push(BandCurve::new(label.to_string(), &e.band(), 1e6));
    }
    let angles = sector_angles_deg(curves[0].mean.len());
    let n = runs.ensemble.members;
    let axis = "accumulated wear depth after 40 rotations (µm)";
    let panel = band_panel(
        format!("{title}, mean of {n}, 5-95 % shaded"),
        &angles,
        &curves,
        axis,
    );
    render(&output_path("figures", &format!("{name}.png")), &[panel])?;
    let columns: Vec<(String, &BandCurve)> = curves
        .iter()
        .map(|c| (c.label.replace([' ', '='], "").replace("r/min", "rpm"), c))
        .collect();
    write_band_csv(name, &angles, &columns)?;
    Ok(lines)
}

fn fig11(runs: &Runs) -> Result<Vec<String>> {
    comparison_figure(
        runs,
        "fig11",
        "Wear for different clearances (2000 r/min)",
        &[
            ("standard", "c = 0.02 mm"),
            ("clearance_0.2mm", "c = 0.2 mm"),
            ("clearance_0.5mm", "c = 0.5 mm"),
        ],
    )
}

fn fig15(runs: &Runs) -> Result<Vec<String>> {
    comparison_figure(
        runs,
        "fig15",
        "Wear at different crank speeds (c = 0.02 mm)",
        &[
            ("speed_30rpm", "30 r/min"),
            ("speed_600rpm", "600 r/min"),
            ("standard", "2000 r/min"),
        ],
    )
}

/// Figure 5: polar picture of the worn bearing (standard scene): the ensemble-mean radius at
/// each snapshot, and the 5 % and 95 % quantiles after the last.
fn fig05(runs: &Runs) -> Result<Vec<String>> {
    let e = runs.wear("standard")?;
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
        wear_line("standard", e),
        format!("radial deviation magnified x{magnify}"),
    ])
}

/// Share of history intervals that carry 90 % of the wear of a sector's depth history.
pub fn share_for_90pct(depth: &[f64]) -> f64 {
    let mut steps: Vec<f64> = depth.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(|a, b| b.total_cmp(a));
    let total: f64 = steps.iter().sum();
    let mut acc = 0.0;
    let carrying = steps.iter().take_while(|d| {
        acc += **d;
        acc - **d < 0.9 * total
    });
    carrying.count() as f64 / steps.len().max(1) as f64
}

/// Per member, the share of crank positions that carry 90 % of the wear of each of its own
/// three deepest regions (figure 7's staircase).
pub fn staircase_shares(e: &WearEnsemble) -> Vec<Vec<f64>> {
    e.members
        .iter()
        .map(|m| {
            m.peaks
                .iter()
                .take(3)
                .map(|p| {
                    // from the unworn bearing: the first history point is after one interval
                    let depth: Vec<f64> = std::iter::once(0.0)
                        .chain(m.history.iter().map(|(_, d)| d[p.sector]))
                        .collect();
                    share_for_90pct(&depth)
                })
                .collect()
        })
        .collect()
}

/// Figure 7: bearing radius in the three severe regions of the mean profile against crank
/// position, mean over the members with the 5-95 % band. A staircase means each region wears
/// only during part of every rotation.
fn fig07(runs: &Runs) -> Result<Vec<String>> {
    let e = runs.wear("standard")?;
    let r = e.scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let points = e.members.iter().map(|m| m.history.len()).min().unwrap_or(0);
    let interval = e.period / crate::runs::HISTORY_PER_ROTATION as f64;
    let crank: Vec<f64> = (1..=points)
        .map(|k| k as f64 * interval / e.period)
        .collect();
    let mut curves = Vec::new();
    for p in mean_profile_peaks(e).iter().take(3) {
        let per_point: Vec<Distribution> = (0..points)
            .map(|k| Distribution::of(e.members.iter().map(|m| r + m.history[k].1[p.sector] * 1e3)))
            .collect();
        curves.push(BandCurve {
            label: format!("region at {:.0} deg", p.angle_deg),
            mean: per_point.iter().map(|d| d.mean).collect(),
            lo: per_point.iter().map(|d| d.quantiles[0]).collect(),
            hi: per_point.iter().map(|d| d.quantiles[4]).collect(),
        });
    }
    let shares = staircase_shares(e);
    let lines: Vec<String> = (0..3)
        .map(|i| {
            let d = Distribution::of(shares.iter().filter_map(|s| s.get(i).copied()));
            format!(
                "region {} of each member: 90% of its wear in {} % of the crank positions",
                i + 1,
                d.mean_sd(100.0, 0)
            )
        })
        .collect();
    let axes = Axes {
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
            format!(
                "Bearing radius in the severe wear regions (0.02 mm, 2000 r/min), mean of {}",
                e.members.len()
            ),
            "crank position (rotations)",
            "bearing radius (mm)",
            curves
                .iter()
                .map(|c| Series::new(c.label.clone(), &crank, &c.mean, Style::Line))
                .collect(),
        )
    };
    render(&output_path("figures", "fig07.png"), &[axes])?;
    let mut header = vec!["crank_rotations".to_string()];
    let mut cols: Vec<&[f64]> = vec![&crank];
    for c in &curves {
        let tag = c.label.replace(' ', "_");
        header.extend(["mean", "q05", "q95"].map(|w| format!("{tag}_{w}_mm")));
        cols.extend([c.mean.as_slice(), c.lo.as_slice(), c.hi.as_slice()]);
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&output_path("data", "fig07.csv"), &header, &cols)?;
    Ok(lines)
}

/// Table 3: per case, mean ± sd over the members of the concordances and the motion measures,
/// the members per motion mode and dominance, and whether the paper's values lie within the
/// 5-95 % band; writes `data/table3.csv`.
fn table3(runs: &Runs) -> Result<Vec<String>> {
    let golden = Golden::load()?;
    let header = [
        "clearance_mm",
        "speed_rpm",
        "members",
        "paper_motion",
        "continuous_contact_members",
        "paper_pw",
        "pw_mean",
        "pw_sd",
        "pw_q05",
        "pw_q95",
        "paper_sw",
        "sw_mean",
        "sw_sd",
        "sw_q05",
        "sw_q95",
        "paper_dominant",
        "pw_dominant_members",
        "paper_pw_in_band",
        "paper_sw_in_band",
        "contact_fraction_mean",
        "contact_fraction_sd",
        "impacts_per_rotation_mean",
        "impacts_per_rotation_sd",
    ];
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for ((name, c_mm, rpm), g) in CASES.iter().zip(&golden.table3) {
        let e = runs.steady(name)?;
        let n = e.members.len();
        let pw = e.stat(|m| m.concordance.pressure_wear);
        let sw = e.stat(|m| m.concordance.sliding_wear);
        let cf = e.stat(|m| m.motion.contact_fraction);
        let imp = e.stat(|m| m.motion.impacts_per_rotation);
        let inside = |d: &Distribution, v: f64| {
            let (lo, hi) = d.band90();
            (lo..=hi).contains(&v)
        };
        let num = |x: f64| format!("{x:.4}");
        rows.push(vec![
            c_mm.to_string(),
            rpm.to_string(),
            n.to_string(),
            g.motion.clone(),
            e.continuous().to_string(),
            num(g.pw),
            num(pw.mean),
            num(pw.sd),
            num(pw.quantiles[0]),
            num(pw.quantiles[4]),
            num(g.sw),
            num(sw.mean),
            num(sw.sd),
            num(sw.quantiles[0]),
            num(sw.quantiles[4]),
            g.dominant().to_string(),
            e.pressure_dominated().to_string(),
            inside(&pw, g.pw).to_string(),
            inside(&sw, g.sw).to_string(),
            num(cf.mean),
            num(cf.sd),
            format!("{:.2}", imp.mean),
            format!("{:.2}", imp.sd),
        ]);
        lines.push(format!(
            "{c_mm} mm, {rpm} r/min: paper {} P-w {:.4} s-w {:.4} ({}) | ours: continuous contact in \
             {} of {n}, P-w {}, s-w {}, P-w dominant in {} of {n}",
            g.motion,
            g.pw,
            g.sw,
            g.dominant(),
            e.continuous(),
            pw.mean_sd(1.0, 4),
            sw.mean_sd(1.0, 4),
            e.pressure_dominated()
        ));
    }
    write_rows(&output_path("data", "table3.csv"), &header, rows)?;
    Ok(lines)
}

/// Runs a figure's `main`: prints the error and exits non-zero on failure (2 for bad input).
pub fn exit_on_error<T>(result: Result<T>) -> T {
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        let code = match e {
            Error::Invalid { .. } | Error::Parse { .. } => 2,
            _ => 1,
        };
        std::process::exit(code)
    })
}

/// `main` of a figure program: runs the default ensembles it needs, draws it, prints its
/// summary lines.
pub fn figure_main(name: &str) {
    let Some(figure) = FIGURES.iter().find(|f| f.name == name) else {
        exit_on_error::<()>(Err(Error::invalid("figure", name, "a name of FIGURES")));
        return;
    };
    let ensemble = EnsembleSettings::default();
    let bar = crate::output::progress_bar(0, "ensemble members");
    let runs = exit_on_error(Runs::compute(
        figure.needs,
        ensemble,
        &|_| {},
        |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        },
    ));
    bar.finish_and_clear();
    let lines = exit_on_error((figure.draw)(&runs));
    let png = if name == "table3" {
        String::new()
    } else {
        format!("figures/{name}.png and ")
    };
    println!(
        "wrote {png}data/{name}.csv from {} members (seed {}) in {:.1} s",
        ensemble.members, ensemble.seed, runs.seconds
    );
    for line in &lines {
        println!("{line}");
    }
}
