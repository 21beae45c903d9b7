//! Output folders of runs: the files, `README.txt` and `summary.json` of one run ([`run`]) and
//! of an ensemble ([`ensemble`]), written here for the `jointwear` program and Python's
//! `Run.save` / `Ensemble.save` alike, so that both write identical folders; and the pieces
//! every output folder shares (also `longlife`'s): wear profiles at several rotation counts,
//! the conventions its `README.txt` states (units, frames, signs, number format), per-joint
//! file names.
//!
//! A folder is written through [`write_folder`] (atomic files and a manifest; the files of the
//! previous write into the folder that this one did not rewrite are removed, and only names
//! its writers write, `FOLDER_FILES`; a folder holding another command's outputs is refused,
//! [`FolderCommand`]); claiming it against other processes
//! ([`crate::io::lock::claim_folder`]) is the caller's, who may hold it from before the run.

pub mod ensemble;
pub mod run;

use crate::io::output::{
    manifest_title, read_manifest, sweep_file_in, write_csv, write_json, write_outputs, write_text,
    MANIFEST,
};
use crate::io::plot::{render, Axes, Series, Style};
use crate::laws::wear::sector_angles_deg;
use crate::mechanism::{BodyIndex, Mechanism};
use crate::scene::variant::shell_words;
use crate::simulation::ensemble::Perturbation;
use crate::simulation::journal::refuse_journal;
use crate::{Error, Result};
use serde::Serialize;
use std::path::Path;

/// Where the scene of a folder came from, as its `summary.json` and `README.txt` say.
#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    /// The scene file as named (for a Python scene built from a dict, the `scene.toml` its
    /// folder holds).
    pub path: String,
    /// The fingerprint of the scene and its changes ([`crate::scene::variant::fingerprint`]).
    pub fingerprint: String,
    /// Every change to the scene file as `[key, value]`, in the order made.
    pub changes: Vec<(String, String)>,
    /// The command line that runs this scene: `jointwear run SCENE --set … --rotations N`.
    pub command: String,
}

/// The part of a file name that stands for the clearance joint `name`: letters, digits, `-`
/// and `_` kept, every other character turned into `_` (`wear_<part>.csv`).
pub fn joint_file_part(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The file `<stem>_<joint>.csv` of a per-joint output, the joint's name made safe for a file
/// name ([`joint_file_part`]; a scene whose joints would share a file is refused at load).
pub fn joint_file(stem: &str, joint: &str) -> String {
    format!("{stem}_{}.csv", joint_file_part(joint))
}

/// The recorded rotations of a run.
pub const TIMESERIES_FILE: &str = "timeseries.csv";

/// Stem of a run's final wear profile per joint, `wear_<joint>.csv`.
pub const WEAR_STEM: &str = "wear";

/// Stem of a run's wear snapshots per joint.
pub const SNAPSHOTS_STEM: &str = "wear_snapshots";

/// The final wear profiles of a run, or an ensemble's band.
pub const WEAR_FIGURE: &str = "wear.png";

/// A run's wear snapshots.
pub const EVOLUTION_FIGURE: &str = "wear_evolution.png";

/// A run's journal orbits.
pub const TRAJECTORY_FIGURE: &str = "trajectory.png";

/// A run's normal forces.
pub const NORMAL_FORCE_FIGURE: &str = "normal_force.png";

/// An ensemble's members, one row each.
pub const MEMBERS_FILE: &str = "ensemble_members.csv";

/// An ensemble's statistics.
pub const STATISTICS_FILE: &str = "ensemble_summary.csv";

/// Stem of an ensemble's wear band per joint.
pub const BAND_STEM: &str = "ensemble_wear";

/// A long-life prediction's clearance growth.
pub const GROWTH_FILE: &str = "longlife_growth.csv";

/// Its figure.
pub const GROWTH_FIGURE: &str = "longlife_growth.png";

/// A long-life prediction's blocks.
pub const BLOCKS_FILE: &str = "longlife_blocks.csv";

/// Stem of a long-life prediction's profiles per joint.
pub const PROFILES_STEM: &str = "longlife_profiles";

/// Their figure.
pub const PROFILES_FIGURE: &str = "longlife_profiles.png";

/// A file of output folders: one name, or per clearance joint `<stem>_<joint>.csv`
/// ([`joint_file`]).
#[derive(Clone, Copy)]
enum FolderFile {
    Named(&'static str),
    PerJoint(&'static str),
}

/// Every file the writers of output folders write: `run` ([`run`]), `run --ensemble`
/// ([`ensemble`]) and `longlife` (the program's), also through Python's `save`. A writer
/// cannot write another name into its folder ([`write_folder`] refuses it, so a new file
/// fails its first write until it is listed here), and a rerun removes no other, whatever a
/// manifest lists: never the user's files, a checkpoint, the lock or a dot-file.
const FOLDER_FILES: [FolderFile; 17] = [
    FolderFile::Named(SUMMARY_FILE),
    FolderFile::Named(README_FILE),
    FolderFile::Named(TIMESERIES_FILE),
    FolderFile::PerJoint(WEAR_STEM),
    FolderFile::PerJoint(SNAPSHOTS_STEM),
    FolderFile::Named(WEAR_FIGURE),
    FolderFile::Named(EVOLUTION_FIGURE),
    FolderFile::Named(TRAJECTORY_FIGURE),
    FolderFile::Named(NORMAL_FORCE_FIGURE),
    FolderFile::Named(MEMBERS_FILE),
    FolderFile::Named(STATISTICS_FILE),
    FolderFile::PerJoint(BAND_STEM),
    FolderFile::Named(GROWTH_FILE),
    FolderFile::Named(GROWTH_FIGURE),
    FolderFile::Named(BLOCKS_FILE),
    FolderFile::PerJoint(PROFILES_STEM),
    FolderFile::Named(PROFILES_FIGURE),
];

/// Whether `name` is a file of output folders ([`FOLDER_FILES`]): a per-joint file's joint
/// part is one [`joint_file_part`] can have made of a joint's name (never empty).
fn is_folder_file(name: &str) -> bool {
    FOLDER_FILES.iter().any(|f| match *f {
        FolderFile::Named(n) => n == name,
        FolderFile::PerJoint(stem) => (name.strip_prefix(stem))
            .and_then(|rest| rest.strip_prefix('_'))
            .and_then(|rest| rest.strip_suffix(".csv"))
            .is_some_and(|part| !part.is_empty() && joint_file(stem, part) == name),
    })
}

/// Writes an output folder: [`write_outputs`] with the names its writers write (`FOLDER_FILES`),
/// the only ones it may write or remove. `title` is the command line that makes the folder's
/// outputs (`jointwear run SCENE …`); a folder holding another command's outputs is refused
/// ([`check_command`]), whose files the write would remove or overwrite.
pub fn write_folder<T>(dir: &Path, title: &str, write: impl FnOnce() -> Result<T>) -> Result<T> {
    // Its callers have checked the folder as they claimed it, naming their own option and
    // remedy; this check is for a writer that did not.
    let remedy = "give another folder or move those files away first";
    check_command("output folder", dir, FolderCommand::of(title), remedy)?;
    write_outputs(dir, title, is_folder_file, write)
}

/// Checks the output folder `dir`, given as `option` (`--out`), before `command` runs to write
/// into it: a manifest listing a file that is not an output ([`read_manifest`]), or the
/// outputs of another command ([`check_command`], whose refusal ends with `remedy`), is
/// refused at once (bad input), not after the run; so is a folder holding a sweep file
/// ([`sweep_file_in`]), whose sweep refuses to write beside the manifest this write would
/// leave: a killed sweep's finished cases could no longer be resumed (`run --out <folder of
/// sweep.csv>` did that, exit 0); and, for every command but `run --ensemble`, a folder
/// holding the journal of an unfinished ensemble ([`refuse_journal`]), stranded likewise.
pub fn check_manifest(
    option: &str,
    dir: &Path,
    command: FolderCommand,
    remedy: &str,
) -> Result<()> {
    if let Some(sweep) = sweep_file_in(dir) {
        return Err(Error::invalid(
            option,
            dir.display(),
            format!(
                "a folder without a sweep file: {} is one, which `jointwear sweep` writes and \
                 resumes only in a folder of no other command's outputs (it would refuse it \
                 beside this write's {MANIFEST}, its finished cases then stranded); move that \
                 file to a folder of its own (an unfinished sweep resumes there with \
                 `jointwear sweep ... --resume --out <its new path>`), or give another \
                 {option}",
                sweep.display()
            ),
        ));
    }
    if command != FolderCommand::Ensemble {
        let how = "continue that ensemble with `jointwear run ... --ensemble N --resume`, or \
                   start it over with `jointwear run ... --ensemble N --discard-checkpoint`";
        refuse_journal(option, dir, how)?;
    }
    read_manifest(dir, is_folder_file)?;
    check_command(option, dir, Some(command), remedy)
}

/// What the command line's user can do about an `--out` holding another command's outputs
/// ([`check_command`]'s `remedy`).
pub const OUT_REMEDY: &str = "give another folder (each command's default, out/<scene \
                              stem>/<kind>, is its own) or move those files away first";

/// A command that writes output folders, as the command line at the top of a folder's
/// manifest names it. Each replaces the files of its own previous write into a folder and
/// never another command's: `run` and `longlife` both write `summary.json` and `README.txt`,
/// and a write removes the files of the previous one it does not rewrite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FolderCommand {
    /// `jointwear run` (Python's `Run.save` of a run).
    Run,
    /// `jointwear run --member K` (`Run.save` of a member).
    Member,
    /// `jointwear run --ensemble N` (`Ensemble.save`).
    Ensemble,
    /// `jointwear longlife`.
    LongLife,
}

impl FolderCommand {
    /// The command of the command line `title`, as the writers of folders make it:
    /// `jointwear longlife SCENE …`, or `jointwear run SCENE …` ending in `--ensemble N --seed
    /// S` or `--member K --seed S` (then perhaps `--perturbation P`) for an ensemble or a
    /// member. None for any other line (an edited manifest).
    pub fn of(title: &str) -> Option<FolderCommand> {
        // Read as a shell reads it: a quoted `--set` value may hold `--member 3 --seed 1`.
        // (A line recorded before words were quoted may not close a quote: read word by word.)
        let words = shell_words(title)
            .unwrap_or_else(|| title.split(' ').map(String::from).collect::<Vec<_>>());
        let mut words: Vec<&str> = words.iter().map(String::as_str).collect();
        if words.len() > 2 && words[words.len() - 2] == "--perturbation" {
            words.truncate(words.len() - 2);
        }
        let n = words.len();
        // `--ensemble N --seed S` or `--member K --seed S`, after `jointwear run SCENE`.
        let last_flag = (n >= 7 && words[n - 2] == "--seed").then(|| words[n - 4]);
        match words[..] {
            ["jointwear", "longlife", ..] => Some(FolderCommand::LongLife),
            ["jointwear", "run", ..] => Some(match last_flag {
                Some("--ensemble") => FolderCommand::Ensemble,
                Some("--member") => FolderCommand::Member,
                _ => FolderCommand::Run,
            }),
            _ => None,
        }
    }

    /// The command as it is typed: `run`, `run --member`, `run --ensemble`, `longlife`.
    pub fn name(self) -> &'static str {
        match self {
            FolderCommand::Run => "run",
            FolderCommand::Member => "run --member",
            FolderCommand::Ensemble => "run --ensemble",
            FolderCommand::LongLife => "longlife",
        }
    }
}

/// Refuses (bad input, naming `option` and `dir`, and ending with `remedy`, what the one who
/// gave `dir` can do instead) to write the outputs of `command` into `dir` when its manifest
/// names another command (or none, edited), whose outputs the write would remove or
/// overwrite; a folder without a manifest, or with one of `command`'s own, is accepted.
pub fn check_command(
    option: &str,
    dir: &Path,
    command: Option<FolderCommand>,
    remedy: &str,
) -> Result<()> {
    let Some(title) = manifest_title(dir)? else {
        return Ok(());
    };
    let held = FolderCommand::of(&title);
    if held == command {
        return Ok(());
    }
    let named = |c: Option<FolderCommand>, none: &str| {
        c.map_or(none.to_string(), |c| format!("`jointwear {}`", c.name()))
    };
    Err(Error::invalid(
        option,
        dir.display(),
        format!(
            "a folder holding no other command's outputs (or {}'s own, which it replaces): it \
             holds the outputs of {} (`{title}`, as its {MANIFEST} says), which this write \
             would remove or overwrite; likely cause: the folder of another command given \
             again; {remedy}",
            named(command, "this write"),
            named(held, "an unknown command"),
        ),
    ))
}

/// The machine-readable summary every output folder holds.
pub const SUMMARY_FILE: &str = "summary.json";

/// The description of an output folder's files: units, frames and sign conventions.
pub const README_FILE: &str = "README.txt";

/// What wrote an output folder, as its summary says: `jointwear <version>`.
pub const PROGRAM: &str = concat!("jointwear ", env!("CARGO_PKG_VERSION"));

/// Writes an output folder's [`SUMMARY_FILE`] and [`README_FILE`].
pub fn write_summary(dir: &Path, summary: &impl Serialize, readme: &str) -> Result<()> {
    write_json(&dir.join(SUMMARY_FILE), summary)?;
    write_text(&dir.join(README_FILE), readme)
}

/// At most this many profiles are drawn in one panel of a profile figure (the palette has
/// nine colours); the CSV holds them all.
const MAX_DRAWN_PROFILES: usize = 8;

/// Wear profiles of the worn clearance joints of `m` after several rotation counts:
/// `snapshots` holds `(rotations, depth per joint per sector in m)`, in increasing rotations.
/// Writes per worn joint `<stem>_<joint>.csv` (`angle_deg`, then `rot<N>_m` per count, depth
/// in m) and `png`, one panel per joint (depth in µm; at most `MAX_DRAWN_PROFILES` (8) evenly
/// spread profiles, the last always among them). Writes nothing without snapshots or wear.
pub fn write_profiles(
    dir: &Path,
    stem: &str,
    png: &str,
    m: &Mechanism,
    snapshots: &[(u64, &[Vec<f64>])],
) -> Result<()> {
    let Some((_, first)) = snapshots.first() else {
        return Ok(());
    };
    let worn: Vec<usize> = (0..m.clearance_joints.len())
        .filter(|&k| m.clearance_joints[k].wear.is_some())
        .collect();
    let drawn = drawn_profiles(snapshots.len());
    let mut profiles = Vec::new();
    for &k in &worn {
        let angles = sector_angles_deg(first[k].len());
        let mut header = vec!["angle_deg".to_string()];
        header.extend(snapshots.iter().map(|(n, _)| format!("rot{n}_m")));
        let mut columns: Vec<&[f64]> = vec![&angles];
        columns.extend(snapshots.iter().map(|(_, d)| d[k].as_slice()));
        let header_ref: Vec<&str> = header.iter().map(String::as_str).collect();
        let name = &m.clearance_joints[k].name;
        let path = dir.join(joint_file(stem, name));
        write_csv(&path, &header_ref, &columns)?;
        let um: Vec<(u64, Vec<f64>)> = drawn
            .iter()
            .map(|&i| {
                let (n, d) = &snapshots[i];
                (*n, d[k].iter().map(|x| x * 1e6).collect())
            })
            .collect();
        profiles.push((k, angles, um));
    }
    let shown = if drawn.len() < snapshots.len() {
        format!(" ({} of {} snapshots)", drawn.len(), snapshots.len())
    } else {
        String::new()
    };
    let panels: Vec<Axes> = profiles
        .iter()
        .map(|(k, angles, um)| {
            let series = um
                .iter()
                .map(|(n, d)| Series::new(format!("{n} rotations"), angles, d, Style::Line))
                .collect();
            wear_panel(m, *k, &format!("bearing wear profile{shown}"), series)
        })
        .collect();
    if !panels.is_empty() {
        render(&dir.join(png), &panels)?;
    }
    Ok(())
}

/// Indices of the profiles drawn out of `count`: all of them up to [`MAX_DRAWN_PROFILES`],
/// otherwise that many evenly spread, the last included.
fn drawn_profiles(count: usize) -> Vec<usize> {
    if count <= MAX_DRAWN_PROFILES {
        return (0..count).collect();
    }
    let last = count - 1;
    let mut picked: Vec<usize> = (1..=MAX_DRAWN_PROFILES)
        .map(|i| (i * count).div_ceil(MAX_DRAWN_PROFILES) - 1)
        .collect();
    picked.dedup();
    debug_assert_eq!(picked.last(), Some(&last));
    picked
}

/// The name of body `b` of `m` (`ground` for the ground).
pub fn body_name(m: &Mechanism, b: BodyIndex) -> &str {
    b.map_or("ground", |i| m.bodies()[i].name.as_str())
}

/// The arguments that name an ensemble's perturbation protocol on a command line: none for
/// the default.
pub fn perturbation_arg(p: &Perturbation) -> String {
    if *p == Perturbation::default() {
        String::new()
    } else {
        format!(" --perturbation {}", p.key())
    }
}

/// A panel of clearance joint `k`'s wear profiles `series` (µm) over the angle of its
/// bearing's frame, titled by the joint: each joint is drawn in a panel of its own, since two
/// joints' angles are measured in different bodies' frames.
pub fn wear_panel<'a>(m: &Mechanism, k: usize, title: &str, series: Vec<Series<'a>>) -> Axes<'a> {
    let cj = &m.clearance_joints[k];
    let body = body_name(m, cj.bearing.body);
    Axes {
        x_range: Some((0.0, 360.0)),
        ..Axes::new(
            format!("{}: {title}", cj.name),
            format!("bearing angle (deg, counter-clockwise from {body}'s +x)"),
            "wear depth (µm)",
            series,
        )
    }
}

/// The opening of every `README.txt`: what wrote the folder, then the conventions shared by
/// all its files (units, number format, frames, angles, time).
pub fn conventions(command: &str, m: &Mechanism, title: &str) -> String {
    let driver = body_name(m, Some(m.driver.body));
    let mut text = format!(
        "Outputs of `{command}` ({PROGRAM}): {title}\n\
         jointwear-manifest.txt lists the files of this run; other files in this folder are \
         not from it.\n\
         \n\
         CONVENTIONS\n\
         * Units: SI (m, s, N, Pa, kg), angles in rad, except where a name ends in _deg \
         (degrees). Every column name ends in its unit (_m, _s, _n, _pa, _m_s, _m_s2, _rad, \
         _rad_s2, _deg).\n\
         * Numbers: the shortest decimal text that parses back to the identical IEEE-754 \
         double (0.72, 1500, 1.25e-9); NaN where a value does not exist; `null` in JSON.\n\
         * Global frame: the scene's ground frame (x, y as in the scene file, which gives \
         them in mm; written here in m). Angles are counter-clockwise positive.\n\
         * Bearing frame of a clearance joint: the frame of the body that holds the bearing, \
         turning with it; bearing angles are measured counter-clockwise from its +x axis, in \
         [0, 360) deg. Wear profiles, wear peaks and the contact angle all use it.\n\
         * Time: from the start of the run (t = 0 at the assembled initial pose), settling \
         rotations included. The driven body is `{driver}`.\n\
         * Wear depth: radial depth worn into the bearing (m), >= 0; sector i of N is \
         centred at (i + 0.5) * 360 / N deg.\n\
         \n\
         CLEARANCE JOINTS (journal in bearing)\n"
    );
    for cj in &m.clearance_joints {
        text.push_str(&format!(
            "* {}: journal on `{}`, bearing on `{}` (bearing frame: `{}`), radial clearance \
             {} m{}\n",
            cj.name,
            body_name(m, cj.journal.body),
            body_name(m, cj.bearing.body),
            body_name(m, cj.bearing.body),
            crate::io::output::number(cj.given_clearance),
            if cj.wear.is_some() {
                ""
            } else {
                " (no wear model: no wear files)"
            }
        ));
    }
    text
}

/// The columns of `timeseries.csv`, described for `README.txt`.
pub fn timeseries_columns(m: &Mechanism) -> String {
    let driver = body_name(m, Some(m.driver.body));
    let mut text = format!(
        "  time_s                    time since the start of the run (s)\n\
         \x20 driver_angle_rad          angle of the driven body `{driver}` in the global frame \
         (rad), UNWRAPPED: continuous, it changes by 2*pi per rotation and is not reduced to \
         [0, 2*pi)\n\
         \x20 per clearance joint J:\n\
         \x20 J.ex_m, J.ey_m            eccentricity e = journal centre - bearing centre, \
         components in the GLOBAL frame (m)\n\
         \x20 J.contact_angle_deg       direction of e in the BEARING frame, [0, 360) deg: \
         where the journal is closest to (or presses on) the bearing wall; the angle of the \
         wear profiles (0 when e = 0)\n\
         \x20 J.penetration_m           delta = |e| - c - h(contact angle) (m): POSITIVE in \
         contact (overlap), NEGATIVE in free flight (minus the gap)\n\
         \x20 J.normal_force_n          contact normal force magnitude (N), >= 0, zero in free \
         flight; it pushes the journal along -e/|e|\n\
         \x20 J.friction_force_n        friction force on the journal along the tangent \
         t = (-n_y, n_x), n = e/|e| (t is n turned 90 deg counter-clockwise) (N); its sign \
         is opposite to the sliding velocity's\n\
         \x20 J.sliding_velocity_m_s    v_t = de/dt . t + w_journal R_journal - w_bearing \
         R_bearing (m/s): velocity of the journal surface relative to the bearing surface at \
         the contact point, along t\n\
         \x20 J.pressure_pa             peak contact pressure (Pa) of the joint's pressure \
         model; 0 out of contact or without a wear model\n\
         \x20 J.wear_rate_m_s           Archard wear rate dh/dt at the contact centre, \
         k/H * pressure * |v_t| (m/s); 0 without a wear model\n\
         \x20 per body B (moving bodies: {}):\n\
         \x20 B.ax_m_s2, B.ay_m_s2      acceleration of the centre of mass, GLOBAL frame (m/s2)\n\
         \x20 B.alpha_rad_s2            angular acceleration, counter-clockwise positive \
         (rad/s2)\n",
        m.bodies()
            .iter()
            .map(|b| b.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names a rerun may remove are the writers' alone. Would fail with any name a
    /// manifest lists taken (the user's notes, a scene, the checkpoint, the lock, a dot-file).
    #[test]
    fn folder_files_are_the_writers_names_only() {
        for name in [
            "timeseries.csv",
            "wear_rod-slider.csv",
            "wear_snapshots_crank_1.csv",
            "ensemble_wear_j.csv",
            "longlife_profiles_j.csv",
            "summary.json",
            "README.txt",
        ] {
            assert!(is_folder_file(name), "{name}");
        }
        for name in [
            "notes.txt",
            "myscene.toml",
            crate::simulation::checkpoint::CHECKPOINT_FILE,
            crate::io::lock::FOLDER_LOCK,
            crate::io::output::MANIFEST,
            ".timeseries.tmp-1-0.csv",
            "wear_.csv",
            "wear_a b.csv",
            "wear_a.png",
            "../timeseries.csv",
        ] {
            assert!(!is_folder_file(name), "{name}");
        }
    }

    /// Would fail on an off-by-one pick (the last profile left out) or on more profiles than
    /// the palette has colours.
    #[test]
    fn drawn_profiles_are_spread_and_keep_the_last() {
        assert_eq!(drawn_profiles(3), [0, 1, 2]);
        assert_eq!(drawn_profiles(8), (0..8).collect::<Vec<_>>());
        for count in 9..200 {
            let d = drawn_profiles(count);
            assert_eq!(d.len(), MAX_DRAWN_PROFILES, "{count}");
            assert_eq!(*d.last().unwrap(), count - 1);
            assert!(d.windows(2).all(|w| w[0] < w[1]));
        }
        assert_eq!(drawn_profiles(40), [4, 9, 14, 19, 24, 29, 34, 39]);
    }

    /// The command of each writer's command line, whatever its `--set` values say; and
    /// `write_folder` (Python's `save` writes through it) refuses a folder of another
    /// command's outputs, removing nothing, while a write of the same command replaces its
    /// own. Fails without the check: the `run` write removed the longlife's growth file.
    #[test]
    fn a_folder_of_another_commands_outputs_is_refused() {
        use FolderCommand::*;
        for (title, command) in [
            ("jointwear run a.toml", Some(Run)),
            (
                "jointwear run a.toml --set title=--member --rotations 3",
                Some(Run),
            ),
            ("jointwear run a b.toml --member 3 --seed 1", Some(Member)),
            // Fails without reading the words as a shell does: a run whose quoted title ends
            // in `--member 3 --seed 1` was a member's folder, which its own rerun was refused.
            (
                r#"jointwear run a.toml --set 'title="x --member 3 --seed 1"'"#,
                Some(Run),
            ),
            (
                r#"jointwear run a.toml --set title="x --ensemble 3 --seed 1""#,
                Some(Run),
            ),
            ("jointwear run 'a b.toml' --member 3 --seed 1", Some(Member)),
            (
                "jointwear run a.toml --set title=it's --member 3 --seed 1",
                Some(Member),
            ),
            ("jointwear run a.toml --ensemble 8 --seed 2", Some(Ensemble)),
            (
                "jointwear run a.toml --member 3 --seed 1 --perturbation axis_10nm",
                Some(Member),
            ),
            (
                "jointwear run a.toml --ensemble 8 --seed 2 --perturbation disc_1nm",
                Some(Ensemble),
            ),
            (
                "jointwear longlife a.toml --rotations 5 --member 1 --seed 2",
                Some(LongLife),
            ),
            ("edited", None),
        ] {
            assert_eq!(FolderCommand::of(title), command, "{title}");
        }
        let dir = std::env::temp_dir().join(format!("jointwear-command-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let write = |title: &str, name: &str| {
            write_folder(&dir, title, || write_text(&dir.join(name), name))
        };
        write("jointwear longlife a.toml --rotations 5", GROWTH_FILE).unwrap();
        write("jointwear longlife a.toml --rotations 6", GROWTH_FILE).unwrap();
        let e = write("jointwear run a.toml", TIMESERIES_FILE).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, Error::Invalid { .. }), "{text}");
        assert!(
            text.contains("`jointwear longlife a.toml --rotations 6`"),
            "{text}"
        );
        assert!(dir.join(GROWTH_FILE).exists() && !dir.join(TIMESERIES_FILE).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
