//! The work-precision study: how the integration error trades against run time, and the
//! choice of the scenes' default tolerance (section 5 of `paper.md`).
//!
//! The standard scene (wear on, 40 rotations) is run with adaptive Dopri5 at rtol 1e-3 … 1e-10,
//! and DOP853 at a few tolerances, always with `atol = 1e-3·rtol` (one atol
//! for every controlled state component: positions in m and rad, velocities in m/s and rad/s)
//! and `max_step = 1e-3 s`, loose enough that the step cap does not decide the step of an
//! adaptive run (DOP853 keeps the scene's 1e-4 s, see [`wp_max_step`]). Fixed-step RK4 runs
//! at 1e-5 … 1e-6 s. Each setting is measured twice with
//! identical steps: one rotation recorded every 1 µs (orbit, contact force), and the 40
//! rotations of wear without recording, whose wall time is the cost reported. Errors are taken
//! against [`REFERENCE`] (DOP853 at rtol 1e-12); [`SECOND_REFERENCE`] (Dopri5 at rtol 1e-11)
//! measured against it gives the error floor, below which no error is meaningful:
//! * orbit: max |e − e_ref| of the journal centre over the first rotation (µm). The journal
//!   impacts within the first rotation and impact motion is sensitive to its initial state, so
//!   this measure is meaningful only while trajectories have not yet separated; once they do it
//!   saturates at about the clearance;
//! * force: relative error of the peak contact force over the first rotation;
//! * wear: RMS difference of the 40-rotation wear profile over the maximum reference depth. One
//!   run's profile follows one impact sequence, so this single-run error saturates at the
//!   ensemble spread (a few per cent) whatever the tolerance. The meaningful measure is the
//!   *ensemble* one: the RMS difference between the mean profile of a [`WP_MEMBERS`]-member
//!   ensemble and that of a reference ensemble ([`SECOND_REFERENCE`]'s setting), over the
//!   deepest reference mean wear, beside its sampling error
//!   `sqrt(mean over sectors of (sd² + sd_ref²) / N)` over the same depth: an error within about
//!   twice its sampling error is indistinguishable from the reference at that ensemble size.
//!   Settings whose single run takes more than [`WP_ENSEMBLE_MAX_EVALUATIONS`] evaluations are left out of the
//!   ensemble measure (their 16 members would take minutes) and say so.
//!
//! Rule for the default tolerance ([`WorkPrecision::rule`]): the first-rotation orbit
//! and force errors measured over ensemble members, with the old setting's accuracy over the
//! same members as the bound ([`super::tolerance_rule`]); the single-trajectory errors of this
//! study's CSV draw one sample of them.
//! The 40-rotation wear profile is reported, not used: after many impacts it can follow another
//! impact sequence (about 1 % RMS, without a trend in the tolerance).

use super::integration::Integration;
use super::tolerance_rule::{rule_rows, RuleRow};
use super::work_precision_figure::{plot_work_precision, Point};
use crate::analysis::statistics::Band;
use crate::io::output::{read_rows, write_rows};
use crate::io::progress::{Progress, Silent};
use crate::ode::{Method, Stats};
use crate::paper::cases::{wear_run_with, Need, Runs, CASES};
use crate::paper::figures::output_path;
use crate::paper::provenance::{self, Inputs};
use crate::scene::{scene_path, SceneFile, StepControlSpec};
use crate::simulation::ensemble::EnsembleSettings;
use crate::simulation::{simulate, RunOutput};
use crate::Result;

/// Step cap of the adaptive work-precision runs (s): far above the steps the tolerances choose.
pub const WP_MAX_STEP: f64 = 1e-3;

/// Step cap of `method` in the work-precision sweep: [`WP_MAX_STEP`], except DOP853, which is
/// kept at the scene's 1e-4 s because its 12-stage trial steps of ~1e-3 s reach deep into the
/// contact and overflow, to be rejected (one DOP853 row at 1e-3 s measures what that costs).
pub fn wp_max_step(method: Method) -> f64 {
    match method {
        Method::Dop853 => 1e-4,
        _ => WP_MAX_STEP,
    }
}
/// Recording interval of the first-rotation runs (s).
const WP_RECORD_INTERVAL: f64 = 1e-6;
/// Reference of the work-precision study.
pub const REFERENCE: Integration = Integration {
    method: Method::Dop853,
    rtol: 1e-12,
    atol: 1e-15,
    max_step: 1e-4,
    control: StepControlSpec::I,
};
/// Second reference: its error against [`REFERENCE`] is the error floor.
pub const SECOND_REFERENCE: Integration = Integration {
    method: Method::Dopri5,
    rtol: 1e-11,
    atol: 1e-14,
    max_step: WP_MAX_STEP,
    control: StepControlSpec::I,
};
/// An ode45-like Dopri5 as the paper ran it: MATLAB's default tolerances (rtol 1e-3, atol
/// 1e-6) with the paper's maximum step of 1e-5 s; the baseline the default setting must beat
/// in evaluations at equal accuracy of the ensemble statistics.
pub const ODE45_PAPER: Integration = Integration {
    method: Method::Dopri5,
    rtol: 1e-3,
    atol: 1e-6,
    max_step: 1e-5,
    control: StepControlSpec::I,
};

/// What the first rotation of a run recorded every [`WP_RECORD_INTERVAL`] (after
/// [`first_rotation_only`]) shows of its integration error.
pub(super) struct FirstRotation {
    ex: Vec<f64>,
    ey: Vec<f64>,
    peak_force: f64,
    /// Right-hand-side evaluations of the rotation.
    pub(super) evaluations: u64,
    /// Contact onsets the run located in the rotation at its first clearance joint (the standard
    /// scene's only one).
    pub(super) onsets: u64,
}

impl FirstRotation {
    /// The journal orbit and peak contact force of the first clearance joint of `out`.
    pub(super) fn of(out: &RunOutput) -> FirstRotation {
        let j = &out.recording.joints[0];
        FirstRotation {
            ex: j.ex.clone(),
            ey: j.ey.clone(),
            peak_force: j.normal_force.iter().cloned().fold(0.0, f64::max),
            evaluations: out.stats.evaluations,
            onsets: out.impacts[0],
        }
    }

    /// The orbit error (max journal-centre distance, µm) and the relative peak-force error
    /// against `r`.
    pub(super) fn errors(&self, r: &FirstRotation) -> (f64, f64) {
        let orbit = (self.ex.iter().zip(&self.ey))
            .zip(r.ex.iter().zip(&r.ey))
            .map(|((x, y), (xr, yr))| (x - xr).hypot(y - yr))
            .fold(0.0, f64::max);
        (
            orbit * 1e6,
            (self.peak_force - r.peak_force).abs() / r.peak_force,
        )
    }
}

/// Sets `f` to run its first rotation only, recorded every [`WP_RECORD_INTERVAL`].
pub(super) fn first_rotation_only(f: &mut SceneFile) {
    f.run.rotations = 1;
    f.run.record_rotations = 1;
    f.run.record_interval_s = WP_RECORD_INTERVAL;
    f.run.wear_snapshots.clear();
}

/// What the work-precision study compares between two runs.
struct Measured {
    first: FirstRotation,
    wear: Vec<f64>,
    wall_time: f64,
    stats: Stats,
}

/// Errors of one run against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// Max journal-centre distance over the first rotation (µm).
    pub orbit_um: f64,
    /// Relative error of the peak contact force over the first rotation.
    pub force_rel: f64,
    /// RMS wear-profile difference after 40 rotations over the max reference depth.
    pub wear_rel: f64,
}

/// Members of the work-precision study's wear ensembles.
pub const WP_MEMBERS: usize = 16;
/// Right-hand-side evaluations of a single run above which a setting gets no wear ensemble
/// (about 5 s of wall time here). A count, not a wall time, so that which rows are measured
/// does not depend on the machine or its load.
pub const WP_ENSEMBLE_MAX_EVALUATIONS: u64 = 20_000_000;

/// Error of a setting's ensemble-mean wear profile against the reference ensemble's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnsembleWearError {
    /// RMS difference of the mean profiles over the deepest reference mean wear.
    pub error: f64,
    /// Its sampling error, on the same scale.
    pub sampling: f64,
}

/// One setting of the work-precision study.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkRow {
    /// The setting.
    pub integration: Integration,
    /// The ensemble wear error, where measured.
    pub ensemble: Option<EnsembleWearError>,
    /// Wall time of the 40 rotations (s), 0 on failure.
    pub wall_time: f64,
    /// Work counters of the 40 rotations.
    pub stats: Stats,
    /// `None` when the run failed.
    pub errors: Option<Errors>,
    /// The error (with its time) of a failed run.
    pub failure: Option<String>,
}

/// Result of [`work_precision`].
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecision {
    /// Every setting, the two references last.
    pub rows: Vec<WorkRow>,
    /// Error of [`SECOND_REFERENCE`] against [`REFERENCE`].
    pub floor: Errors,
    /// The default-tolerance rule's measurement over members ([`rule_rows`]), from which
    /// [`super::tolerance_rule::pick`] chooses.
    pub rule: Vec<RuleRow>,
}

pub(super) fn standard() -> Result<SceneFile> {
    SceneFile::read(scene_path(CASES.standard.scene))
}

/// Step guard of each 40-rotation run but the reference's (which needs about 5e6 steps): the
/// other settings need at most 3e6.
const WP_MAX_STEPS: u64 = 4_000_000;

fn measure(int: &Integration) -> Result<Measured> {
    let apply = |f: &mut SceneFile| {
        int.apply(f);
        if *int != REFERENCE {
            f.run.max_steps = WP_MAX_STEPS;
        }
    };
    let mut f = standard()?;
    apply(&mut f);
    first_rotation_only(&mut f);
    let first = FirstRotation::of(&simulate(&f.build()?)?);
    let (_, wear) = wear_run_with(CASES.standard.scene, 0, apply)?;
    Ok(Measured {
        first,
        wear: wear.final_wear[0].clone(),
        wall_time: wear.wall_time,
        stats: wear.stats,
    })
}

fn errors(m: &Measured, r: &Measured) -> Errors {
    let (orbit_um, force_rel) = m.first.errors(&r.first);
    let ms = m
        .wear
        .iter()
        .zip(&r.wear)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / r.wear.len() as f64;
    let depth = r.wear.iter().cloned().fold(0.0, f64::max);
    Errors {
        orbit_um,
        force_rel,
        wear_rel: ms.sqrt() / depth,
    }
}

/// The settings of the work-precision sweep, references excluded.
pub fn work_precision_settings() -> Vec<Integration> {
    let adaptive = |method, rtols: &[f64]| -> Vec<Integration> {
        rtols
            .iter()
            .map(|&r| Integration::adaptive(method, r))
            .collect()
    };
    let mut s = adaptive(
        Method::Dopri5,
        &[
            1e-3,
            1e-4,
            1e-5,
            1e-6,
            PREVIOUS_SCENE.rtol,
            1e-7,
            1e-8,
            1e-9,
            1e-10,
        ],
    );
    s.push(SCENE);
    s.extend(adaptive(Method::Dop853, &[1e-5, 1e-7, 1e-9, 1e-11]));
    s.push(Integration {
        max_step: WP_MAX_STEP,
        ..Integration::adaptive(Method::Dop853, 1e-7)
    });
    s.extend([1e-5, 5e-6, 2e-6, 1e-6].map(Integration::rk4));
    s.push(ODE45_PAPER);
    s
}

/// The study's table under `data/`.
pub const WORK_PRECISION_FILE: &str = "work_precision.csv";

/// The study's figure under `figures/`, which the default report redraws from the table.
pub const WORK_PRECISION_FIGURE: &str = "work_precision.png";

/// What produced `data/work_precision.csv` ([`provenance`]): the standard scene and the
/// settings measured, the references, the step guard and the wear ensembles.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[WORK_PRECISION_FILE],
    // drawn by this run (`--all`) or redrawn by it from the checked CSV
    figures: &[],
    command: "cargo run --release --bin work_precision",
    rerun_by_all: true,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            vec![CASES.standard.scene],
            false,
            (
                work_precision_settings(),
                (REFERENCE, SECOND_REFERENCE, WP_MAX_STEPS),
                (WP_MEMBERS, WP_ENSEMBLE_MAX_EVALUATIONS),
                EnsembleSettings::default(),
            ),
        )
    },
};

/// The work-precision study (see the module documentation); `progress` is told each run and
/// wear ensemble.
/// Writes `data/work_precision.csv`, `figures/work_precision.png` and the rule's
/// `data/work_precision_members.csv`, each CSV with its record ([`provenance`]).
pub fn work_precision(progress: &dyn Progress) -> Result<WorkPrecision> {
    let (rows, floor) = provenance::recorded(&PROVENANCE, &[], || settings_study(progress))?;
    let rule = rule_rows(progress)?;
    Ok(WorkPrecision { rows, floor, rule })
}

/// Every setting's row and the error floor, written to `data/work_precision.csv` and drawn.
fn settings_study(progress: &dyn Progress) -> Result<(Vec<WorkRow>, Errors)> {
    let settings = work_precision_settings();
    // the reference, every setting and the second reference; the ensembles are added once known
    let mut total = settings.len() as u64 + 2;
    let mut done = 0;
    let mut start = |int: &Integration, total: u64, what: &str| {
        progress.observe(done, Some(total));
        progress.stage(&format!("{} {}{what}", int.method_name(), int.setting()));
        done += 1;
    };
    start(&REFERENCE, total, "");
    let reference = measure(&REFERENCE)?;
    let row = |int: Integration, m: &Measured| WorkRow {
        integration: int,
        ensemble: None,
        wall_time: m.wall_time,
        stats: m.stats,
        errors: Some(errors(m, &reference)),
        failure: None,
    };
    let mut rows = Vec::new();
    for int in settings.into_iter().chain([SECOND_REFERENCE]) {
        start(&int, total, "");
        rows.push(match measure(&int) {
            Ok(m) => row(int, &m),
            Err(e) => WorkRow {
                integration: int,
                ensemble: None,
                wall_time: 0.0,
                stats: Stats::default(),
                errors: None,
                failure: Some(e.to_string()),
            },
        });
    }
    rows.push(row(REFERENCE, &reference));
    let floor = rows
        .iter()
        .find(|r| r.integration == SECOND_REFERENCE)
        .and_then(|r| r.errors)
        .ok_or_else(|| crate::Error::Integration {
            time: 0.0,
            cause: "the second reference failed".into(),
        })?;
    let with_ensemble = |r: &WorkRow| {
        r.failure.is_none()
            && r.stats.evaluations <= WP_ENSEMBLE_MAX_EVALUATIONS
            && r.integration != REFERENCE
    };
    total += 1 + rows.iter().filter(|r| with_ensemble(r)).count() as u64;
    // the reference ensemble draws other offsets, so the two means are independent samples
    start(&SECOND_REFERENCE, total, " (reference ensemble)");
    let reference = wear_ensemble(&SECOND_REFERENCE, 2)?;
    for r in rows.iter_mut().filter(|r| with_ensemble(r)) {
        start(&r.integration, total, " (ensemble)");
        let e = wear_ensemble(&r.integration, 1)?;
        r.ensemble = Some(ensemble_error(&e, &reference));
    }
    write_work_precision(&rows)?;
    let points: Vec<Point> = rows.iter().map(Point::of).collect();
    plot_work_precision(&points, &floor)?;
    Ok((rows, floor))
}

/// Per sector, the mean and sd of the 40-rotation wear profile over [`WP_MEMBERS`] members.
fn wear_ensemble(int: &Integration, seed: u64) -> Result<Band> {
    let apply = |f: &mut SceneFile| {
        int.apply(f);
        f.run.max_steps = WP_MAX_STEPS;
    };
    let ensemble = EnsembleSettings {
        members: WP_MEMBERS,
        seed,
        ..EnsembleSettings::default()
    };
    let needs = [Need::Wear(CASES.standard.scene)];
    let runs = Runs::compute(&needs, ensemble, &apply, &Silent)?;
    Ok(runs.wear(CASES.standard.scene)?.band())
}

/// The ensemble-mean wear error of `e` against `reference` (see the module documentation).
fn ensemble_error(e: &Band, reference: &Band) -> EnsembleWearError {
    let depth = reference.mean().iter().cloned().fold(0.0, f64::max);
    let sectors = reference.sectors.len() as f64;
    let (mut sq, mut var) = (0.0, 0.0);
    for (a, b) in e.sectors.iter().zip(&reference.sectors) {
        sq += (a.mean - b.mean).powi(2);
        var += a.sd.powi(2) / a.n as f64 + b.sd.powi(2) / b.n as f64;
    }
    EnsembleWearError {
        error: (sq / sectors).sqrt() / depth,
        sampling: (var / sectors).sqrt() / depth,
    }
}

/// Largest relative peak-force error of the default tolerance: above the floor of about 2e-5
/// that sampling the peak every 1 µs sets at every tolerance.
pub const FORCE_BOUND: f64 = 1e-4;
/// The scenes' integration (`data/scenes/standard.toml`): Dopri5 with Söderlind's PI.4.2
/// filter at the default-tolerance rule's pick for it ([`super::tolerance_rule`]), rtol 2.5e-7,
/// atol `1e-3·rtol`. Over the rule's 512 members the median ratio of a member's first-rotation
/// orbit error to its own bound's is 0.865 at 2.5e-7 (interval 0.801-0.921) and 1.057 at 3e-7
/// (1.008-1.133): the paired rule, its strict and its lenient reading all pick 2.5e-7, so the
/// members settle the choice (2026-11-28). Until then the scenes ran the I controller at its
/// own pick, [`PREVIOUS_SCENE`]. paper.md sections 5 and 7 state the picks from
/// `data/work_precision_members.csv`.
pub const SCENE: Integration = Integration {
    method: Method::Dopri5,
    rtol: 2.5e-7,
    atol: 2.5e-10,
    max_step: WP_MAX_STEP,
    control: StepControlSpec::Pi42,
};

/// The scenes' integration until 2026-11-28: Dopri5 with the I controller at the rule's pick
/// for it, rtol 1.5e-7 (median ratio 0.833, interval 0.757-0.898; at 2e-7 1.054, 0.972-1.109,
/// so the members did not settle it). The work-precision sweep keeps it as a row.
pub const PREVIOUS_SCENE: Integration = Integration {
    method: Method::Dopri5,
    rtol: 1.5e-7,
    atol: 1.5e-10,
    max_step: WP_MAX_STEP,
    control: StepControlSpec::I,
};

/// Column of `data/work_precision.csv`: the method.
const METHOD: &str = "method";
/// Column of `data/work_precision.csv`: the setting.
const SETTING: &str = "setting";
/// Column of `data/work_precision.csv`: right-hand-side evaluations.
const EVALUATIONS: &str = "evaluations";
/// Column of `data/work_precision.csv`: [`EnsembleWearError::error`].
const ENSEMBLE_ERROR: &str = "ensemble_wear_err_rel";
/// Column of `data/work_precision.csv`: [`EnsembleWearError::sampling`].
const ENSEMBLE_SAMPLING: &str = "ensemble_wear_sampling_rel";

/// Columns of `data/work_precision.csv`: the first-rotation orbit and force errors and the
/// single-run wear error ([`Errors`]).
const ERRORS: [&str; 3] = ["orbit_err_um", "force_err_rel", "wear_err_rel"];

/// Columns of `data/work_precision.csv`.
pub const WORK_PRECISION_HEADER: [&str; 12] = [
    METHOD,
    SETTING,
    "wall_time_s",
    "steps",
    "rejected",
    EVALUATIONS,
    ERRORS[0],
    ERRORS[1],
    ERRORS[2],
    ENSEMBLE_ERROR,
    ENSEMBLE_SAMPLING,
    "failure",
];

/// A setting's cost and ensemble wear error as an earlier run of the study wrote them.
pub struct EnsembleCost {
    /// Method name (`dopri5`, `dop853`, `rk4`).
    pub method: String,
    /// Setting as in the CSV (`rtol=1e-7 max_step=1e-3`, with its role if any).
    pub setting: String,
    /// Right-hand-side evaluations of one 40-rotation run.
    pub evaluations: u64,
    /// Its ensemble wear error.
    pub error: EnsembleWearError,
}

/// The ensemble wear errors an earlier run of the study wrote to `data/work_precision.csv`,
/// of every setting that has one, in file order; `None` when the file or one of those columns
/// is missing.
pub fn read_ensemble_wear_errors() -> Option<Vec<EnsembleCost>> {
    let (header, rows) = read_rows(&output_path("data", WORK_PRECISION_FILE)).ok()?;
    let col = |name: &str| header.iter().position(|h| h == name);
    let (method, setting) = (col(METHOD)?, col(SETTING)?);
    let (error, sampling) = (col(ENSEMBLE_ERROR)?, col(ENSEMBLE_SAMPLING)?);
    let evaluations = col(EVALUATIONS)?;
    let parsed = rows
        .iter()
        .filter_map(|r| {
            Some(EnsembleCost {
                method: r[method].clone(),
                setting: r[setting].clone(),
                evaluations: r[evaluations].parse().ok()?,
                error: EnsembleWearError {
                    error: r[error].parse().ok()?,
                    sampling: r[sampling].parse().ok()?,
                },
            })
        })
        .collect();
    Some(parsed)
}

fn write_work_precision(rows: &[WorkRow]) -> Result<()> {
    let num = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4e}"));
    write_rows(
        &output_path("data", WORK_PRECISION_FILE),
        &WORK_PRECISION_HEADER,
        rows.iter().map(|r| {
            let role = match r.integration {
                i if i == REFERENCE => " (reference)",
                i if i == SECOND_REFERENCE => " (second reference)",
                i if i == ODE45_PAPER => " (ode45-like at the paper's max step)",
                _ => "",
            };
            vec![
                r.integration.method_name().to_string(),
                format!("{}{role}", r.integration.setting()),
                format!("{:.3}", r.wall_time),
                r.stats.steps.to_string(),
                r.stats.rejected.to_string(),
                r.stats.evaluations.to_string(),
                num(r.errors.map(|e| e.orbit_um)),
                num(r.errors.map(|e| e.force_rel)),
                num(r.errors.map(|e| e.wear_rel)),
                num(r.ensemble.map(|e| e.error)),
                num(r.ensemble.map(|e| e.sampling)),
                r.failure.clone().unwrap_or_default(),
            ]
        }),
    )
}
