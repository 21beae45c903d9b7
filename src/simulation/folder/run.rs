//! The folder of one run: its time series, final wear profiles and snapshots, the default
//! plots, `summary.json` and `README.txt` ([`write_run`]).

use super::{
    body_name, conventions, joint_file, perturbation_arg, timeseries_columns, wear_panel,
    write_folder, write_profiles, write_summary, Origin, EVOLUTION_FIGURE, NORMAL_FORCE_FIGURE,
    PROGRAM, SNAPSHOTS_STEM, SUMMARY_FILE, TIMESERIES_FILE, TRAJECTORY_FIGURE, WEAR_FIGURE,
    WEAR_STEM,
};
use crate::analysis::regions::{MIN_PROMINENCE_OF_HEIGHT, MIN_RELATIVE_PROMINENCE};
use crate::io::output::write_csv;
use crate::io::plot::{render, Axes, Series, Style};
use crate::laws::wear::sector_angles_deg;
use crate::ode::Method;
use crate::scene::StepControlSpec;
use crate::simulation::ensemble::EnsembleSettings;
use crate::simulation::summary::{summarize, JointSummary};
use crate::simulation::{RunOutput, RunSettings, Scene, Settling};
use crate::Result;
use serde::Serialize;
use std::path::Path;

/// Writes the folder `dir` of run `out` of `scene` (from `origin`; with `member`, the ensemble
/// and member number it is, `jointwear run --member K --seed S`) and returns its joint
/// summaries. Its `README.txt` and manifest name the command that runs it.
pub fn write_run(
    dir: &Path,
    origin: &Origin,
    scene: &Scene,
    out: &RunOutput,
    member: Option<(&EnsembleSettings, usize)>,
) -> Result<Vec<JointSummary>> {
    let joints = summarize(scene, out);
    // A member ran with its own settings (its tolerances under `tolerance_S`), not the scene's.
    let run = member.map_or_else(
        || scene.run.clone(),
        |(e, k)| e.perturbation.run_settings(&scene.run, e.seed, k),
    );
    let mut summary = RunSummary::new(origin, scene, &run, out, &joints);
    let mut title = origin.command.clone();
    if let Some((e, k)) = member {
        title.push_str(&format!(
            " --member {k} --seed {}{}",
            e.seed,
            perturbation_arg(&e.perturbation)
        ));
        summary.ensemble_member = Some(EnsembleMember::of(e, k));
    }
    write_folder(dir, &title, || {
        write_files(scene, out, dir)?;
        write_summary(dir, &summary, &readme(&title, scene, out))
    })?;
    Ok(joints)
}

/// Time series, final wear profiles and the default plots of a run.
fn write_files(scene: &Scene, out: &RunOutput, dir: &Path) -> Result<()> {
    let (m, rec) = (&scene.mechanism, &out.recording);
    let table = rec.columns(m);
    let header: Vec<&str> = table.iter().map(|(name, _)| name.as_str()).collect();
    let columns: Vec<&[f64]> = table.iter().map(|(_, data)| &data[..]).collect();
    write_csv(&dir.join(TIMESERIES_FILE), &header, &columns)?;

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
        let path = dir.join(joint_file(WEAR_STEM, name));
        write_csv(
            &path,
            &["angle_deg", "depth_m"],
            &[angles, &out.final_wear[*k]],
        )?;
    }
    let snapshots: Vec<(u64, &[Vec<f64>])> = out
        .wear_snapshots
        .iter()
        .map(|s| (u64::from(s.rotation), s.depths.as_slice()))
        .collect();
    write_profiles(dir, SNAPSHOTS_STEM, EVOLUTION_FIGURE, m, &snapshots)?;
    if !worn.is_empty() {
        // (From the start: settling rotations wear too.)
        let title = format!(
            "wear after {} rotations",
            out.rotations_simulated(&scene.run)
        );
        let panels: Vec<Axes> = worn
            .iter()
            .map(|(k, a, um)| {
                let series = vec![Series::new("wear depth", a, um, Style::Line)];
                wear_panel(m, *k, &title, series)
            })
            .collect();
        render(&dir.join(WEAR_FIGURE), &panels)?;
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
        render(&dir.join(TRAJECTORY_FIGURE), &panels)?;
        // one panel per joint, titled by it
        let panels: Vec<Axes> = m
            .clearance_joints
            .iter()
            .zip(&rec.joints)
            .map(|(cj, t)| {
                Axes::new(
                    format!("{}: contact normal force, recorded rotations", cj.name),
                    "time (s)",
                    "normal force (N)",
                    vec![Series::new(
                        "normal force",
                        &rec.time,
                        &t.normal_force,
                        Style::Line,
                    )],
                )
            })
            .collect();
        render(&dir.join(NORMAL_FORCE_FIGURE), &panels)?;
    }
    Ok(())
}

/// `summary.json` of a run: what was run and what it measured, for programs to read.
#[derive(Serialize)]
struct RunSummary {
    /// `jointwear <version>`.
    program: String,
    /// The scene file and what `--set`/`--rotations` changed in it.
    scene: SceneSummary,
    /// The run settings as simulated (a member's its own: [`Perturbation::run_settings`]).
    ///
    /// [`Perturbation::run_settings`]: crate::simulation::ensemble::Perturbation::run_settings
    settings: SettingsSummary,
    /// Integrator and recording counters.
    counts: Counts,
    /// Wall-clock time of the simulation (s), writing excluded.
    wall_time_s: f64,
    /// Relative energy balance residual, with `run.energy_accounting`.
    energy_balance_residual: Option<f64>,
    /// How the run settled, for `run.settle`.
    settling: Option<Settling>,
    /// With `--member`: the ensemble member this run is; `null` for the scene's own start.
    ensemble_member: Option<EnsembleMember>,
    /// Per clearance joint.
    joints: Vec<JointResult>,
}

/// The ensemble member a run is, as `summary.json`'s `ensemble_member` (and Python's
/// `Run.ensemble_member`) says it.
#[derive(Serialize)]
pub struct EnsembleMember {
    /// 0-based.
    member: usize,
    seed: u64,
    /// The protocol's key, as `--perturbation` takes it and the ensemble's summary writes it.
    perturbation: String,
    /// What the protocol does, in words.
    perturbation_description: String,
    /// The member's factor on the scene's rtol and atol (1 but under `tolerance_S`); the
    /// settings above are the member's, multiplied by it.
    tolerance_factor: f64,
}

impl EnsembleMember {
    /// Member `k` of the ensemble `e`.
    pub fn of(e: &EnsembleSettings, k: usize) -> EnsembleMember {
        EnsembleMember {
            member: k,
            seed: e.seed,
            perturbation: e.perturbation.key(),
            perturbation_description: e.perturbation.describe(),
            tolerance_factor: e.perturbation.tolerance_factor(e.seed, k),
        }
    }
}

#[derive(Serialize)]
struct SceneSummary {
    path: String,
    title: String,
    /// Fingerprint of the resolved scene document and its changes (checkpoints carry it).
    fingerprint: String,
    /// `[key, value]` in the order applied: the `--set` values, `--rotations` as
    /// `run.rotations`, and what it cut.
    changes: Vec<(String, String)>,
}

#[derive(Serialize)]
struct SettingsSummary {
    rotations: u32,
    record_rotations: u32,
    record_interval_s: f64,
    wear_snapshots: Vec<u32>,
    method: Method,
    rtol: f64,
    atol: f64,
    /// The step-size controller (`run.step_control`): the steps and counts depend on it.
    step_control: StepControlSpec,
    /// `null`: no bound.
    max_step_s: f64,
    baumgarte_per_s: f64,
    max_steps: u64,
    driver_body: String,
    /// Signed: positive counter-clockwise.
    driver_speed_rpm: f64,
    driver_period_s: f64,
}

#[derive(Serialize)]
struct Counts {
    /// Driver rotations integrated: settling rotations, then `settings.rotations`.
    rotations_simulated: u32,
    settling_rotations: u32,
    /// Rows of `timeseries.csv`.
    recorded_samples: usize,
    steps: u64,
    rejected_steps: u64,
    rhs_evaluations: u64,
    /// Contact onsets located (all joints).
    contact_onsets: u64,
}

#[derive(Serialize)]
struct JointResult {
    name: String,
    journal_body: String,
    bearing_body: String,
    radial_clearance_m: f64,
    /// Largest normal force of the recorded rotations (N); `null` when none were recorded.
    max_normal_force_recorded_n: Option<f64>,
    /// Largest penetration of the recorded rotations (m); `null` when none were recorded.
    max_penetration_recorded_m: Option<f64>,
    /// Largest penetration at the accepted steps of the whole run, start-up transient
    /// included (m).
    max_penetration_whole_run_m: f64,
    /// Contact onsets of this joint over the whole run.
    contact_onsets: u64,
    /// Motion of the recorded rotations; `null` when none were recorded.
    motion: Option<MotionResult>,
    /// Deepest wear of the final profile (m); `null` without a wear model.
    max_wear_depth_m: Option<f64>,
    /// Wear regions of the final profile, most prominent first.
    wear_regions: Vec<RegionResult>,
}

#[derive(Serialize)]
struct MotionResult {
    /// `continuous contact` or `free flight and impact`.
    mode: String,
    contact_fraction: f64,
    impacts_per_rotation: f64,
    mean_flight_time_s: f64,
}

#[derive(Serialize)]
struct RegionResult {
    /// Bearing frame, counter-clockwise from its +x axis.
    angle_deg: f64,
    depth_m: f64,
    prominence_m: f64,
    width_deg: f64,
}

impl RunSummary {
    /// The summary of run `out` of `scene` simulated with `run` (the scene's settings, or an
    /// ensemble member's own).
    fn new(
        origin: &Origin,
        scene: &Scene,
        run: &RunSettings,
        out: &RunOutput,
        joints: &[JointSummary],
    ) -> RunSummary {
        let m = &scene.mechanism;
        let settling = out.settling.map_or(0, |s| s.rotations);
        RunSummary {
            program: PROGRAM.into(),
            scene: SceneSummary {
                path: origin.path.clone(),
                title: scene.title.clone(),
                fingerprint: origin.fingerprint.clone(),
                changes: origin.changes.clone(),
            },
            settings: SettingsSummary {
                rotations: run.rotations,
                record_rotations: run.record_rotations,
                record_interval_s: run.record_interval,
                wear_snapshots: run.wear_snapshots.clone(),
                method: run.method,
                rtol: run.tolerances.rtol,
                atol: run.tolerances.atol,
                step_control: run.step_control,
                max_step_s: run.tolerances.max_step,
                baumgarte_per_s: run.baumgarte,
                max_steps: run.max_steps,
                driver_body: body_name(m, Some(m.driver.body)).to_string(),
                driver_speed_rpm: m.driver.speed_rpm,
                driver_period_s: out.period,
            },
            counts: Counts {
                rotations_simulated: out.rotations_simulated(run),
                settling_rotations: settling,
                recorded_samples: out.recording.time.len(),
                steps: out.stats.steps,
                rejected_steps: out.stats.rejected,
                rhs_evaluations: out.stats.evaluations,
                contact_onsets: out.stats.events,
            },
            wall_time_s: out.wall_time,
            energy_balance_residual: out.energy.map(|e| e.residual()),
            settling: out.settling,
            ensemble_member: None,
            joints: m
                .clearance_joints
                .iter()
                .zip(joints)
                .enumerate()
                .map(|(k, (cj, j))| JointResult {
                    name: j.name.clone(),
                    journal_body: body_name(m, cj.journal.body).to_string(),
                    bearing_body: body_name(m, cj.bearing.body).to_string(),
                    radial_clearance_m: cj.given_clearance,
                    max_normal_force_recorded_n: j.max_normal_force_recorded,
                    max_penetration_recorded_m: j.max_penetration_recorded,
                    max_penetration_whole_run_m: j.max_penetration_whole_run,
                    contact_onsets: out.impacts[k],
                    motion: j.motion.map(|m| MotionResult {
                        mode: m.mode().to_string(),
                        contact_fraction: m.contact_fraction,
                        impacts_per_rotation: m.impacts_per_rotation,
                        mean_flight_time_s: m.mean_flight_time,
                    }),
                    max_wear_depth_m: cj
                        .wear
                        .map(|_| out.final_wear[k].iter().cloned().fold(0.0, f64::max)),
                    wear_regions: j
                        .regions
                        .iter()
                        .map(|p| RegionResult {
                            angle_deg: p.angle_deg,
                            depth_m: p.depth,
                            prominence_m: p.prominence,
                            width_deg: p.width_deg,
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}

/// `README.txt` of a run's folder: the conventions, then every file and column it wrote.
fn readme(title: &str, scene: &Scene, out: &RunOutput) -> String {
    let m = &scene.mechanism;
    let run = &scene.run;
    let mut text = conventions(title, m, &scene.title);
    text.push_str("\nFILES\n");
    let rows = out.recording.time.len();
    text.push_str(&format!(
        "timeseries.csv: the last {} rotation(s) of the run (run.record_rotations), sampled \
         every {} s: {rows} rows.\n",
        run.record_rotations,
        crate::io::output::number(run.record_interval),
    ));
    text.push_str(&timeseries_columns(m));
    let worn: Vec<&str> = m
        .clearance_joints
        .iter()
        .filter(|cj| cj.wear.is_some())
        .map(|cj| cj.name.as_str())
        .collect();
    if !worn.is_empty() {
        let files: Vec<String> = worn.iter().map(|n| joint_file(WEAR_STEM, n)).collect();
        text.push_str(&format!(
            "{}: the wear profile of the bearing at the end of the run.\n\
             \x20 angle_deg    sector centre in the bearing frame (deg)\n\
             \x20 depth_m      depth worn into the bearing (m)\n\
             wear.png: those profiles (µm).\n\n",
            files.join(", ")
        ));
        if !out.wear_snapshots.is_empty() {
            let files: Vec<String> = worn.iter().map(|n| joint_file(SNAPSHOTS_STEM, n)).collect();
            let counts: Vec<String> = out
                .wear_snapshots
                .iter()
                .map(|s| s.rotation.to_string())
                .collect();
            text.push_str(&format!(
                "{}: the wear profile after each of the rotation counts of run.wear_snapshots \
                 ({}; counted from the start, settling rotations included).\n\
                 \x20 angle_deg    sector centre in the bearing frame (deg)\n\
                 \x20 rot<N>_m     depth worn into the bearing after N rotations (m)\n\
                 wear_evolution.png: those profiles (µm), one panel per joint.\n\n",
                files.join(", "),
                counts.join(", ")
            ));
        }
    }
    if rows > 0 && !m.clearance_joints.is_empty() {
        text.push_str(
            "trajectory.png: journal centre relative to the bearing centre (ex, ey, global \
             frame, µm) inside the clearance circle, recorded rotations.\n\
             normal_force.png: contact normal force against time, recorded rotations.\n\n",
        );
    }
    text.push_str(&format!(
        "{SUMMARY_FILE}: the run as JSON: program; scene (path, title, fingerprint, changes: \
         the [key, value] pairs of --set and --rotations); settings (as simulated, SI units in \
         the key names; method and tolerances, a --member run's its own: the scene's rtol and \
         atol times its tolerance_factor; driver_speed_rpm signed, positive \
         counter-clockwise); counts (rotations simulated, settling rotations, recorded samples, \
         steps, rejected steps, right-hand-side evaluations, contact onsets); wall_time_s; \
         energy_balance_residual (with run.energy_accounting: driver work less the mechanical \
         energy's change and the damping and friction losses, over the whole run from the \
         start, relative to the larger of the driver work and the mechanical change; else \
         null); settling (rotations, orbit_change: the last settling rotation's RMS orbit \
         change over the clearance, steady: false where run.steady_state.max_rotations was \
         reached first, and the recorded rotations are then not a steady state; null without \
         settling); joints (per clearance joint: bodies, radial \
         clearance, max_normal_force_recorded_n and max_penetration_recorded_m, the largest \
         samples (every run.record_interval_s) of the recorded rotations, or null if none were \
         recorded, max_penetration_whole_run_m over \
         every step from the start (the start-up transient, the impact after the centred \
         start, included), contact onsets, motion (mode: \
         `continuous contact` or `free flight and impact`, contact fraction, impacts per \
         rotation, mean duration of the free flights that begin and end inside the recorded \
         rotations, null if none) or null, max_wear_depth_m, wear_regions: angle_deg in the \
         bearing frame, depth_m, prominence_m, width_deg at half prominence, most prominent \
         first; a region is a hump of the profile by topographic prominence, at least {:.0} % of \
         the most prominent one's and {:.0} % of its own height above the shallowest sector); \
         ensemble_member (with --member: member, seed, perturbation, perturbation_description, \
         tolerance_factor: the factor on the scene's rtol and atol, uniform in [1 - S, 1 + S] \
         under tolerance_S, else 1; null without).\n",
        100.0 * MIN_RELATIVE_PROMINENCE,
        100.0 * MIN_PROMINENCE_OF_HEIGHT,
    ));
    text
}
