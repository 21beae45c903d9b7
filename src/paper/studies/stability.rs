//! The stability study: whether stiff and extreme cases run to completion (section 6 of
//! `paper.md`).
//!
//! Each scene of `data/scenes/stability/` varies one physical value of the standard scene to an
//! extreme. It runs [`STABILITY_ROTATIONS`] rotations (tests: one) with energy accounting and
//! a step guard of [`STABILITY_MAX_STEPS`], at the scene's own integration settings. Reported:
//! completion (or the error, naming time and cause), non-finite values, the largest
//! penetration, the energy-balance residual, the deepest wear over the clearance, the steps,
//! rejections and wall time.

use crate::io::output::write_rows;
use crate::io::progress::Progress;
use crate::ode::Stats;
use crate::paper::figures::output_path;
use crate::scene::{scene_path, SceneFile};
use crate::simulation::simulate;
use crate::Result;
use std::path::Path;

/// Rotations of each stability case in the study.
pub const STABILITY_ROTATIONS: u32 = 3;
/// Step guard of the stability runs: a case needing more accepted steps fails (about 15 s;
/// the slowest completing case needs about 260 000 steps for 3 rotations).
pub const STABILITY_MAX_STEPS: u64 = 1_000_000;

/// One stability case.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityRow {
    /// Scene name under `data/scenes/stability/`.
    pub case: String,
    /// Rotations run.
    pub rotations: u32,
    /// The error of a failed run (naming time and cause).
    pub failure: Option<String>,
    /// Whether state, wear and penetration stayed finite (false also for a failed run).
    pub finite: bool,
    /// Largest penetration over the clearance joints and the whole run (m), start-up
    /// transient included: what stability needs bounded.
    pub max_penetration_whole_run: f64,
    /// Smallest radial clearance of the scene (m).
    pub clearance: f64,
    /// Deepest wear over all joints (m).
    pub max_wear: f64,
    /// Energy-balance residual (relative to the driver work).
    pub energy_residual: f64,
    /// Work counters of the run.
    pub stats: Stats,
    /// Wall time of the run (s).
    pub wall_time: f64,
}

/// The stability scenes, sorted by name.
pub fn stability_cases() -> Result<Vec<String>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/scenes/stability");
    let io = |source| crate::Error::Io {
        path: dir.clone(),
        source,
    };
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        if path.extension().is_some_and(|e| e == "toml") {
            if let Some(stem) = path.file_stem().and_then(|s| s.to_str()) {
                names.push(stem.to_string());
            }
        }
    }
    names.sort();
    Ok(names)
}

/// Runs stability case `name` for `rotations` with energy accounting and a step guard of
/// `max_steps`. A numerical failure is a row with its error; only bad scene files are `Err`.
pub fn stability_case(name: &str, rotations: u32, max_steps: u64) -> Result<StabilityRow> {
    let mut f = SceneFile::read(scene_path(&format!("stability/{name}")))?;
    f.run.rotations = rotations;
    f.run.record_rotations = 0;
    f.run.wear_snapshots.clear();
    f.run.energy_accounting = true;
    f.run.max_steps = max_steps;
    let scene = f.build()?;
    let clearance = scene
        .mechanism
        .clearance_joints
        .iter()
        .map(|c| c.r_bearing - c.r_journal)
        .fold(f64::INFINITY, f64::min);
    let mut row = StabilityRow {
        case: name.to_string(),
        rotations,
        failure: None,
        finite: false,
        max_penetration_whole_run: f64::NAN,
        clearance,
        max_wear: f64::NAN,
        energy_residual: f64::NAN,
        stats: Stats::default(),
        wall_time: 0.0,
    };
    let clock = std::time::Instant::now();
    match simulate(&scene) {
        Ok(out) => {
            let wear = out.final_wear.iter().flatten();
            row.finite = out.final_state.iter().chain(wear).all(|v| v.is_finite())
                && out.max_penetration_whole_run.iter().all(|p| p.is_finite());
            row.max_penetration_whole_run =
                (out.max_penetration_whole_run.iter().cloned()).fold(f64::MIN, f64::max);
            row.max_wear = out.final_wear.iter().flatten().cloned().fold(0.0, f64::max);
            row.energy_residual = out.energy.map_or(f64::NAN, |e| e.residual());
            row.stats = out.stats;
            row.wall_time = out.wall_time;
        }
        Err(e) => {
            row.failure = Some(e.to_string());
            row.wall_time = clock.elapsed().as_secs_f64();
        }
    }
    Ok(row)
}

/// The stability study (see the module documentation); `progress` is told each case.
/// Writes `data/stability.csv`.
pub fn stability(progress: &dyn Progress) -> Result<Vec<StabilityRow>> {
    let cases = stability_cases()?;
    let total = Some(cases.len() as u64);
    let mut rows = Vec::new();
    for name in cases {
        progress.observe(rows.len() as u64, total);
        progress.stage(&name);
        rows.push(stability_case(
            &name,
            STABILITY_ROTATIONS,
            STABILITY_MAX_STEPS,
        )?);
    }
    progress.observe(rows.len() as u64, total);
    write_rows(
        &output_path("data", "stability.csv"),
        &STABILITY_HEADER,
        rows.iter().map(StabilityRow::csv_row),
    )?;
    Ok(rows)
}

/// Columns of `data/stability.csv`.
pub const STABILITY_HEADER: [&str; 13] = [
    "case",
    "rotations",
    "completed",
    "finite",
    "max_penetration_whole_run_um",
    "clearance_um",
    "max_wear_um",
    "energy_residual",
    "steps",
    "rejected",
    "evaluations",
    "wall_time_s",
    "failure",
];

impl StabilityRow {
    /// Its row of `data/stability.csv` (columns [`STABILITY_HEADER`]).
    pub fn csv_row(&self) -> Vec<String> {
        vec![
            self.case.clone(),
            self.rotations.to_string(),
            self.failure.is_none().to_string(),
            self.finite.to_string(),
            format!("{:.4e}", self.max_penetration_whole_run * 1e6),
            format!("{:.4e}", self.clearance * 1e6),
            format!("{:.4e}", self.max_wear * 1e6),
            format!("{:.3e}", self.energy_residual),
            self.stats.steps.to_string(),
            self.stats.rejected.to_string(),
            self.stats.evaluations.to_string(),
            format!("{:.3}", self.wall_time),
            self.failure.clone().unwrap_or_default(),
        ]
    }
}
