//! The journal of an ensemble written into an output folder: each member's results saved as
//! it finishes, so that an ensemble killed or interrupted part-way loses no finished member
//! and `run --ensemble N --resume` runs only the others, its outputs those of an ensemble that
//! never stopped (wall times aside).
//!
//! The journal is the folder `ensemble_journal/` ([`JOURNAL_DIR`]) of the ensemble's output
//! folder, with one file `member-<k>.json` per finished member, written atomically: a member
//! killed while its entry is written leaves no entry (its hidden temporary is ignored, and
//! removed with the journal). An entry holds what it is of ([`JOURNAL_FORMAT`], the program's
//! [`ARITHMETIC`], the scene's fingerprint, the ensemble's member count, seed and protocol, and
//! the member's number), the member's joint summaries, final wear profiles and wall time, and
//! the checksum of both, a checkpoint's: the 64-bit FNV-1a hash, as 16 hex digits, of the two
//! as compact JSON (keys sorted, `serde_json`'s `Value` as it prints) joined by U+001F. An entry
//! is read back only if its checksum matches, it is of this scene and ensemble, and its
//! results fit the scene (joints, sectors, finite values in range); otherwise the resumption
//! is refused naming the file and the field, never trusted. The ensemble removes its journal
//! when it has written its outputs.

use super::checkpoint::{checksum, refuse_unfinished, ARITHMETIC};
use super::ensemble::{EnsembleSettings, MAX_MEMBERS};
use super::summary::JointSummary;
use super::Scene;
use crate::io::output::{create_dir_synced, read_bounded_text, write_atomic, write_json_file};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Name of the journal folder in an ensemble's output folder.
pub const JOURNAL_DIR: &str = "ensemble_journal";

/// The version of the journal's entries: one of another version is refused, not read.
pub const JOURNAL_FORMAT: u32 = 1;

/// What the command line says to do with a journal it cannot continue.
const START_OVER: &str = "start the ensemble over with --discard-checkpoint";

/// One finished member's results, as the ensemble's outputs are built from them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MemberResult {
    /// Its summary per clearance joint.
    pub joints: Vec<JointSummary>,
    /// Its final wear profile per clearance joint, per sector (m).
    pub final_wear: Vec<Vec<f64>>,
    /// Its wall time (s).
    pub wall_time_s: f64,
}

/// What an entry is of: the ensemble, the scene and the member.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Binding {
    format: u32,
    arithmetic: u32,
    fingerprint: String,
    members: usize,
    seed: u64,
    perturbation: String,
    member: usize,
}

/// An entry's file.
#[derive(Serialize, Deserialize)]
struct Entry {
    of: serde_json::Value,
    checksum: String,
    result: serde_json::Value,
}

/// The journal of an ensemble of a scene, in an output folder.
pub struct Journal {
    dir: PathBuf,
    fingerprint: String,
    settings: EnsembleSettings,
}

impl Journal {
    /// The journal of the ensemble `settings` of the scene with `fingerprint` in the output
    /// folder `folder` (nothing is read or written yet).
    pub fn new(folder: &Path, fingerprint: &str, settings: &EnsembleSettings) -> Journal {
        Journal {
            dir: folder.join(JOURNAL_DIR),
            fingerprint: fingerprint.to_string(),
            settings: *settings,
        }
    }

    /// The journal's folder.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Whether the folder holds a journal (of any ensemble).
    pub fn exists(&self) -> bool {
        self.dir.exists()
    }

    /// What the entry of `member` is of.
    fn binding(&self, member: usize) -> Binding {
        Binding {
            format: JOURNAL_FORMAT,
            arithmetic: ARITHMETIC,
            fingerprint: self.fingerprint.clone(),
            members: self.settings.members,
            seed: self.settings.seed,
            perturbation: self.settings.perturbation.key(),
            member,
        }
    }

    /// The file of `member`'s entry.
    fn entry_path(&self, member: usize) -> PathBuf {
        self.dir.join(format!("member-{member}.json"))
    }

    /// Saves the results of `member`, atomically. The journal's folder appears with its first
    /// entry: an ensemble that fails before any member finished (a scene that every member
    /// refuses, say) leaves no journal, which would hold nothing to resume and refuse the
    /// folder to the next command.
    pub fn record(&self, member: usize, result: &MemberResult) -> Result<()> {
        let path = self.entry_path(member);
        create_dir_synced(&self.dir)?;
        let json = |e: serde_json::Error| Error::Parse {
            path: path.clone(),
            message: format!("the member's results cannot be written as JSON: {e}"),
        };
        let of = serde_json::to_value(self.binding(member)).map_err(json)?;
        let result = serde_json::to_value(result).map_err(json)?;
        let entry = Entry {
            checksum: checksum(&of.to_string(), &result),
            of,
            result,
        };
        write_atomic(&path, |tmp| write_json_file(tmp, &entry))
    }

    /// Removes the journal (the ensemble has written its outputs).
    pub fn remove(&self) -> Result<()> {
        std::fs::remove_dir_all(&self.dir).map_err(|source| Error::Io {
            path: self.dir.clone(),
            source,
        })
    }

    /// The members of the journal, each finished one's results (None for the others), read
    /// back and checked against this ensemble of `scene`: an entry cut short, edited, of
    /// another scene or ensemble, of another version, or whose results do not fit the scene
    /// is refused (bad input naming the file and the field), as is a file of the journal
    /// that is no entry.
    pub fn read(&self, scene: &Scene) -> Result<Vec<Option<MemberResult>>> {
        let io = |source| Error::Io {
            path: self.dir.clone(),
            source,
        };
        let mut members = vec![None; self.settings.members];
        for e in std::fs::read_dir(&self.dir).map_err(io)? {
            let e = e.map_err(io)?;
            let name = e.file_name().to_string_lossy().into_owned();
            // A hidden temporary of an entry whose writer was killed: no entry.
            if name.starts_with('.') {
                continue;
            }
            let member = (name.strip_prefix("member-"))
                .and_then(|n| n.strip_suffix(".json"))
                // Digits only, as written: `usize::from_str` also takes a leading `+`, which
                // read `member-+1.json` as member 1 and then opened `member-1.json`.
                .filter(|n| n.bytes().all(|b| b.is_ascii_digit()))
                .filter(|n| !n.starts_with('0') || *n == "0")
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|&k| k < MAX_MEMBERS);
            let Some(member) = member else {
                return Err(Error::invalid(
                    format!("file of {}", self.dir.display()),
                    name,
                    format!(
                        "an entry of the ensemble's journal, member-<k>.json: the journal holds \
                         a file it did not write (move it away, or {START_OVER})"
                    ),
                ));
            };
            if member >= self.settings.members {
                return Err(mismatch(
                    &self.entry_path(member),
                    "--ensemble",
                    format!("an ensemble with member {member}"),
                    format!(
                        "{} members, as this run: the journal is of an ensemble with more \
                         members (resume it with its own --ensemble N, or {START_OVER})",
                        self.settings.members
                    ),
                ));
            }
            members[member] = Some(self.read_entry(scene, member)?);
        }
        Ok(members)
    }

    /// The entry of `member`, checked (see [`Journal::read`]).
    fn read_entry(&self, scene: &Scene, member: usize) -> Result<MemberResult> {
        let path = self.entry_path(member);
        let text = read_bounded_text(
            &path,
            max_entry_bytes(scene),
            "an entry of an ensemble's journal",
            "a member's summaries and final wear profiles as JSON text",
        )?;
        let damaged = |message: String| Error::Parse {
            path: path.clone(),
            message: format!(
                "{message}: the entry is cut short, edited or not this program's ({START_OVER})"
            ),
        };
        let entry: Entry = serde_json::from_str(&text).map_err(|e| damaged(e.to_string()))?;
        let format = entry.of.get("format");
        if format != Some(&JOURNAL_FORMAT.into()) {
            return Err(mismatch(
                &path,
                "format",
                format.map_or("(absent)".to_string(), |f| f.to_string()),
                format!(
                    "{JOURNAL_FORMAT}, the version of the journal this program writes: the \
                     entry was written by another version ({START_OVER}, or resume it with the \
                     version that wrote it)"
                ),
            ));
        }
        let sum = checksum(&entry.of.to_string(), &entry.result);
        if entry.checksum != sum {
            return Err(mismatch(
                &path,
                "checksum",
                &entry.checksum,
                format!(
                    "{sum}, the checksum of what the entry holds: it was edited or damaged \
                     since it was written ({START_OVER})"
                ),
            ));
        }
        let of: Binding =
            serde_json::from_value(entry.of).map_err(|e| damaged(format!("`of`: {e}")))?;
        self.check_binding(&path, &of, member)?;
        let result: MemberResult =
            serde_json::from_value(entry.result).map_err(|e| damaged(format!("`result`: {e}")))?;
        check_result(scene, &result).map_err(|(field, value, expected)| {
            mismatch(&path, &format!("result.{field}"), value, expected)
        })?;
        Ok(result)
    }

    /// Refuses an entry at `path` of another ensemble, scene, arithmetic or member than
    /// `member` of this one.
    fn check_binding(&self, path: &Path, of: &Binding, member: usize) -> Result<()> {
        let want = self.binding(member);
        let again = "resume with the --ensemble, --seed and --perturbation it was started \
                     with, the scene and its --set and --rotations as they were";
        let checks: [(&str, String, String, String); 6] = [
            (
                "arithmetic",
                of.arithmetic.to_string(),
                want.arithmetic.to_string(),
                format!(
                    "this program's floating-point operations: the member was run by a version \
                     whose runs differ by rounding ({START_OVER})"
                ),
            ),
            (
                "fingerprint",
                of.fingerprint.clone(),
                want.fingerprint.clone(),
                format!(
                    "the scene with this run's --set and --rotations values: the scene was \
                     edited since, or run with other values ({again}, or {START_OVER})"
                ),
            ),
            (
                "--ensemble",
                of.members.to_string(),
                want.members.to_string(),
                format!("this run's member count ({again}, or {START_OVER})"),
            ),
            (
                "--seed",
                of.seed.to_string(),
                want.seed.to_string(),
                format!("this run's seed ({again}, or {START_OVER})"),
            ),
            (
                "--perturbation",
                of.perturbation.clone(),
                want.perturbation.clone(),
                format!("this run's protocol ({again}, or {START_OVER})"),
            ),
            (
                "member",
                of.member.to_string(),
                want.member.to_string(),
                format!("the member its file name gives: the entry was renamed ({START_OVER})"),
            ),
        ];
        match checks.into_iter().find(|(_, is, should, _)| is != should) {
            None => Ok(()),
            Some((field, is, should, why)) => {
                Err(mismatch(path, field, is, format!("{should}, {why}")))
            }
        }
    }
}

/// A refusal of the entry at `path` whose `field` holds `value` where the ensemble resumed
/// expects what `expected` says.
fn mismatch(path: &Path, field: &str, value: impl std::fmt::Display, expected: String) -> Error {
    Error::invalid(format!("{field} (of {})", path.display()), value, expected)
}

/// Largest entry read back for `scene` (bytes): per clearance joint its name, a summary of a
/// few numbers and of at most one wear region per sector, and its profile, at most 25 bytes
/// of text a number and 32 with a key; twice that, and 64 KiB of room. It bounds what a wrong
/// file makes `--resume` read.
fn max_entry_bytes(scene: &Scene) -> u64 {
    let joints = &scene.mechanism.clearance_joints;
    let per_joint = |sectors: usize, name: usize| (2 * name + 4096 + 7 * 32 * sectors) as u64;
    let all: u64 = joints
        .iter()
        .map(|cj| per_joint(cj.initial_profile.depths().len(), cj.name.len()))
        .sum();
    2 * all + 65536
}

/// Why `result` cannot be a member's of `scene`, if it cannot: the field, its value and what
/// it must be.
fn check_result(
    scene: &Scene,
    result: &MemberResult,
) -> std::result::Result<(), (String, String, String)> {
    let joints = &scene.mechanism.clearance_joints;
    let names: Vec<&str> = joints.iter().map(|cj| cj.name.as_str()).collect();
    let had: Vec<&str> = result.joints.iter().map(|j| j.name.as_str()).collect();
    if had != names || result.final_wear.len() != joints.len() {
        return Err((
            "joints".into(),
            format!("{had:?} with {} profiles", result.final_wear.len()),
            format!("the scene's clearance joints {names:?}, one profile each"),
        ));
    }
    let settles = scene.run.settle.is_some();
    for (k, (cj, (summary, wear))) in joints
        .iter()
        .zip(result.joints.iter().zip(&result.final_wear))
        .enumerate()
    {
        let sectors = cj.initial_profile.depths().len();
        if wear.len() != sectors {
            return Err((
                format!("final_wear[{k}]"),
                format!("{} sectors", wear.len()),
                format!("the {sectors} sectors of joint `{}`", cj.name),
            ));
        }
        if let Some((i, d)) = wear
            .iter()
            .enumerate()
            .find(|(_, d)| !(d.is_finite() && **d >= 0.0))
        {
            return Err((
                format!("final_wear[{k}][{i}]"),
                d.to_string(),
                "a finite wear depth of at least 0 m".into(),
            ));
        }
        if summary.settled.is_some() != settles {
            return Err((
                format!("joints[{k}].settled"),
                format!("{:?}", summary.settled),
                format!(
                    "{} for this scene, which {}",
                    if settles { "true or false" } else { "null" },
                    if settles {
                        "settles"
                    } else {
                        "does not settle"
                    }
                ),
            ));
        }
        if !settles && summary.rotations_simulated != scene.run.rotations {
            return Err((
                format!("joints[{k}].rotations_simulated"),
                summary.rotations_simulated.to_string(),
                format!("{}, the scene's run.rotations", scene.run.rotations),
            ));
        }
    }
    if !(result.wall_time_s.is_finite() && result.wall_time_s >= 0.0) {
        return Err((
            "wall_time_s".into(),
            result.wall_time_s.to_string(),
            "a finite wall time of at least 0 s".into(),
        ));
    }
    Ok(())
}

/// Refuses (bad input, naming `option` and `dir`) an output folder `dir` that holds the
/// journal of an unfinished ensemble, which a write of another command's outputs would leave
/// stranded (its `--resume` then refused as into another command's folder); `how` says what
/// the user can do about that ensemble besides choosing another `option`.
pub fn refuse_journal(option: &str, dir: &Path, how: &str) -> Result<()> {
    refuse_unfinished(
        option,
        dir,
        JOURNAL_DIR,
        "the journal of an unfinished ensemble",
        how,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file whose name is an entry's but for a sign, `member-+1.json`, is no entry: refused
    /// naming it. Would fail with `+1` read as member 1 and the refusal naming
    /// `member-1.json`, which does not exist ("No such file or directory").
    #[test]
    fn a_file_named_as_an_entry_with_a_sign_is_refused_naming_it() {
        let scene = Scene::load(crate::scene::scene_path("standard")).unwrap();
        let dir = std::env::temp_dir().join(format!("jointwear-journal-{}", std::process::id()));
        let settings = EnsembleSettings {
            members: 2,
            ..EnsembleSettings::default()
        };
        let journal = Journal::new(&dir, "f", &settings);
        std::fs::create_dir_all(journal.path()).unwrap();
        std::fs::write(journal.path().join("member-+1.json"), "{}").unwrap();
        let e = journal.read(&scene).unwrap_err().to_string();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(
            e.contains("member-+1.json") && e.contains("did not write"),
            "{e}"
        );
    }
}
