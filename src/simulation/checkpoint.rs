//! Checkpoint files of long runs: a run can save its whole state between rotations and a later
//! process continue it, bit for bit the same as a run that was never interrupted.
//!
//! The file (`checkpoint.json` in the run's output folder) holds the scene's fingerprint (the
//! resolved scene document, as sweeps fingerprint theirs), the [`Checkpoint`] and the checksum
//! of both; a checkpoint of another scene, or of the same scene edited since, is refused, and
//! so is one whose fingerprint and content do not match its checksum (edited or damaged: a
//! fingerprint edited to the scene's would resume another scene's run as this one's). [`super::Simulation::resume`]
//! then checks every field against the scene. Floats are written in the shortest form that
//! parses back to the same bits. Files are written atomically, so a run killed while writing
//! keeps its previous checkpoint.
//!
//! The checksum is the 64-bit FNV-1a hash ([`fnv1a`]), as 16 hex digits, of the scene's
//! fingerprint, the character U+001F and the checkpoint written as compact JSON with the keys
//! of every object in sorted order (`serde_json`'s `Value` as it prints).

use super::record::{Sampler, Settler};
use super::RunOutput;
use crate::io::output::{fnv1a, read_bounded_text, write_atomic, write_json_file};
use crate::ode::IntegratorState;
use crate::scene::RECORD_BUDGET_BYTES;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Everything a run carries from one rotation to the next: resuming from it continues the
/// run bit for bit ([`super::Simulation::checkpoint`], [`super::Simulation::resume`]).
#[derive(Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// The [`ARITHMETIC`] of the program that wrote it.
    pub(super) arithmetic: u32,
    /// Rotations completed.
    pub(super) rotation: u32,
    pub(super) end_rotation: Option<u32>,
    pub(super) integrator: IntegratorState,
    /// Penetration of each joint at the last step's end (m).
    pub(super) gaps: Vec<f64>,
    /// Their rates there (m/s): where a gap's rate changes sign within a step, an onset is
    /// searched around its extremum ([`crate::ode`]'s events).
    pub(super) gap_rates: Vec<f64>,
    /// Wear depth per joint per sector (m).
    pub(super) profiles: Vec<Vec<f64>>,
    /// Onset velocity of each joint's current contact (m/s).
    pub(super) impact_velocities: Vec<f64>,
    pub(super) settler: Option<Settler>,
    pub(super) sampler: Option<Sampler>,
    /// `None` without a wear history (JSON has no infinity).
    pub(super) next_history: Option<f64>,
    pub(super) energy_start: Option<(f64, f64)>,
    /// The outputs so far; `wall_time` is the wall time spent so far.
    pub(super) out: RunOutput,
}

/// The version of what a run computes from its steps. A change that moves runs by rounding
/// alone (2: the right-hand side's shorter dependency chains of 2026-11-27), or what a run
/// accumulates over them (3: the whole run's largest penetration taken at peaks inside steps
/// too), raises it, so that a checkpoint written before is refused rather than continued under
/// other rules, which would match neither program's uninterrupted run.
pub const ARITHMETIC: u32 = 3;

/// File name of a run's checkpoint in its output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

/// Refuses (bad input, naming `option` and `dir`) an output folder `dir` that holds the
/// checkpoint of an unfinished run, which a write of outputs would overwrite or leave beside
/// them (a later `--resume` would replace them); `how` says what the user can do about that
/// run besides choosing another `option`.
pub fn refuse_checkpoint(option: &str, dir: &Path, how: &str) -> Result<()> {
    refuse_unfinished(
        option,
        dir,
        CHECKPOINT_FILE,
        "the checkpoint of an unfinished run",
        how,
    )
}

/// Refuses (bad input, naming `option` and `dir`) an output folder `dir` in which `name`
/// exists: the saved state (`what`) of an unfinished job that the folder's next outputs would
/// strand; `how` says what the user can do about that job besides choosing another `option`.
pub(crate) fn refuse_unfinished(
    option: &str,
    dir: &Path,
    name: &str,
    what: &str,
    how: &str,
) -> Result<()> {
    let saved = dir.join(name);
    if !saved.exists() {
        return Ok(());
    }
    Err(Error::invalid(
        option,
        dir.display(),
        format!(
            "a folder without {what}: there is one at {}; {how}, or choose another {option}",
            saved.display()
        ),
    ))
}

#[derive(Serialize, Deserialize)]
struct CheckpointFile {
    scene_fingerprint: String,
    /// [`checksum`] of `scene_fingerprint` and `checkpoint`.
    checksum: String,
    checkpoint: serde_json::Value,
}

/// The checksum of a saved state `body` (JSON) of what `head` says it is of: the 64-bit FNV-1a
/// hash, as 16 hex digits, of `head`, U+001F and `body` as compact JSON. A checkpoint's head is
/// its scene's fingerprint (see the module documentation), an ensemble journal entry's its
/// binding as compact JSON (`crate::simulation::journal`).
pub(crate) fn checksum(head: &str, body: &serde_json::Value) -> String {
    let mut text = format!("{head}\u{1f}").into_bytes();
    // (Written into memory, once: a checkpoint may hold a long recording. It cannot fail.)
    let _ = serde_json::to_writer(&mut text, body);
    format!("{:016x}", fnv1a(&text))
}

/// Writes `checkpoint` of the scene with `fingerprint` to `path`, atomically.
pub fn write_checkpoint(path: &Path, fingerprint: &str, checkpoint: Checkpoint) -> Result<()> {
    let checkpoint = serde_json::to_value(checkpoint).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: format!("the checkpoint cannot be written as JSON: {e}"),
    })?;
    let file = CheckpointFile {
        scene_fingerprint: fingerprint.to_string(),
        checksum: checksum(fingerprint, &checkpoint),
        checkpoint,
    };
    write_atomic(path, |tmp| write_json_file(tmp, &file))
}

/// Largest checkpoint file read back (bytes): the record budget's `f64`s
/// ([`RECORD_BUDGET_BYTES`]) as JSON text, at most about 25 bytes of text each, with room for
/// the rest. It bounds what a wrong file makes `--resume` read.
pub const MAX_CHECKPOINT_BYTES: u64 = (RECORD_BUDGET_BYTES as u64 / 8) * 32;

/// Reads the checkpoint at `path`, which must be a regular file of at most
/// [`MAX_CHECKPOINT_BYTES`] (a FIFO or device named like it made `--resume` wait or read
/// without end), of the scene with `fingerprint`, and match its checksum.
pub fn read_checkpoint(path: &Path, fingerprint: &str) -> Result<Checkpoint> {
    let text = read_bounded_text(
        path,
        MAX_CHECKPOINT_BYTES,
        "a checkpoint",
        "the record budget's numbers as JSON text",
    )?;
    let parse = |e: serde_json::Error| Error::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let file: CheckpointFile = serde_json::from_str(&text).map_err(parse)?;
    // The one field an earlier version did not write, named with its remedy rather than left
    // to the parser's "missing field".
    if file.checkpoint.get("gap_rates").is_none() {
        return Err(Error::invalid(
            "checkpoint.gap_rates",
            format!("(absent from {})", path.display()),
            "the gaps' rates, which this version keeps to locate contact onsets inside a step: the \
             checkpoint was written by an earlier version, whose run this one would not continue \
             bit for bit (start over with --discard-checkpoint)",
        ));
    }
    let arithmetic = file.checkpoint.get("arithmetic");
    if arithmetic != Some(&ARITHMETIC.into()) {
        return Err(Error::invalid(
            "checkpoint.arithmetic",
            arithmetic.map_or_else(
                || format!("(absent from {})", path.display()),
                |a| a.to_string(),
            ),
            format!(
                "{ARITHMETIC}, the version of this program's floating-point operations: the \
                 checkpoint was written by a version whose run this one would not continue bit \
                 for bit (start over with --discard-checkpoint)"
            ),
        ));
    }
    let sum = checksum(&file.scene_fingerprint, &file.checkpoint);
    // (The checksum of the checkpoint alone, as versions before 2026-11-28 wrote it: such a
    // file cannot vouch for its fingerprint, and is refused, saying so.)
    let earlier = format!("{:016x}", fnv1a(file.checkpoint.to_string().as_bytes()));
    if file.checksum != sum && file.checksum == earlier {
        return Err(Error::invalid(
            format!("checksum (of {})", path.display()),
            &file.checksum,
            format!(
                "{sum}, the checksum of the scene fingerprint and checkpoint the file holds: \
                 the checkpoint was written by an earlier version (before 2026-11-28), whose \
                 checksum left the fingerprint out, so that this one cannot tell the run is \
                 this scene's (finish it with the version that wrote it, or start over with \
                 --discard-checkpoint)"
            ),
        ));
    }
    if file.checksum != sum {
        return Err(Error::invalid(
            format!("checksum (of {})", path.display()),
            &file.checksum,
            format!(
                "{sum}, the checksum of the scene fingerprint and checkpoint the file holds: it \
                 was edited or damaged since it was written (start over with \
                 --discard-checkpoint)"
            ),
        ));
    }
    if file.scene_fingerprint != fingerprint {
        return Err(Error::invalid(
            "--resume",
            format!(
                "{} (scene fingerprint {})",
                path.display(),
                file.scene_fingerprint
            ),
            format!(
                "a checkpoint of this scene as it is now, with the same --set and --rotations \
                 values (fingerprint {fingerprint}): the scene was edited since, the run was \
                 started with other --set/--rotations values, or the checkpoint is another \
                 scene's"
            ),
        ));
    }
    serde_json::from_value(file.checkpoint).map_err(parse)
}
