//! Checkpoint files of long runs: a run can save its whole state between rotations and a later
//! process continue it, bit for bit the same as a run that was never interrupted.
//!
//! The file (`checkpoint.json` in the run's output folder) holds the scene's fingerprint (the
//! resolved scene document, as sweeps fingerprint theirs) and the [`Checkpoint`]; a checkpoint
//! of another scene, or of the same scene edited since, is refused. Floats are written in the
//! shortest form that parses back to the same bits. Files are written atomically, so a run
//! killed while writing keeps its previous checkpoint.

use super::record::{Sampler, Settler};
use super::RunOutput;
use crate::io::output::write_atomic;
use crate::ode::IntegratorState;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Everything a run carries from one rotation to the next: resuming from it continues the
/// run bit for bit ([`super::Simulation::checkpoint`], [`super::Simulation::resume`]).
#[derive(Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Rotations completed.
    pub(super) rotation: u32,
    pub(super) end_rotation: Option<u32>,
    pub(super) integrator: IntegratorState,
    pub(super) gaps: Vec<f64>,
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

/// File name of a run's checkpoint in its output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";

#[derive(Serialize, Deserialize)]
struct CheckpointFile {
    scene_fingerprint: String,
    checkpoint: Checkpoint,
}

/// Writes `checkpoint` of the scene with `fingerprint` to `path`, atomically.
pub fn write_checkpoint(path: &Path, fingerprint: &str, checkpoint: Checkpoint) -> Result<()> {
    let file = CheckpointFile {
        scene_fingerprint: fingerprint.to_string(),
        checkpoint,
    };
    write_atomic(path, |tmp| {
        let w =
            std::io::BufWriter::new(std::fs::File::create(tmp).map_err(|source| Error::Io {
                path: tmp.to_path_buf(),
                source,
            })?);
        serde_json::to_writer(w, &file).map_err(|e| Error::Parse {
            path: tmp.to_path_buf(),
            message: e.to_string(),
        })
    })
}

/// Reads the checkpoint at `path`, which must be of the scene with `fingerprint`.
pub fn read_checkpoint(path: &Path, fingerprint: &str) -> Result<Checkpoint> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let file: CheckpointFile = serde_json::from_str(&text).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
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
    Ok(file.checkpoint)
}
