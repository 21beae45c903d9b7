//! `jointwear run SCENE`: one run of a scene, with checkpoints and resumption, its time series,
//! wear profiles and default plots, and the summary it prints.

use crate::failure::{CliResult, Failure};
use crate::{file_part, load, out_dir};
use jointwear::io::interrupt;
use jointwear::io::output::{check_output_dir, write_csv, write_outputs};
use jointwear::io::plot::{render, Axes, Series, Style};
use jointwear::io::progress::{progress_bar, Progress};
use jointwear::laws::wear::sector_angles_deg;
use jointwear::scene::SceneFile;
use jointwear::simulation::checkpoint::{read_checkpoint, write_checkpoint, CHECKPOINT_FILE};
use jointwear::simulation::Scene;
use jointwear::simulation::{RunOutput, Simulation};
use jointwear::sweep::file::fingerprint;
use jointwear::sweep::summarize;
use jointwear::Error;
use std::path::{Path, PathBuf};

/// `run` without `--ensemble`: simulates the scene at `path` (or resumes its checkpoint),
/// writes its outputs into `out` and prints a summary.
pub fn run(
    path: &Path,
    out: Option<PathBuf>,
    checkpoint_every: Option<u32>,
    resume: bool,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    let scene = load(path)?;
    let dir = out_dir(path, out);
    check_output_dir("--out", &dir).map_err(bad)?;
    if checkpoint_every == Some(0) {
        return Err(Failure::input(
            path,
            Error::invalid("--checkpoint-every", 0, "at least 1 rotation"),
        ));
    }
    let saved = dir.join(CHECKPOINT_FILE);
    let fingerprint = scene_fingerprint(path)?;
    let mut sim = if resume {
        let checkpoint = read_checkpoint(&saved, &fingerprint).map_err(|e| match e {
            Error::Io { .. } => Failure::input(
                path,
                Error::invalid(
                    "--resume",
                    saved.display(),
                    "a checkpoint written by `run --checkpoint-every K` into this --out folder",
                ),
            ),
            e => Failure::input(path, e),
        })?;
        Simulation::resume(&scene, checkpoint).map_err(|e| Failure::input(path, e))?
    } else {
        Simulation::start(&scene).map_err(bad)?
    };
    if checkpoint_every.is_some() {
        interrupt::keep(format!(
            "the last checkpoint stays in {} (continue with --resume)",
            saved.display()
        ));
    }
    let bar = progress_bar(scene.run.rotations as u64, "rotations");
    let result = (|| {
        while !sim.is_finished() {
            sim.advance_rotation()?;
            let done = sim.rotations_done();
            // While a run settles its length is unknown: the bar then counts settling rotations.
            let total = sim.total_rotations();
            let total = total.unwrap_or(done + scene.run.rotations);
            bar.observe(done.into(), Some(total.into()));
            if checkpoint_every.is_some_and(|k| done % k == 0) {
                write_checkpoint(&saved, &fingerprint, sim.checkpoint())?;
            }
        }
        Ok(())
    })();
    bar.finish_and_clear();
    result.map_err(bad)?;
    let out = sim.finish();
    let title = format!("jointwear run {}", path.display());
    write_outputs(&dir, &title, || write_run(&scene, &out, &dir))
        .map_err(|e| Failure::from(path, e))?;
    // A completed run needs no checkpoint; a failed one keeps its last.
    if saved.exists() {
        std::fs::remove_file(&saved).map_err(|source| {
            bad(Error::Io {
                path: saved.clone(),
                source,
            })
        })?;
    }
    print_summary(&scene, &out);
    println!("outputs in {}", dir.display());
    Ok(())
}

/// The fingerprint of a scene file as it is now (its resolved document).
fn scene_fingerprint(path: &Path) -> CliResult<String> {
    let doc = SceneFile::read_document(path).map_err(|e| Failure::input(path, e))?;
    Ok(fingerprint(&doc, &[]))
}

/// Time series, final wear profiles and the default plots of a run.
fn write_run(scene: &Scene, out: &RunOutput, dir: &Path) -> jointwear::Result<()> {
    let m = &scene.mechanism;
    let rec = &out.recording;
    let mut header = vec!["time_s".to_string(), "driver_angle_rad".to_string()];
    let mut columns: Vec<&[f64]> = vec![&rec.time, &rec.driver_angle];
    for (cj, tr) in m.clearance_joints.iter().zip(&rec.joints) {
        let series: [(&str, &[f64]); 8] = [
            ("ex_m", &tr.ex),
            ("ey_m", &tr.ey),
            ("penetration_m", &tr.delta),
            ("normal_force_n", &tr.normal_force),
            ("friction_force_n", &tr.friction_force),
            ("sliding_velocity_m_s", &tr.sliding_velocity),
            ("pressure_pa", &tr.pressure),
            ("wear_rate_m_s", &tr.wear_rate),
        ];
        for (name, data) in series {
            header.push(format!("{}.{name}", cj.name));
            columns.push(data);
        }
    }
    for (body, acc) in m.bodies().iter().zip(&rec.accelerations) {
        for (name, data) in ["ax_m_s2", "ay_m_s2", "alpha_rad_s2"].iter().zip(acc) {
            header.push(format!("{}.{name}", body.name));
            columns.push(data);
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&dir.join("timeseries.csv"), &header, &columns)?;

    let worn: Vec<(usize, Vec<f64>, Vec<f64>)> = m
        .clearance_joints
        .iter()
        .enumerate()
        .filter(|(_, cj)| cj.wear.is_some())
        .map(|(k, _)| {
            let depth = &out.final_wear[k];
            (
                k,
                sector_angles_deg(depth.len()),
                depth.iter().map(|d| d * 1e6).collect(),
            )
        })
        .collect();
    for (k, angles, _) in &worn {
        let name = &m.clearance_joints[*k].name;
        let path = dir.join(format!("wear_{}.csv", file_part(name)));
        write_csv(
            &path,
            &["angle_deg", "depth_m"],
            &[angles, &out.final_wear[*k]],
        )?;
    }
    if !worn.is_empty() {
        let series = worn
            .iter()
            .map(|(k, a, um)| Series::new(&m.clearance_joints[*k].name, a, um, Style::Line))
            .collect();
        let axes = Axes {
            x_range: Some((0.0, 360.0)),
            ..Axes::new(
                format!("Wear after {} rotations", scene.run.rotations),
                "bearing angle (deg)",
                "wear depth (µm)",
                series,
            )
        };
        render(&dir.join("wear.png"), &[axes])?;
    }
    if rec.time.is_empty() {
        return Ok(());
    }
    let um = |v: &[f64]| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
    let orbits: Vec<(Vec<f64>, Vec<f64>)> =
        rec.joints.iter().map(|t| (um(&t.ex), um(&t.ey))).collect();
    let panels: Vec<Axes> = m
        .clearance_joints
        .iter()
        .zip(&orbits)
        .map(|(cj, (x, y))| {
            let c = (cj.r_bearing - cj.r_journal) * 1e6;
            Axes {
                equal_aspect: true,
                circles: vec![(0.0, 0.0, c)],
                ..Axes::new(
                    format!("{}: journal centre (c = {c:.3} µm)", cj.name),
                    "x (µm)",
                    "y (µm)",
                    vec![Series::new("journal centre", x, y, Style::Line)],
                )
            }
        })
        .collect();
    if !panels.is_empty() {
        render(&dir.join("trajectory.png"), &panels)?;
        let series = m
            .clearance_joints
            .iter()
            .zip(&rec.joints)
            .map(|(cj, t)| Series::new(&cj.name, &rec.time, &t.normal_force, Style::Line))
            .collect();
        let axes = Axes::new(
            "Contact normal force",
            "time (s)",
            "normal force (N)",
            series,
        );
        render(&dir.join("normal_force.png"), &[axes])?;
    }
    Ok(())
}

/// The run's summary on stdout: counters, and per joint forces, motion and wear peaks.
fn print_summary(scene: &Scene, out: &RunOutput) {
    let s = &out.stats;
    println!("{}", scene.title);
    println!(
        "  {} rotations in {:.2} s wall time: {} steps, {} rejected, {} evaluations, {} contact onsets",
        scene.run.rotations, out.wall_time, s.steps, s.rejected, s.evaluations, s.events
    );
    if let Some(e) = out.energy {
        println!("  energy balance residual {:.2e}", e.residual());
    }
    for j in summarize(scene, out) {
        println!("  joint {}:", j.name);
        println!(
            "    max normal force {:.2} N (recorded rotations), max penetration {:.3} µm",
            j.max_normal_force,
            j.max_penetration * 1e6
        );
        if let Some(m) = j.motion {
            println!(
                "    motion: {} ({:.0} % in contact, {:.1} impacts per rotation)",
                m.mode(),
                100.0 * m.contact_fraction,
                m.impacts_per_rotation
            );
        }
        for p in j.peaks.iter().take(3) {
            println!(
                "    wear peak at {:6.1} deg: depth {:.4} µm, width {:.0} deg",
                p.angle_deg,
                p.depth * 1e6,
                p.width_deg
            );
        }
    }
}
