//! `jointwear longlife SCENE`: wear after many rotations by cycle-jump extrapolation, to a
//! rotation count or a wear limit; its growth and profile CSVs, figures and summary.

use crate::checked_out_dir;
use crate::failure::{CliResult, Failure};
use crate::outputs::write_profiles;
use jointwear::io::output::{write_csv, write_outputs};
use jointwear::io::plot::{render, Axes, Series, Style};
use jointwear::io::progress::progress_bar;
use jointwear::scene::SceneFile;
use jointwear::simulation::longlife::{predict, LongLife, LongLifeSettings};
use jointwear::simulation::Scene;
use jointwear::Error;
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
    let dir = checked_out_dir(path, out)?;
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
    let title = format!("jointwear longlife {}", path.display());
    write_outputs(&dir, &title, || write_longlife(&scene, &life, &dir)).map_err(bad)?;
    let last = life.history.last().map_or(0, |s| s.rotations);
    println!(
        "{}: {last} rotations predicted from {} simulated in {:.1} s ({} blocks)",
        scene.title,
        life.simulated,
        life.wall_time,
        life.history.len() - 1
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
    for (k, cj) in scene.mechanism.clearance_joints.iter().enumerate() {
        let depth = life.history.last().map_or(0.0, |s| s.max_depth(k));
        println!(
            "  joint {}: max wear {:.3} µm ({:.0} % of its limit) after {last} rotations, \
             clearance {:.3} -> {:.3} µm",
            cj.name,
            depth * 1e6,
            100.0 * depth / life.limits[k],
            life.clearances[k] * 1e6,
            (life.clearances[k] + depth) * 1e6
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
