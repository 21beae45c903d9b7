//! `jointwear run SCENE --ensemble N`: members in parallel from seeded initial offsets, their
//! statistics as CSVs (members, summary, per-sector wear bands), the band plot and the summary
//! it prints.

use crate::failure::{CliResult, Failure};
use crate::{file_part, load, out_dir};
use jointwear::analysis::statistics::{Distribution, QUANTILES};
use jointwear::io::output::{check_output_dir, write_outputs, write_rows};
use jointwear::io::plot::{render, Axes, Series, Shade, Style};
use jointwear::io::progress::progress_bar;
use jointwear::laws::wear::sector_angles_deg;
use jointwear::simulation::ensemble::{self, member_offsets, EnsembleSettings};
use jointwear::simulation::Scene;
use jointwear::sweep::{
    header, joint_statistics, summarize, CaseResult, JointStatistics, JointSummary, Outcome,
};
use std::path::{Path, PathBuf};

/// `run --ensemble`: members in parallel, their statistics as CSVs, a band plot and a summary.
pub fn run_ensemble(
    path: &Path,
    out: Option<PathBuf>,
    settings: EnsembleSettings,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    settings.validate().map_err(|e| Failure::input(path, e))?;
    let scene = load(path)?;
    let dir = out_dir(path, out);
    check_output_dir("--out", &dir).map_err(bad)?;
    let clock = std::time::Instant::now();
    let bar = progress_bar(settings.members as u64, "members");
    let members = ensemble::run(
        &scene,
        &settings,
        |_, o| ((summarize(&scene, &o), o.final_wear), o.wall_time),
        &bar,
    );
    bar.finish_and_clear();
    let (members, walls): (Vec<Member>, Vec<f64>) = members.map_err(bad)?.into_iter().unzip();
    let wall = clock.elapsed().as_secs_f64();
    let title = format!(
        "jointwear run {} --ensemble {}",
        path.display(),
        settings.members
    );
    let stats = write_outputs(&dir, &title, || {
        write_ensemble(&scene, &settings, &members, &walls, &dir)
    })
    .map_err(bad)?;
    println!("{}", scene.title);
    println!(
        "  {} members (seed {}) of {} rotations in {wall:.2} s wall time",
        settings.members, settings.seed, scene.run.rotations
    );
    for j in &stats {
        println!("  joint {} (mean ± sd, [5 %, 95 %]):", j.name);
        for (name, d) in &j.scalars {
            if name == &"continuous_contact" {
                let k = (d.mean * d.n as f64).round();
                println!("    continuous contact in {k} of {} members", d.n);
            } else if d.n > 0 {
                println!(
                    "    {name:22} {:.6e} ± {:.2e}  [{:.6e}, {:.6e}]",
                    d.mean, d.sd, d.quantiles[0], d.quantiles[4]
                );
            }
        }
    }
    println!("outputs in {}", dir.display());
    Ok(())
}

/// One member of `run --ensemble`: its joint summaries and final wear profiles.
type Member = (Vec<JointSummary>, Vec<Vec<f64>>);

/// The ensemble's CSVs and band plot; returns the statistics it wrote.
fn write_ensemble(
    scene: &Scene,
    settings: &EnsembleSettings,
    members: &[Member],
    walls: &[f64],
    dir: &Path,
) -> jointwear::Result<Vec<JointStatistics>> {
    let m = &scene.mechanism;
    let joints: Vec<String> = m.clearance_joints.iter().map(|c| c.name.clone()).collect();
    // One row per member: its offsets d (journal body frame), then a sweep row's joint columns.
    let mut head = vec!["member".to_string()];
    for j in &joints {
        head.extend([
            format!("{j}.offset_body_x_m"),
            format!("{j}.offset_body_y_m"),
        ]);
    }
    head.extend(header(&[], &joints).into_iter().skip(1));
    let rows = members
        .iter()
        .zip(walls)
        .enumerate()
        .map(|(i, ((summary, _), secs))| {
            let mut row = vec![i.to_string()];
            for d in member_offsets(settings.seed, i, joints.len()) {
                row.extend([format!("{:e}", d.x), format!("{:e}", d.y)]);
            }
            let record = CaseResult {
                case: i,
                values: Vec::new(),
                outcome: Ok((Outcome::Run(summary.clone()), *secs)),
            }
            .record(header(&[], &joints).len() - 3);
            row.extend(record.into_iter().skip(1));
            row
        });
    write_rows(&dir.join("ensemble_members.csv"), &head, rows)?;
    let stats = joint_statistics(scene, members);
    let q = QUANTILES.map(|p| format!("q{:02.0}", 100.0 * p));
    let mut head = vec!["joint", "quantity", "n", "mean", "sd", "min"];
    head.extend(q.iter().map(String::as_str));
    head.push("max");
    let numbers = |d: &Distribution| -> Vec<String> {
        [d.mean, d.sd, d.min]
            .iter()
            .chain(&d.quantiles)
            .chain([&d.max])
            .map(|x| format!("{x:e}"))
            .collect()
    };
    let mut rows = Vec::new();
    for j in &stats {
        for (name, d) in &j.scalars {
            let mut row = vec![j.name.clone(), name.to_string(), d.n.to_string()];
            row.extend(numbers(d));
            rows.push(row);
        }
    }
    write_rows(&dir.join("ensemble_summary.csv"), &head, rows)?;
    let mut series = Vec::new();
    for j in &stats {
        let Some(band) = &j.wear else { continue };
        let angles = sector_angles_deg(band.sectors.len());
        let mut head = vec!["angle_deg".to_string()];
        head.extend(["mean_m", "sd_m", "min_m"].map(String::from));
        head.extend(q.iter().map(|q| format!("{q}_m")));
        head.push("max_m".into());
        let rows = band.sectors.iter().zip(&angles).map(|(d, a)| {
            let mut row = vec![format!("{a:e}")];
            row.extend(numbers(d));
            row
        });
        let file = format!("ensemble_wear_{}.csv", file_part(&j.name));
        write_rows(&dir.join(file), &head, rows)?;
        let um = |v: Vec<f64>| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
        let (mean, lo, hi) = (um(band.mean()), um(band.quantile(0)), um(band.quantile(4)));
        series.push((j.name.clone(), angles, mean, lo, hi));
    }
    if !series.is_empty() {
        let axes = Axes {
            x_range: Some((0.0, 360.0)),
            shades: series
                .iter()
                .enumerate()
                .map(|(i, (_, _, _, lo, hi))| Shade { series: i, lo, hi })
                .collect(),
            ..Axes::new(
                format!(
                    "Wear after {} rotations: mean of {} members, 5-95 % shaded",
                    scene.run.rotations, settings.members
                ),
                "bearing angle (deg)",
                "wear depth (µm)",
                series
                    .iter()
                    .map(|(n, a, mean, _, _)| Series::new(n, a, mean, Style::Line))
                    .collect(),
            )
        };
        render(&dir.join("wear.png"), &[axes])?;
    }
    Ok(stats)
}
