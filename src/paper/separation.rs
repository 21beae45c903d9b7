//! How fast two members of an ensemble separate, and so whether members could share a
//! settling phase.
//!
//! Members differ only by their initial journal offsets (at most 10 nm, [`member_state`]). For
//! every Table 3 case, members 0 and 1 of the default seed run [`SEPARATION_ROTATIONS`]
//! rotations from their assembled starts, recorded on the same time grid; per rotation the
//! study takes the RMS distance between their journal centres (relative to the bearing) over
//! the radial clearance:
//!
//! ```text
//! s_r = sqrt(mean over rotation r of |e₀(t) − e₁(t)|²) / c
//! ```
//!
//! Sharing a settling phase (settle once, perturb the settled state per member, record) would
//! be an ensemble of the same thing only if a perturbation of that size grows to the members'
//! spread before the recorded rotations; the rotations it takes are what such a scheme would
//! have to run per member after the perturbation. Writes `data/member_separation.csv`; the
//! report's section 2 reads it.

use crate::io::output::{read_csv, write_csv};
use crate::io::progress::Silent;
use crate::paper::cases::CASES;
use crate::paper::figures::output_path;
use crate::scene::{scene_path, SceneFile};
use crate::simulation::ensemble::{member_state, DEFAULT_SEED};
use crate::simulation::Simulation;
use crate::Result;
use rayon::prelude::*;

/// Rotations each pair of members runs.
pub const SEPARATION_ROTATIONS: u32 = 12;

/// Recorded samples per rotation.
const SAMPLES_PER_ROTATION: f64 = 720.0;

/// File of the study under `data/`.
pub const SEPARATION_FILE: &str = "member_separation.csv";

/// The separation of members 0 and 1 of one case, per rotation.
#[derive(Clone, Debug, PartialEq)]
pub struct Separation {
    /// Case scene.
    pub case: String,
    /// `s_r` of rotations 1, 2, … (see the module documentation).
    pub per_rotation: Vec<f64>,
}

impl Separation {
    /// The first rotation (1-based) whose separation reaches `level` of the clearance.
    pub fn first_reaching(&self, level: f64) -> Option<usize> {
        self.per_rotation
            .iter()
            .position(|s| *s >= level)
            .map(|i| i + 1)
    }
}

/// One case: members 0 and 1 run and compared.
fn separation(case: &'static str) -> Result<Separation> {
    let mut file = SceneFile::read(scene_path(case))?;
    file.run.rotations = SEPARATION_ROTATIONS;
    file.run.record_rotations = SEPARATION_ROTATIONS;
    file.run.record_interval_s = 60.0 / file.driver.speed_rpm.abs() / SAMPLES_PER_ROTATION;
    file.run.wear_snapshots.clear();
    let scene = file.build()?;
    let runs = [0, 1].map(|member| -> Result<_> {
        let y0 = member_state(&scene, DEFAULT_SEED, member)?;
        let mut sim = Simulation::new(scene.mechanism.clone(), scene.run.clone(), &y0)?;
        sim.run_to_end(&Silent)?;
        Ok(sim.finish().recording)
    });
    let [a, b] = runs;
    let (a, b) = (a?, b?);
    let (ja, jb) = (&a.joints[0], &b.joints[0]);
    let samples = ja.ex.len().min(jb.ex.len());
    let per = samples / SEPARATION_ROTATIONS as usize;
    let c = scene.mechanism.clearance_joints[0].clearance();
    let per_rotation = (0..SEPARATION_ROTATIONS as usize)
        .map(|r| {
            let sum: f64 = (r * per..(r + 1) * per)
                .map(|i| (ja.ex[i] - jb.ex[i]).powi(2) + (ja.ey[i] - jb.ey[i]).powi(2))
                .sum();
            (sum / per as f64).sqrt() / c
        })
        .collect();
    Ok(Separation {
        case: case.to_string(),
        per_rotation,
    })
}

/// Runs the study for every Table 3 case (in parallel) and writes its CSV: one column per
/// case, one row per rotation.
pub fn separation_study() -> Result<Vec<Separation>> {
    let cases: Vec<&'static str> = CASES.list().iter().map(|c| c.scene).collect();
    let study = cases
        .par_iter()
        .map(|c| separation(c))
        .collect::<Result<Vec<_>>>()?;
    let rotations: Vec<f64> = (1..=SEPARATION_ROTATIONS).map(f64::from).collect();
    let mut header = vec!["rotation"];
    header.extend(cases.iter().copied());
    let mut columns: Vec<&[f64]> = vec![&rotations];
    columns.extend(study.iter().map(|s| s.per_rotation.as_slice()));
    write_csv(&output_path("data", SEPARATION_FILE), &header, &columns)?;
    Ok(study)
}

/// The separations an earlier run of the study wrote; `None` if the file is missing.
pub fn read_separation() -> Option<Vec<Separation>> {
    let (header, columns) = read_csv(&output_path("data", SEPARATION_FILE)).ok()?;
    let cases = header.iter().zip(&columns).skip(1);
    Some(
        cases
            .map(|(case, column)| Separation {
                case: case.clone(),
                per_rotation: column.clone(),
            })
            .collect(),
    )
}
