//! The paper's figures as library functions. Each loads its scenes, runs only the simulation
//! it plots (two recorded rotations after the steady state, or the 40 rotations of coupled
//! wear), writes `figures/<name>.png` and `data/<name>.csv` atomically, and returns a
//! [`Summary`] of the numbers it measured; the `src/bin/` programs only call them, and the
//! report reads their summaries.

use crate::analysis::{peaks, Motion, Peak};
use crate::concordance::{centred_cmf, Concordance};
use crate::output::{write_csv, write_rows};
use crate::plot::{render, render_polar, Axes, Series, Style};
use crate::scene::{scene_path, Scene, SceneFile};
use crate::simulation::{simulate, RunOutput};
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where generated outputs go: `figures/` and `data/` under the crate root.
pub fn output_path(dir: &str, file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(dir).join(file)
}

/// Minimum prominence of a reported wear peak, as a fraction of the deepest wear.
pub const PEAK_PROMINENCE: f64 = 0.05;

/// The scenes of the paper's cases: (scene, clearance mm, speed r/min), in Table 3's order.
pub const CASES: [(&str, f64, f64); 5] = [
    ("speed_30rpm", 0.02, 30.0),
    ("speed_600rpm", 0.02, 600.0),
    ("standard", 0.02, 2000.0),
    ("clearance_0.2mm", 0.2, 2000.0),
    ("clearance_0.5mm", 0.5, 2000.0),
];

/// Numbers a figure measured, by name, and the lines its program prints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    pub values: BTreeMap<String, f64>,
    pub lines: Vec<String>,
}

impl Summary {
    fn set(&mut self, key: impl Into<String>, value: f64) {
        self.values.insert(key.into(), value);
    }

    fn say(&mut self, line: impl Into<String>) {
        self.lines.push(line.into());
    }

    /// A measured value; NaN if the figure did not measure it.
    pub fn get(&self, key: &str) -> f64 {
        self.values.get(key).copied().unwrap_or(f64::NAN)
    }
}

/// Sector centre angles (deg) of a profile with `n` sectors.
pub fn sector_angles_deg(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (i as f64 + 0.5) * 360.0 / n as f64)
        .collect()
}

/// Two recorded rotations after the steady state of a scene.
pub fn steady_run(name: &str) -> Result<(Scene, RunOutput)> {
    steady_run_with(name, |_| {})
}

/// [`steady_run`] of a scene varied by `modify`.
pub fn steady_run_with(name: &str, modify: impl Fn(&mut SceneFile)) -> Result<(Scene, RunOutput)> {
    let mut file = SceneFile::read(scene_path(name))?;
    modify(&mut file);
    file.run.settle = true;
    file.run.rotations = 2;
    file.run.record_rotations = 2;
    file.run.wear_snapshots.clear();
    let scene = file.build()?;
    let out = simulate(&scene)?;
    Ok((scene, out))
}

/// The scene's rotations of coupled wear without time series, with `history` wear profiles
/// saved per rotation.
pub fn wear_run(name: &str, history: u32) -> Result<(Scene, RunOutput)> {
    wear_run_with(name, history, |_| {})
}

/// [`wear_run`] of a scene varied by `modify`.
pub fn wear_run_with(
    name: &str,
    history: u32,
    modify: impl Fn(&mut SceneFile),
) -> Result<(Scene, RunOutput)> {
    let mut file = SceneFile::read(scene_path(name))?;
    modify(&mut file);
    file.run.record_rotations = 0;
    file.run.profile_history_per_rotation = history;
    let scene = file.build()?;
    let out = simulate(&scene)?;
    Ok((scene, out))
}

/// Radial clearance (m) of the scene's first clearance joint.
fn clearance(scene: &Scene) -> f64 {
    let cj = &scene.mechanism.clearance_joints[0];
    cj.r_bearing - cj.r_journal
}

/// Index of the body called `name`.
fn body(scene: &Scene, name: &str) -> Result<usize> {
    scene
        .mechanism
        .bodies()
        .iter()
        .position(|b| b.name == name)
        .ok_or_else(|| {
            Error::invalid(
                "bodies",
                format!("no body `{name}`"),
                "the paper's slider-crank",
            )
        })
}

/// Recorded series of a steady run used by the time-series figures (SI unless named).
struct Traces {
    /// Crank angle from the start of the recording (deg).
    crank_deg: Vec<f64>,
    slider_acc: Vec<f64>,
    wear_rate_um_s: Vec<f64>,
    ex_um: Vec<f64>,
    ey_um: Vec<f64>,
    motion: Motion,
    concordance: Concordance,
}

fn traces(scene: &Scene, out: &RunOutput) -> Result<Traces> {
    let rec = &out.recording;
    let j = &rec.joints[0];
    let slider = body(scene, "slider")?;
    let start = rec.driver_angle[0];
    let dt = rec.time[1] - rec.time[0];
    let um = |v: &[f64], s: f64| v.iter().map(|x| x * s).collect::<Vec<f64>>();
    Ok(Traces {
        crank_deg: rec
            .driver_angle
            .iter()
            .map(|a| (a - start).abs().to_degrees())
            .collect(),
        slider_acc: rec.accelerations[slider][0].clone(),
        wear_rate_um_s: um(&j.wear_rate, 1e6),
        ex_um: um(&j.ex, 1e6),
        ey_um: um(&j.ey, 1e6),
        motion: Motion::classify(&j.delta, dt, scene.run.rotations as f64),
        concordance: Concordance::of(&j.pressure, &j.sliding_velocity, &j.wear_rate, dt),
    })
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

/// Motion mode and concordances of a steady run.
pub fn steady_metrics(scene: &Scene, out: &RunOutput) -> Result<(Motion, Concordance)> {
    let t = traces(scene, out)?;
    Ok((t.motion, t.concordance))
}

/// Records what a steady run measured under `key`.
fn summarise_steady(s: &mut Summary, key: &str, out: &RunOutput, t: &Traces) {
    let Some(settle) = out.settling else { return };
    let j = &out.recording.joints[0];
    let abs_acc: Vec<f64> = t.slider_acc.iter().map(|a| a.abs()).collect();
    // Share of the circumference (1 deg bins) the journal touches while in contact.
    let mut touched = [false; 360];
    for (th, d) in j.theta.iter().zip(&j.delta) {
        if *d >= 0.0 {
            touched[(th.to_degrees() as usize).min(359)] = true;
        }
    }
    let coverage = touched.iter().filter(|&&b| b).count() as f64 / 360.0;
    let max_acc = t.slider_acc.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let max_force = out.recording.joints[0]
        .normal_force
        .iter()
        .cloned()
        .fold(0.0, f64::max);
    let max_pen = out.recording.joints[0]
        .delta
        .iter()
        .cloned()
        .fold(f64::MIN, f64::max);
    for (name, v) in [
        ("settle_rotations", settle.rotations as f64),
        ("settle_orbit_change", settle.orbit_change),
        ("steady", if settle.steady { 1.0 } else { 0.0 }),
        ("contact_fraction", t.motion.contact_fraction),
        ("impacts_per_rotation", t.motion.impacts_per_rotation),
        ("mean_flight_time_s", t.motion.mean_flight_time),
        ("max_slider_acc", max_acc),
        ("max_normal_force", max_force),
        ("max_penetration", max_pen),
        ("contact_coverage", coverage),
        (
            "max_wear_rate",
            j.wear_rate.iter().cloned().fold(0.0, f64::max),
        ),
        ("acc_wear_correlation", centred_cmf(&abs_acc, &j.wear_rate)),
        (
            "force_wear_correlation",
            centred_cmf(&j.normal_force, &j.wear_rate),
        ),
        ("pw", t.concordance.pressure_wear),
        ("sw", t.concordance.sliding_wear),
        ("wall_time_s", out.wall_time),
    ] {
        s.set(format!("{key}.{name}"), v);
    }
    s.say(format!(
        "{key}: {} (in contact {:.1}% of the time, {:.1} impacts/rotation), settled after {} rotations{}; \
         max |slider acc| {max_acc:.0} m/s², max force {max_force:.0} N, max penetration {:.2} µm; \
         CMF P-w {:.4}, s-w {:.4}",
        t.motion.mode(),
        100.0 * t.motion.contact_fraction,
        t.motion.impacts_per_rotation,
        settle.rotations,
        if settle.steady { "" } else { " (orbit not repeating: recorded anyway)" },
        max_pen * 1e6,
        t.concordance.pressure_wear,
        t.concordance.sliding_wear,
    ));
}

/// Writes the time series of steady runs in long format, one block per case.
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

/// A time-series figure of one or two steady cases: `panel` draws each.
fn steady_figure(
    name: &str,
    cases: &[(&str, f64, String)],
    panel: impl for<'a> Fn(String, &'a Traces, f64) -> Axes<'a>,
) -> Result<Summary> {
    let mut s = Summary::default();
    let mut runs = Vec::new();
    for (scene_name, case, title) in cases {
        let (scene, out) = steady_run(scene_name)?;
        let t = traces(&scene, &out)?;
        summarise_steady(&mut s, scene_name, &out, &t);
        runs.push((*case, title.clone(), t, clearance(&scene)));
    }
    let panels: Vec<Axes> = runs
        .iter()
        .map(|(_, title, t, c)| panel(title.clone(), t, *c))
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &panels)?;
    write_steady_csv(
        name,
        &runs
            .iter()
            .map(|(case, _, t, _)| (*case, t))
            .collect::<Vec<_>>(),
    )?;
    Ok(s)
}

/// Figure 3: slider acceleration and wear rate, standard scene.
pub fn fig03() -> Result<Summary> {
    let title = "Slider acceleration and wear rate (0.02 mm, 2000 r/min)".to_string();
    steady_figure("fig03", &[("standard", 0.02, title)], |t, tr, _| {
        acceleration_panel(t, tr)
    })
}

/// Figure 4: journal trajectory, standard scene.
pub fn fig04() -> Result<Summary> {
    let title = "Journal trajectory (0.02 mm, 2000 r/min)".to_string();
    steady_figure("fig04", &[("standard", 0.02, title)], trajectory_panel)
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

/// Figure 8: journal trajectories for 0.2 and 0.5 mm.
pub fn fig08() -> Result<Summary> {
    steady_figure(
        "fig08",
        &clearance_cases("Journal trajectory"),
        trajectory_panel,
    )
}

/// Figure 9: slider acceleration and wear rate for 0.2 and 0.5 mm.
pub fn fig09() -> Result<Summary> {
    steady_figure(
        "fig09",
        &clearance_cases("Slider acceleration and wear rate"),
        |t, tr, _| acceleration_panel(t, tr),
    )
}

/// Figure 12: journal trajectories at 30 and 600 r/min.
pub fn fig12() -> Result<Summary> {
    steady_figure(
        "fig12",
        &speed_cases("Journal trajectory"),
        trajectory_panel,
    )
}

/// Figure 13: slider acceleration and wear rate at 30 and 600 r/min.
pub fn fig13() -> Result<Summary> {
    steady_figure(
        "fig13",
        &speed_cases("Slider acceleration and wear rate"),
        |t, tr, _| acceleration_panel(t, tr),
    )
}

/// Records the peaks and totals of a final wear profile under `key`.
fn summarise_wear(s: &mut Summary, key: &str, scene: &Scene, out: &RunOutput) -> Vec<Peak> {
    let depths = &out.final_wear[0];
    let found = peaks(depths, PEAK_PROMINENCE);
    let mean = depths.iter().sum::<f64>() / depths.len() as f64;
    let max = depths.iter().cloned().fold(0.0, f64::max);
    s.set(format!("{key}.max_depth"), max);
    s.set(format!("{key}.mean_depth"), mean);
    s.set(format!("{key}.wall_time_s"), out.wall_time);
    s.set(format!("{key}.peaks"), found.len() as f64);
    for (i, p) in found.iter().take(3).enumerate() {
        s.set(format!("{key}.peak{}.angle_deg", i + 1), p.angle_deg);
        s.set(format!("{key}.peak{}.depth", i + 1), p.depth);
    }
    let list: Vec<String> = found
        .iter()
        .take(3)
        .map(|p| format!("{:.1} deg ({:.3} µm)", p.angle_deg, p.depth * 1e6))
        .collect();
    s.say(format!(
        "{key}: after {} rotations max wear {:.3} µm, mean {:.3} µm (peak/mean {:.1}); peaks {}",
        scene.run.rotations,
        max * 1e6,
        mean * 1e6,
        max / mean,
        list.join(", ")
    ));
    found
}

/// Wear profile series in µm for each snapshot of a run.
fn snapshot_series(out: &RunOutput) -> Vec<(String, Vec<f64>)> {
    out.wear_snapshots
        .iter()
        .map(|s| {
            (
                format!("{} rotations", s.rotation),
                s.depths[0].iter().map(|d| d * 1e6).collect(),
            )
        })
        .collect()
}

fn profile_panel<'a>(
    title: String,
    angles: &'a [f64],
    profiles: &'a [(String, Vec<f64>)],
    y: &str,
) -> Axes<'a> {
    Axes {
        x_range: Some((0.0, 360.0)),
        ..Axes::new(
            title,
            "circumferential angle (deg)",
            y,
            profiles
                .iter()
                .map(|(l, d)| Series::new(l.clone(), angles, d, Style::Line))
                .collect(),
        )
    }
}

const WEAR_AXIS: &str = "bearing radius increase = wear depth (µm)";

/// Writes wear profiles (mm) of several runs: `angle_deg` then one column per label.
fn write_profiles_csv(name: &str, angles: &[f64], columns: &[(String, Vec<f64>)]) -> Result<()> {
    let mut header = vec!["angle_deg"];
    header.extend(columns.iter().map(|(h, _)| h.as_str()));
    let mm: Vec<Vec<f64>> = columns
        .iter()
        .map(|(_, c)| c.iter().map(|d| d * 1e-3).collect())
        .collect();
    let mut cols: Vec<&[f64]> = vec![angles];
    cols.extend(mm.iter().map(Vec::as_slice));
    write_csv(&output_path("data", &format!("{name}.csv")), &header, &cols)
}

/// Profiles after each snapshot, one panel per case (figures 6, 10, 14).
fn profile_figure(name: &str, cases: &[(&str, f64, String)]) -> Result<(Summary, Vec<Vec<Peak>>)> {
    let mut s = Summary::default();
    let mut panels = Vec::new();
    let mut found = Vec::new();
    for (scene_name, _, title) in cases {
        let (scene, out) = wear_run(scene_name, 0)?;
        let regions = summarise_wear(&mut s, scene_name, &scene, &out);
        // growth of each final region through the snapshots
        for snap in &out.wear_snapshots {
            for (i, p) in regions.iter().take(3).enumerate() {
                s.set(
                    format!("{scene_name}.rot{}.peak{}.depth", snap.rotation, i + 1),
                    snap.depths[0][p.sector],
                );
            }
        }
        found.push(regions);
        panels.push((title.clone(), snapshot_series(&out)));
    }
    let angles = sector_angles_deg(panels[0].1[0].1.len());
    let axes: Vec<Axes> = panels
        .iter()
        .map(|(t, p)| profile_panel(t.clone(), &angles, p, WEAR_AXIS))
        .collect();
    render(&output_path("figures", &format!("{name}.png")), &axes)?;
    let columns: Vec<(String, Vec<f64>)> = cases
        .iter()
        .zip(&panels)
        .flat_map(|((_, case, _), (_, p))| {
            let tag = if cases.len() > 1 {
                format!("case{case}_")
            } else {
                String::new()
            };
            p.iter().map(move |(l, d)| {
                (
                    format!("{tag}rot{}", l.split(' ').next().unwrap_or("")),
                    d.clone(),
                )
            })
        })
        .collect();
    write_profiles_csv(name, &angles, &columns)?;
    Ok((s, found))
}

/// Figure 6: wear depth against angle after 10, 20, 30 and 40 rotations of the standard
/// scene; the summary holds the peaks of the final profile, deepest first.
pub fn fig06() -> Result<Summary> {
    let title = "Bearing wear with crank rotation (c = 0.02 mm, 2000 r/min)".to_string();
    Ok(profile_figure("fig06", &[("standard", 0.02, title)])?.0)
}

/// Figure 10: wear profiles for 0.2 and 0.5 mm.
pub fn fig10() -> Result<Summary> {
    Ok(profile_figure("fig10", &clearance_cases("Bearing wear"))?.0)
}

/// Figure 14: wear profiles at 30 and 600 r/min.
pub fn fig14() -> Result<Summary> {
    Ok(profile_figure("fig14", &speed_cases("Bearing wear"))?.0)
}

/// Final wear profiles of several cases in one panel (figures 11, 15).
fn comparison_figure(name: &str, title: &str, cases: &[(&str, String)]) -> Result<Summary> {
    let mut s = Summary::default();
    let mut profiles = Vec::new();
    for (scene_name, label) in cases {
        let (scene, out) = wear_run(scene_name, 0)?;
        let found = summarise_wear(&mut s, scene_name, &scene, &out);
        // spread of the main regions' depths: 0 when the three deepest regions are equal
        if let [a, .., c] = &found[..found.len().min(3)] {
            s.set(
                format!("{scene_name}.region_spread"),
                (a.depth - c.depth) / a.depth,
            );
        }
        profiles.push((
            label.clone(),
            out.final_wear[0]
                .iter()
                .map(|d| d * 1e6)
                .collect::<Vec<f64>>(),
        ));
    }
    let angles = sector_angles_deg(profiles[0].1.len());
    let axis = "accumulated wear depth after 40 rotations (µm)";
    render(
        &output_path("figures", &format!("{name}.png")),
        &[profile_panel(title.into(), &angles, &profiles, axis)],
    )?;
    write_profiles_csv(name, &angles, &profiles)?;
    Ok(s)
}

/// Figure 11: accumulated wear for 0.02, 0.2 and 0.5 mm.
pub fn fig11() -> Result<Summary> {
    let cases = [
        ("standard", "c = 0.02 mm".to_string()),
        ("clearance_0.2mm", "c = 0.2 mm".to_string()),
        ("clearance_0.5mm", "c = 0.5 mm".to_string()),
    ];
    comparison_figure(
        "fig11",
        "Accumulated wear for different clearances (2000 r/min)",
        &cases,
    )
}

/// Figure 15: accumulated wear at 30, 600 and 2000 r/min.
pub fn fig15() -> Result<Summary> {
    let cases = [
        ("speed_30rpm", "30 r/min".to_string()),
        ("speed_600rpm", "600 r/min".to_string()),
        ("standard", "2000 r/min".to_string()),
    ];
    comparison_figure(
        "fig15",
        "Accumulated wear for different crank speeds (c = 0.02 mm)",
        &cases,
    )
}

/// Figure 5: polar picture of the worn bearing after 40 rotations (standard scene).
pub fn fig05() -> Result<Summary> {
    let (scene, out) = wear_run("standard", 0)?;
    let mut s = Summary::default();
    summarise_wear(&mut s, "standard", &scene, &out);
    let r = scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let angles = sector_angles_deg(out.final_wear[0].len());
    let radius: Vec<Vec<f64>> = out
        .wear_snapshots
        .iter()
        .map(|w| w.depths[0].iter().map(|d| r + d * 1e3).collect())
        .collect();
    let deepest = out.final_wear[0].iter().cloned().fold(0.0, f64::max) * 1e3;
    // magnify so the deepest wear shows as a quarter of the radius, rounded to 1, 2 or 5 × 10ⁿ
    let raw = 0.25 * r / deepest.max(1e-12);
    let decade = 10f64.powf(raw.log10().floor());
    let magnify = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|m| *m <= raw)
        .unwrap_or(decade);
    let profiles: Vec<(String, Vec<f64>)> = out
        .wear_snapshots
        .iter()
        .zip(radius.iter())
        .map(|(w, r)| (format!("{} rotations", w.rotation), r.clone()))
        .collect();
    render_polar(
        &output_path("figures", "fig05.png"),
        "Worn bearing profile, 40 rotations (c = 0.02 mm, 2000 r/min)",
        &angles,
        &profiles,
        r,
        magnify,
    )?;
    let mut header = vec!["angle_deg"];
    let names: Vec<String> = out
        .wear_snapshots
        .iter()
        .map(|w| format!("radius_mm_rot{}", w.rotation))
        .collect();
    header.extend(names.iter().map(String::as_str));
    let mut cols: Vec<&[f64]> = vec![&angles];
    cols.extend(radius.iter().map(Vec::as_slice));
    write_csv(&output_path("data", "fig05.csv"), &header, &cols)?;
    s.set("magnification", magnify);
    Ok(s)
}

/// Figure 7: bearing radius in the three severe regions against crank position, from the wear
/// history (36 profiles per rotation) of the standard scene. A staircase means each region
/// wears only during part of every rotation: the summary gives, per region, the fraction of
/// the history intervals that carry 90% of its wear.
pub fn fig07() -> Result<Summary> {
    const PER_ROTATION: u32 = 36;
    let (scene, out) = wear_run("standard", PER_ROTATION)?;
    let mut s = Summary::default();
    let found = summarise_wear(&mut s, "standard", &scene, &out);
    let r = scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let crank: Vec<f64> = out
        .profile_history
        .iter()
        .map(|(t, _)| t / out.period)
        .collect();
    let mut series = Vec::new();
    for (i, p) in found.iter().take(3).enumerate() {
        let depth: Vec<f64> = out
            .profile_history
            .iter()
            .map(|(_, d)| d[0][p.sector])
            .collect();
        let mut steps: Vec<f64> = depth.windows(2).map(|w| w[1] - w[0]).collect();
        steps.sort_by(|a, b| b.total_cmp(a));
        let total: f64 = steps.iter().sum();
        let mut acc = 0.0;
        let carrying = steps.iter().take_while(|d| {
            acc += **d;
            acc - **d < 0.9 * total
        });
        let share = carrying.count() as f64 / steps.len().max(1) as f64;
        s.set(
            format!("region{}.share_of_intervals_for_90pct", i + 1),
            share,
        );
        s.say(format!(
            "region {} at {:.1} deg: 90% of its wear in {:.0}% of the crank positions",
            i + 1,
            p.angle_deg,
            100.0 * share
        ));
        series.push((
            format!("region at {:.0} deg", p.angle_deg),
            depth.iter().map(|d| r + d * 1e3).collect::<Vec<f64>>(),
        ));
    }
    let axes = Axes::new(
        "Bearing radius in the severe wear regions (0.02 mm, 2000 r/min)",
        "crank position (rotations)",
        "bearing radius (mm)",
        series
            .iter()
            .map(|(l, y)| Series::new(l.clone(), &crank, y, Style::Line))
            .collect(),
    );
    render(&output_path("figures", "fig07.png"), &[axes])?;
    let mut header = vec!["crank_rotations"];
    header.extend(series.iter().map(|(l, _)| l.as_str()));
    let mut cols: Vec<&[f64]> = vec![&crank];
    cols.extend(series.iter().map(|(_, y)| y.as_slice()));
    write_csv(&output_path("data", "fig07.csv"), &header, &cols)?;
    Ok(s)
}

/// One row of Table 3 as measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Table3Row {
    pub clearance_mm: f64,
    pub speed_rpm: f64,
    pub motion: Motion,
    pub concordance: Concordance,
}

/// Table 3: motion mode and concordances of the five cases, each over two recorded rotations
/// after its steady state; writes `data/table3.csv`.
pub fn table3() -> Result<(Vec<Table3Row>, Summary)> {
    let mut s = Summary::default();
    let mut rows = Vec::new();
    for (name, clearance_mm, speed_rpm) in CASES {
        let (scene, out) = steady_run(name)?;
        let t = traces(&scene, &out)?;
        summarise_steady(&mut s, name, &out, &t);
        rows.push(Table3Row {
            clearance_mm,
            speed_rpm,
            motion: t.motion,
            concordance: t.concordance,
        });
    }
    let header = [
        "clearance_mm",
        "speed_rpm",
        "motion",
        "pw",
        "sw",
        "pw_centred",
        "sw_centred",
        "contact_fraction",
        "impacts_per_rotation",
    ];
    write_rows(
        &output_path("data", "table3.csv"),
        &header,
        rows.iter().map(|r| {
            let c = &r.concordance;
            vec![
                r.clearance_mm.to_string(),
                r.speed_rpm.to_string(),
                r.motion.mode().to_string(),
                format!("{:.4}", c.pressure_wear),
                format!("{:.4}", c.sliding_wear),
                format!("{:.4}", c.pressure_wear_centred),
                format!("{:.4}", c.sliding_wear_centred),
                format!("{:.4}", r.motion.contact_fraction),
                format!("{:.2}", r.motion.impacts_per_rotation),
            ]
        }),
    )?;
    Ok((rows, s))
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

/// `main` of a figure program: runs it, prints its summary lines.
pub fn figure_main(name: &str, figure: fn() -> Result<Summary>) {
    let summary = exit_on_error(figure());
    println!("wrote figures/{name}.png and data/{name}.csv");
    for line in &summary.lines {
        println!("{line}");
    }
}
