//! `jointwear longlife SCENE`: wear after many rotations by cycle-jump extrapolation, to a
//! rotation count or a wear limit; its growth and profile CSVs, figures and summary.

use crate::failure::{CliResult, Failure};
use crate::{checked_out_dir, claim_out};
use jointwear::io::output::{write_csv, write_outputs};
use jointwear::io::plot::{render, Axes, Series, Style};
use jointwear::io::progress::progress_bar;
use jointwear::scene::SceneFile;
use jointwear::simulation::folder::{
    body_name, conventions, joint_file, write_profiles, write_summary, PROGRAM, SUMMARY_FILE,
};
use jointwear::simulation::longlife::{predict, LongLife, LongLifeSettings};
use jointwear::simulation::Scene;
use jointwear::Error;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// `longlife`: predicts the wear of the scene at `path` (k/H overridden if given) after
/// `rotations`, or until a joint's wear reaches `until_mm` (default: its clearance).
pub fn longlife(
    path: &Path,
    rotations: f64,
    k_over_h: Option<f64>,
    max_change: f64,
    settle: u32,
    until_mm: Option<f64>,
    out: Option<PathBuf>,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    if !((1.0..=1e12).contains(&rotations) && rotations.fract() == 0.0) {
        return Err(bad(Error::invalid(
            "--rotations",
            rotations,
            "an integer in [1, 1e12]",
        )));
    }
    let mut file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    if let Some(k) = k_over_h {
        for w in file.clearance.iter_mut().filter_map(|c| c.wear.as_mut()) {
            w.k_over_h_per_pa = k;
        }
    }
    let scene = file.build().map_err(bad)?;
    let dir = checked_out_dir(path, "longlife", out)?;
    let _claim = claim_out(path, &dir)?;
    let target = rotations as u64;
    let settings = LongLifeSettings {
        rotations: target,
        settle_rotations: settle,
        max_change,
        snapshots: (1..5).map(|i| target * i / 5).collect(),
        until: until_mm.map(|d| d * 1e-3),
        ..LongLifeSettings::default()
    };
    let bar = progress_bar(target, "rotations");
    let result = predict(&scene, &settings, &bar);
    bar.finish_and_clear();
    let life = result.map_err(bad)?;
    let mut title = format!("jointwear longlife {} --rotations {target}", path.display());
    if let Some(k) = k_over_h {
        title.push_str(&format!(" --k-over-h {k:e}"));
    }
    let summary = LongLifeSummary::new(path, &scene, &settings, &life);
    write_outputs(&dir, &title, || {
        write_longlife(&scene, &life, &dir)?;
        write_summary(&dir, &summary, &readme(&title, &scene))
    })
    .map_err(bad)?;
    let last = summary.rotations_predicted;
    println!(
        "{}: {last} rotations predicted from {} simulated in {:.1} s ({} blocks)",
        scene.title, summary.rotations_simulated, summary.wall_time_s, summary.blocks
    );
    match life.reached {
        Some((at, k)) => println!(
            "  joint {} reached its wear limit of {:.3} µm after {at} rotations{}",
            scene.mechanism.clearance_joints[k].name,
            life.limits[k] * 1e6,
            if until_mm.is_none() {
                " (clearance doubled)"
            } else {
                ""
            }
        ),
        None => println!("  no joint reached its wear limit within {target} rotations"),
    }
    for j in &summary.joints {
        println!(
            "  joint {}: max wear {:.3} µm ({:.0} % of its limit) after {last} rotations, \
             clearance {:.3} -> {:.3} µm",
            j.name,
            j.max_wear_depth_m * 1e6,
            100.0 * j.max_wear_depth_m / j.wear_limit_m,
            j.clearance_m * 1e6,
            j.effective_clearance_m * 1e6
        );
    }
    println!("outputs in {}", dir.display());
    Ok(())
}

/// Profiles at the snapshot counts and clearance growth, as CSVs and figures.
fn write_longlife(scene: &Scene, life: &LongLife, dir: &Path) -> jointwear::Result<()> {
    let m = &scene.mechanism;
    let worn: Vec<usize> = (0..m.clearance_joints.len())
        .filter(|&k| m.clearance_joints[k].wear.is_some())
        .collect();
    let rotations: Vec<f64> = life.history.iter().map(|s| s.rotations as f64).collect();
    let growth: Vec<(Vec<f64>, Vec<f64>)> = worn
        .iter()
        .map(|&k| {
            let depth: Vec<f64> = life.history.iter().map(|s| s.max_depth(k)).collect();
            let clearance = depth.iter().map(|d| d + life.clearances[k]).collect();
            (depth, clearance)
        })
        .collect();
    let mut header = vec!["rotations".to_string()];
    let mut columns: Vec<&[f64]> = vec![&rotations];
    for (&k, (depth, clearance)) in worn.iter().zip(&growth) {
        let name = &m.clearance_joints[k].name;
        header.extend([format!("{name}.max_depth_m"), format!("{name}.clearance_m")]);
        columns.extend([depth.as_slice(), clearance.as_slice()]);
    }
    let header_ref: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&dir.join("longlife_growth.csv"), &header_ref, &columns)?;
    let clearance_um: Vec<Vec<f64>> = growth
        .iter()
        .map(|(_, c)| c.iter().map(|x| x * 1e6).collect())
        .collect();
    let series = worn
        .iter()
        .zip(&clearance_um)
        .map(|(&k, c)| Series::new(&m.clearance_joints[k].name, &rotations, c, Style::Line))
        .collect();
    render(
        &dir.join("longlife_growth.png"),
        &[Axes::new(
            "Clearance growth: c + maximum wear depth",
            "rotations",
            "effective clearance (µm)",
            series,
        )],
    )?;
    let snapshots: Vec<(u64, &[Vec<f64>])> = life
        .snapshots
        .iter()
        .map(|s| (s.rotations, s.depths.as_slice()))
        .collect();
    write_profiles(
        dir,
        "longlife_profiles",
        "longlife_profiles.png",
        m,
        &snapshots,
    )?;
    Ok(())
}

/// `summary.json` of `longlife`: the settings and, per clearance joint, where its wear got.
#[derive(Serialize)]
struct LongLifeSummary {
    /// `jointwear <version>`.
    program: String,
    scene: String,
    title: String,
    rotations_asked: u64,
    settle_rotations: u32,
    max_change: f64,
    /// Rotations predicted: the target, or where a joint reached its limit.
    rotations_predicted: u64,
    rotations_simulated: u64,
    /// Extrapolated blocks.
    blocks: usize,
    wall_time_s: f64,
    /// `[rotations, joint name]` at which a joint reached its wear limit, if any did.
    limit_reached: Option<(u64, String)>,
    joints: Vec<LongLifeJoint>,
}

#[derive(Serialize)]
struct LongLifeJoint {
    name: String,
    journal_body: String,
    bearing_body: String,
    clearance_m: f64,
    /// The depth at which the prediction stops (m).
    wear_limit_m: f64,
    max_wear_depth_m: f64,
    /// `clearance_m + max_wear_depth_m`.
    effective_clearance_m: f64,
}

impl LongLifeSummary {
    fn new(path: &Path, scene: &Scene, settings: &LongLifeSettings, life: &LongLife) -> Self {
        let m = &scene.mechanism;
        let last = life.history.last();
        let joints = (m.clearance_joints.iter().enumerate())
            .map(|(k, cj)| {
                let depth = last.map_or(0.0, |s| s.max_depth(k));
                LongLifeJoint {
                    name: cj.name.clone(),
                    journal_body: body_name(m, cj.journal.body).into(),
                    bearing_body: body_name(m, cj.bearing.body).into(),
                    clearance_m: life.clearances[k],
                    wear_limit_m: life.limits[k],
                    max_wear_depth_m: depth,
                    effective_clearance_m: life.clearances[k] + depth,
                }
            })
            .collect();
        LongLifeSummary {
            program: PROGRAM.into(),
            scene: path.display().to_string(),
            title: scene.title.clone(),
            rotations_asked: settings.rotations,
            settle_rotations: settings.settle_rotations,
            max_change: settings.max_change,
            rotations_predicted: last.map_or(0, |s| s.rotations),
            rotations_simulated: life.simulated,
            blocks: life.history.len().saturating_sub(1),
            wall_time_s: life.wall_time,
            limit_reached: (life.reached).map(|(at, k)| (at, m.clearance_joints[k].name.clone())),
            joints,
        }
    }
}

/// `README.txt` of a `longlife` folder: the conventions, then every file it wrote.
fn readme(title: &str, scene: &Scene) -> String {
    let mut text = conventions(title, &scene.mechanism, &scene.title);
    let worn: Vec<&str> = (scene.mechanism.clearance_joints.iter())
        .filter(|cj| cj.wear.is_some())
        .map(|cj| cj.name.as_str())
        .collect();
    let files = |stem: &str| {
        let names: Vec<String> = worn.iter().map(|n| joint_file(stem, n)).collect();
        names.join(", ")
    };
    text.push_str(&format!(
        "\nFILES\n\
         Rotations are extrapolated, not simulated, between sampled blocks (cycle jump: the \
         wear of a simulated block, scaled to a block length that changes no depth by more \
         than --max-change of the effective clearance).\n\
         longlife_growth.csv: after every block.\n\
         \x20 rotations              rotations counted from the start\n\
         \x20 <joint>.max_depth_m    deepest wear of the joint's bearing (m)\n\
         \x20 <joint>.clearance_m    radial clearance + that depth (m)\n\
         longlife_growth.png: the effective clearance against rotations (µm).\n\
         {}: the wear profile at 1/5, 2/5, 3/5 and 4/5 of the rotations asked for and at the \
         last count predicted.\n\
         \x20 angle_deg    sector centre in the bearing frame (deg)\n\
         \x20 rot<N>_m     depth worn into the bearing after N rotations (m)\n\
         longlife_profiles.png: those profiles (µm), one panel per joint.\n\n\
         {SUMMARY_FILE}: the prediction as JSON: program; scene; the settings; rotations \
         predicted and simulated, blocks, wall_time_s; limit_reached ([rotations, joint] or \
         null); joints (bodies, clearance_m, wear_limit_m, max_wear_depth_m, \
         effective_clearance_m).\n",
        files("longlife_profiles")
    ));
    text
}
