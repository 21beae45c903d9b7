//! `jointwear longlife SCENE`: wear after many rotations by cycle-jump extrapolation, to a
//! rotation count or a wear limit; its growth and profile CSVs, figures and summary.

use crate::failure::{CliResult, Failure};
use crate::{checked_out_dir, claim_outputs};
use jointwear::analysis::life::{
    changes, sample_motion, validated_until, Change, DEEPEST_MOVE_DEG, HOLD_BLOCKS, RATE_JUMP,
    RATE_WINDOW, VALIDATED_WEAR_RATIO,
};
use jointwear::analysis::CONTINUOUS_CONTACT_FRACTION;
use jointwear::io::format::{self as people, quantity};
use jointwear::io::output::{number, write_rows};
use jointwear::io::plot::{render, Axes, Series, Style};
use jointwear::io::progress::progress_bar;
use jointwear::scene::variant::shell_word;
use jointwear::scene::{SceneFile, MAX_K_OVER_H_PER_PA};
use jointwear::simulation::ensemble::{Perturbation, MAX_MEMBERS};
use jointwear::simulation::folder::{
    body_name, conventions, joint_file, write_folder, write_profiles, write_summary, FolderCommand,
    BLOCKS_FILE, GROWTH_FIGURE, GROWTH_FILE, PROFILES_FIGURE, PROFILES_STEM, PROGRAM, SUMMARY_FILE,
};
use jointwear::simulation::longlife::{
    check_max_change, check_settle_rotations, predict, LongLife, LongLifeSettings,
};
use jointwear::simulation::Scene;
use jointwear::Error;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The options of `longlife`, as given.
pub struct Options {
    /// Rotations to predict.
    pub rotations: f64,
    /// k/H (1/Pa) of every worn joint instead of the scene's.
    pub k_over_h: Option<f64>,
    /// Largest depth change per block, as a fraction of the clearance.
    pub max_change: f64,
    /// Rotations simulated before the first block.
    pub settle: u32,
    /// Wear depth (mm) at which the prediction stops.
    pub until_mm: Option<f64>,
    /// `(member, seed)`: predict that ensemble member's mechanism instead of the scene's.
    pub member: Option<(usize, u64)>,
}

impl Options {
    /// The command line that makes the prediction again: `jointwear longlife SCENE` and every
    /// option, the defaults of `--max-change` and `--settle` too (so that it holds under
    /// other defaults), each number exactly (the shortest text that reads back to it);
    /// `--out` aside.
    fn command(&self, path: &Path) -> String {
        let mut command = format!(
            "jointwear longlife {} --rotations {} --max-change {} --settle {}",
            shell_word(&path.display().to_string()),
            people::exact(self.rotations),
            people::exact(self.max_change),
            self.settle
        );
        if let Some(k) = self.k_over_h {
            command.push_str(&format!(" --k-over-h {}", people::exact(k)));
        }
        if let Some(depth) = self.until_mm {
            command.push_str(&format!(" --until {}", people::exact(depth)));
        }
        if let Some((m, seed)) = self.member {
            command.push_str(&format!(" --member {m} --seed {seed}"));
        }
        command
    }
}

/// `longlife`: predicts the wear of the scene at `path` (k/H overridden if given; member K's
/// mechanism, its journal pin shifted by its offset of the default protocol, with `--member`)
/// after `rotations`, or until a joint's wear reaches `until_mm` (default: its clearance) or
/// its worn bearing grows too steep for the paper's gap.
pub fn longlife(path: &Path, options: &Options, out: Option<PathBuf>) -> CliResult<()> {
    let Options {
        rotations,
        k_over_h,
        max_change,
        settle,
        until_mm,
        member,
    } = *options;
    let bad = |e| Failure::from(path, e);
    if !((1.0..=1e12).contains(&rotations) && rotations.fract() == 0.0) {
        return Err(bad(Error::invalid(
            "--rotations",
            people::exact(rotations),
            "an integer in [1, 1e12]",
        )));
    }
    // The options by their own names (written into the scene, they were reported as its
    // fields).
    if let Some(k) = k_over_h.filter(|k| !(0.0..=MAX_K_OVER_H_PER_PA).contains(k)) {
        return Err(bad(Error::invalid(
            "--k-over-h",
            people::exact(k),
            format!("an Archard coefficient k/H in [0, {MAX_K_OVER_H_PER_PA:e}] 1/Pa"),
        )));
    }
    check_settle_rotations("--settle", settle).map_err(bad)?;
    let mut file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    if let Some(k) = k_over_h {
        let worn = |c: &&jointwear::scene::ClearanceSpec| c.wear.is_some();
        if let Some(c) =
            (file.clearance.iter().filter(worn)).find(|c| k > 0.0 && c.clearance_mm == 0.0)
        {
            return Err(bad(Error::invalid(
                "--k-over-h",
                people::exact(k),
                format!(
                    "0 for this scene: its joint `{}` has no clearance, against which any uneven \
                     wear is steeper than the paper's gap describes (README, validity limits)",
                    c.name
                ),
            )));
        }
        for w in file.clearance.iter_mut().filter_map(|c| c.wear.as_mut()) {
            w.k_over_h_per_pa = k;
        }
    }
    let mut scene = file.build().map_err(bad)?;
    check_max_change("--max-change", max_change, &scene).map_err(bad)?;
    if let Some((m, seed)) = member {
        if m >= MAX_MEMBERS {
            return Err(bad(Error::invalid(
                "--member",
                m,
                format!("a member number in [0, {}]", MAX_MEMBERS - 1),
            )));
        }
        scene.mechanism = Perturbation::default().mechanism(&scene, seed, m);
    }
    let dir = checked_out_dir(path, "longlife", out)?;
    let _claim = claim_outputs(path, &dir, FolderCommand::LongLife)?;
    let target = rotations as u64;
    let settings = LongLifeSettings {
        rotations: target,
        settle_rotations: settle,
        max_change,
        snapshots: (1..5).map(|i| target * i / 5).collect(),
        until: until_mm.map(|d| people::shift_decimal(d, -3)),
        ..LongLifeSettings::default()
    };
    let bar = progress_bar(target, "rotations");
    let result = predict(&scene, &settings, &bar);
    bar.finish_and_clear();
    let life = result.map_err(bad)?;
    let title = options.command(path);
    let summary = LongLifeSummary::new(path, &scene, &settings, options, &life);
    write_folder(&dir, &title, || {
        write_longlife(&scene, &life, &dir)?;
        write_summary(&dir, &summary, &readme(&title, &scene))
    })
    .map_err(bad)?;
    let last = summary.rotations_predicted;
    println!(
        "{}: {last} rotations predicted in {} of wall time",
        scene.title,
        quantity(summary.wall_time_s, "s")
    );
    println!(
        "  simulated: {} rotations ({} settling, then one sampled per block); extrapolated: \
         the other {} over {} blocks",
        summary.rotations_simulated,
        u64::from(settle).min(summary.rotations_simulated),
        last.saturating_sub(summary.rotations_simulated),
        summary.blocks
    );
    match life.reached {
        Some((at, k)) => println!(
            "  joint {} reached its wear limit of {} after {at} rotations{}",
            scene.mechanism.clearance_joints[k].name,
            quantity(life.limits[k] * 1e6, "µm"),
            if until_mm.is_none() {
                " (clearance doubled)"
            } else {
                ""
            }
        ),
        None if life.steep.is_none() => {
            println!("  no joint reached its wear limit within {target} rotations")
        }
        None => {}
    }
    if let Some(stop) = &life.steep {
        println!(
            "  stopped after {} of the {target} rotations asked for, where the model stops: {}",
            stop.rotations, stop.cause
        );
    }
    for j in &summary.joints {
        println!(
            "  joint {}: max wear {} ({} of its limit) after {last} rotations, clearance {} -> {}",
            j.name,
            quantity(j.max_wear_depth_m * 1e6, "µm"),
            quantity(100.0 * j.max_wear_depth_m / j.wear_limit_m, "%"),
            quantity(j.clearance_m * 1e6, "µm"),
            quantity(j.effective_clearance_m * 1e6, "µm")
        );
        let validated = quantity(100.0 * VALIDATED_WEAR_RATIO, "%");
        match j.validated_until_rotations {
            Some(at) => println!(
                "    after {at} rotations (interpolated within the block that crosses it) the \
                 wear passes {validated} of the clearance: beyond the regime where the cycle \
                 jump was checked against simulating every rotation"
            ),
            None => println!(
                "    within the validated regime throughout (wear up to {validated} of the \
                 clearance)"
            ),
        }
        for c in &j.changes {
            println!("    after {} rotations: {}", c.at, c.what);
        }
        if !j.changes.is_empty() {
            println!(
                "    the blocks after a change are extrapolated from samples of the new regime \
                 (per block: {BLOCKS_FILE})"
            );
        }
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
    for &k in &worn {
        let name = &m.clearance_joints[k].name;
        header.extend([format!("{name}.max_depth_m"), format!("{name}.clearance_m")]);
    }
    // rotations are counts: written as integers (the shortest float text wrote 6e5 among 598063)
    let rows = life.history.iter().enumerate().map(|(i, s)| {
        let mut row = vec![s.rotations.to_string()];
        for (depth, clearance) in &growth {
            row.extend([number(depth[i]), number(clearance[i])]);
        }
        row
    });
    write_rows(&dir.join(GROWTH_FILE), &header, rows)?;
    write_blocks(scene, life, &dir.join(BLOCKS_FILE))?;
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
        &dir.join(GROWTH_FIGURE),
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
    write_profiles(dir, PROFILES_STEM, PROFILES_FIGURE, m, &snapshots)?;
    Ok(())
}

/// Writes [`BLOCKS_FILE`] of `life` at `path`: per block the rotations at the end of its
/// sample and after it, and per clearance joint the sample's wear rate, contact fraction,
/// contact onsets per rotation and motion mode.
fn write_blocks(scene: &Scene, life: &LongLife, path: &Path) -> jointwear::Result<()> {
    let mut header = vec!["sampled_rotations".to_string(), "rotations".to_string()];
    for cj in &scene.mechanism.clearance_joints {
        header.extend(
            [
                "wear_rate_m_per_rotation",
                "contact_fraction",
                "impacts_per_rotation",
                "motion_mode",
            ]
            .map(|c| format!("{}.{c}", cj.name)),
        );
    }
    let rows = life.blocks.iter().map(|b| {
        let mut row = vec![b.sampled.to_string(), b.rotations.to_string()];
        for s in &b.joints {
            row.extend([
                number(s.wear_rate),
                number(s.contact_fraction),
                number(s.impacts_per_rotation),
                sample_motion(s).mode().to_string(),
            ]);
        }
        row
    });
    write_rows(path, &header, rows)
}

/// `summary.json` of `longlife`: the settings and, per clearance joint, where its wear got.
#[derive(Serialize)]
struct LongLifeSummary {
    /// `jointwear <version>`.
    program: String,
    scene: String,
    title: String,
    rotations_asked: u64,
    /// `[member, seed]` of `--member`: the ensemble member whose mechanism was predicted.
    member: Option<(usize, u64)>,
    settle_rotations: u32,
    max_change: f64,
    /// `--k-over-h` (1/Pa), every worn joint's k/H; `null`: each joint's own from the scene
    /// (the k/H of each as used: `joints[].k_over_h_per_pa`).
    k_over_h_per_pa: Option<f64>,
    /// `--until` (m), the depth at which a joint's wear stops the prediction; `null`: each
    /// joint's radial clearance (the limit of each as used: `joints[].wear_limit_m`).
    until_m: Option<f64>,
    /// Rotations predicted: the target, or where a joint reached its limit or the model's
    /// validity.
    rotations_predicted: u64,
    rotations_simulated: u64,
    /// Extrapolated blocks.
    blocks: usize,
    wall_time_s: f64,
    /// `[rotations, joint name]` at which a joint reached its wear limit, if any did.
    limit_reached: Option<(u64, String)>,
    /// `[rotations, joint name, cause]` after which a joint's worn bearing grew too steep for
    /// the paper's gap, if one did: the prediction stops there, short of its target.
    validity_stop: Option<(u64, String, String)>,
    joints: Vec<LongLifeJoint>,
}

#[derive(Serialize)]
struct LongLifeJoint {
    name: String,
    journal_body: String,
    bearing_body: String,
    clearance_m: f64,
    /// The Archard coefficient k/H the prediction used (1/Pa); `null` for a joint without wear.
    k_over_h_per_pa: Option<f64>,
    /// The depth at which the prediction stops (m).
    wear_limit_m: f64,
    max_wear_depth_m: f64,
    /// `clearance_m + max_wear_depth_m`.
    effective_clearance_m: f64,
    /// Rotations after which the wear passes the validated regime, `null` if it never does.
    validated_until_rotations: Option<u64>,
    /// The changes along the life, in order of rotations.
    changes: Vec<ChangeSummary>,
}

/// One [`Change`] of a joint, for people (`what`) and programs (`kind`, `from`, `to`).
#[derive(Serialize)]
struct ChangeSummary {
    /// Rotations at which it shows.
    at: u64,
    /// `motion_mode`, `wear_rate_m_per_rotation` (medians of the blocks before and after) or
    /// `deepest_wear_angle_deg`.
    kind: &'static str,
    from: serde_json::Value,
    to: serde_json::Value,
    /// In words, as printed.
    what: String,
}

impl ChangeSummary {
    fn new(change: &Change) -> ChangeSummary {
        use serde_json::json;
        match *change {
            Change::Motion { at, from, to, .. } => ChangeSummary {
                at,
                kind: "motion_mode",
                from: json!(from),
                to: json!(to),
                what: format!("motion {from} -> {to}"),
            },
            Change::WearRate {
                at, before, after, ..
            } => ChangeSummary {
                at,
                kind: "wear_rate_m_per_rotation",
                from: json!(before),
                to: json!(after),
                what: format!(
                    "wear rate {} {}-fold, {} -> {} per rotation (medians of {RATE_WINDOW} \
                     blocks)",
                    if after > before { "jumps" } else { "falls" },
                    people::sig_n((after / before).max(before / after), 2),
                    quantity(before * 1e9, "nm"),
                    quantity(after * 1e9, "nm")
                ),
            },
            Change::Deepest {
                at,
                from_deg,
                to_deg,
                ..
            } => ChangeSummary {
                at,
                kind: "deepest_wear_angle_deg",
                from: json!(from_deg),
                to: json!(to_deg),
                what: format!(
                    "profile shape changes: the deepest wear moves from {} to {}",
                    quantity(from_deg, "deg"),
                    quantity(to_deg, "deg")
                ),
            },
        }
    }
}

impl LongLifeSummary {
    fn new(
        path: &Path,
        scene: &Scene,
        settings: &LongLifeSettings,
        options: &Options,
        life: &LongLife,
    ) -> Self {
        let m = &scene.mechanism;
        let last = life.history.last();
        let mut changes = changes(life);
        changes.sort_by_key(Change::at);
        let joints = (m.clearance_joints.iter().enumerate())
            .map(|(k, cj)| {
                let depth = last.map_or(0.0, |s| s.max_depth(k));
                LongLifeJoint {
                    name: cj.name.clone(),
                    journal_body: body_name(m, cj.journal.body).into(),
                    bearing_body: body_name(m, cj.bearing.body).into(),
                    clearance_m: life.clearances[k],
                    k_over_h_per_pa: cj.wear.map(|w| w.k_over_h),
                    wear_limit_m: life.limits[k],
                    max_wear_depth_m: depth,
                    effective_clearance_m: life.clearances[k] + depth,
                    validated_until_rotations: validated_until(life, k),
                    changes: (changes.iter())
                        .filter(|c| c.joint() == k)
                        .map(ChangeSummary::new)
                        .collect(),
                }
            })
            .collect();
        LongLifeSummary {
            program: PROGRAM.into(),
            scene: path.display().to_string(),
            title: scene.title.clone(),
            rotations_asked: settings.rotations,
            member: options.member,
            settle_rotations: settings.settle_rotations,
            max_change: settings.max_change,
            k_over_h_per_pa: options.k_over_h,
            until_m: settings.until,
            rotations_predicted: last.map_or(0, |s| s.rotations),
            rotations_simulated: life.simulated,
            blocks: life.blocks.len(),
            wall_time_s: life.wall_time,
            limit_reached: (life.reached).map(|(at, k)| (at, m.clearance_joints[k].name.clone())),
            validity_stop: (life.steep.as_ref()).map(|s| {
                let name = m.clearance_joints[s.joint].name.clone();
                (s.rotations, name, s.cause.clone())
            }),
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
         \x20 rotations              rotations counted from the start (an integer)\n\
         \x20 <joint>.max_depth_m    deepest wear of the joint's bearing (m)\n\
         \x20 <joint>.clearance_m    radial clearance + that depth (m)\n\
         longlife_growth.png: the effective clearance against rotations (µm).\n\
         {BLOCKS_FILE}: what each block was extrapolated from, one row per block.\n\
         \x20 sampled_rotations                   rotations done when its sample rotation ended\n\
         \x20 rotations                           rotations done after the block\n\
         \x20 <joint>.wear_rate_m_per_rotation    deepening of the fastest-wearing sector per \
         sampled rotation (m): the rate the block extrapolates\n\
         \x20 <joint>.contact_fraction            share of the sample's time in contact \
         (penetration >= 0 at the end of each integration step, weighted by its length)\n\
         \x20 <joint>.impacts_per_rotation        contact onsets per sampled rotation\n\
         \x20 <joint>.motion_mode                 `continuous contact` (contact fraction >= \
         {CONTINUOUS_CONTACT_FRACTION}) or `free flight and impact`\n\
         {}: the wear profile at 1/5, 2/5, 3/5 and 4/5 of the rotations asked for and at the \
         last count predicted.\n\
         \x20 angle_deg    sector centre in the bearing frame (deg)\n\
         \x20 rot<N>_m     depth worn into the bearing after N rotations (m)\n\
         longlife_profiles.png: those profiles (µm), one panel per joint.\n\n\
         {SUMMARY_FILE}: the prediction as JSON: program; scene; the settings (member: [K, \
         seed] with --member, the member whose mechanism was predicted, or null; \
         k_over_h_per_pa: --k-over-h in 1/Pa, or null for each joint's own; until_m: --until \
         in m, or null for each joint's clearance); rotations \
         predicted and simulated, blocks, wall_time_s; limit_reached ([rotations, joint] or \
         null); validity_stop ([rotations, joint, cause] where a joint's worn bearing grew \
         too steep for the paper's gap and the prediction stopped short of its target, or \
         null); joints (bodies, clearance_m as the scene gives it, k_over_h_per_pa as used \
         (null without wear), wear_limit_m, \
         max_wear_depth_m, effective_clearance_m, validated_until_rotations: after how many \
         rotations (interpolated within the block that crosses it, rounded down) the wear \
         passes {validated} of the clearance, the regime tests/longlife.rs \
         checks the cycle jump in against simulating every rotation, or null; changes: in order \
         of rotations, each `at` (rotations), `kind`, `from`, `to` and `what` (as printed): \
         `motion_mode` when the sample's mode changes for at least {HOLD_BLOCKS} blocks, \
         `wear_rate_m_per_rotation` when the median rate of the {RATE_WINDOW} blocks from a \
         block on differs {RATE_JUMP}-fold or more from that of the {RATE_WINDOW} before it, \
         `deepest_wear_angle_deg` when the deepest sector moves more than {DEEPEST_MOVE_DEG} \
         deg for at least {HOLD_BLOCKS} blocks).\n",
        files(PROFILES_STEM),
        validated = quantity(100.0 * VALIDATED_WEAR_RATIO, "%"),
    ));
    text
}
