//! Numerical studies of the integration itself (issue #6): how error trades against run time,
//! whether the paper's results depend on integration accuracy, and whether stiff and extreme
//! cases run to completion. Each study writes `data/<study>.csv` (and a figure where it has
//! one) atomically and returns what it measured; the `src/bin/` programs only call them.
//!
//! # Work-precision ([`work_precision`])
//! The standard scene (wear on, 40 rotations) is run with adaptive Dopri5 at rtol 1e-3 … 1e-10,
//! DOP853 and RODAS3 (Rosenbrock) at a few tolerances, always with `atol = 1e-3·rtol` (one atol
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
//!   Settings whose single run takes more than [`WP_ENSEMBLE_MAX_WALL`] are left out of the
//!   ensemble measure (their 16 members would take minutes) and say so.
//!
//! Rule for the default tolerance ([`WorkPrecision::default_rtol`]): the loosest Dopri5 rtol
//! at which, and at every tighter rtol, the first-rotation orbit error is at most
//! [`ORBIT_BOUND_UM`] (0.5 % of the standard clearance) and the peak-force error at most
//! [`FORCE_BOUND`]: the trajectories, forces and concordances of the figures are then converged.
//! The 40-rotation wear profile is reported, not used: after many impacts it can follow another
//! impact sequence (about 1 % RMS, without a trend in the tolerance).
//!
//! # Accuracy dependence ([`accuracy_dependence`])
//! Every Table 3 case (settled, then 6 rotations recorded and split into 3 windows of 2) and
//! the 40-rotation standard wear profile are computed with four integrations: the scene's own
//! converged settings, an ode45-like Dopri5 at its defaults (rtol 1e-3, atol 1e-6, max step
//! 1e-2 s), and RK4 at 1e-5 s and 1e-4 s. A failed run is recorded with its error (time and
//! cause). A paper result *holds* for an integration when every window (or the wear profile)
//! reproduces it: the motion mode, the dominant factor (P-w or s-w), each concordance within
//! the golden tolerance, the three severe wear regions within the golden angle tolerance and
//! the deepest at 180°. A result *appears only under under-resolved integration* when it fails
//! at converged settings but holds for one of the other three.
//!
//! # Stability ([`stability`])
//! Each scene of `data/scenes/stability/` varies one physical value of the standard scene to an
//! extreme. It runs [`STABILITY_ROTATIONS`] rotations (tests: one) with energy accounting and
//! a step guard of [`STABILITY_MAX_STEPS`], at the scene's own integration settings. Reported:
//! completion (or the error, naming time and cause), non-finite values, the largest
//! penetration, the energy-balance residual, the deepest wear over the clearance, the steps,
//! rejections and wall time.

use crate::analysis::{peaks, Motion};
use crate::concordance::Concordance;
use crate::figures::output_path;
use crate::golden::{angle_distance, Golden};
use crate::integrator::{Method, Stats};
use crate::output::write_rows;
use crate::plot::{render, Axes, Series, Style};
use crate::runs::{wear_run_with, CASES, PEAK_PROMINENCE};
use crate::scene::{scene_path, MethodSpec, SceneFile};
use crate::simulation::{simulate, RunOutput};
use crate::Result;
use std::path::Path;

/// An integration setting applied to a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Integration {
    pub method: Method,
    pub rtol: f64,
    /// Absolute tolerance in state units (m, rad, m/s, rad/s).
    pub atol: f64,
    /// Largest step (s).
    pub max_step: f64,
}

impl Integration {
    /// Adaptive `method` at `rtol`, `atol = 1e-3·rtol`, with the work-precision step cap of
    /// the method ([`wp_max_step`]).
    pub fn adaptive(method: Method, rtol: f64) -> Integration {
        Integration {
            method,
            rtol,
            atol: 1e-3 * rtol,
            max_step: wp_max_step(method),
        }
    }

    /// Classical RK4 with a fixed `step` (s); tolerances unused.
    pub fn rk4(step: f64) -> Integration {
        Integration {
            method: Method::Rk4 { step },
            rtol: 1.0,
            atol: 1.0,
            max_step: step,
        }
    }

    /// Sets the scene's run to this integration.
    pub fn apply(&self, f: &mut SceneFile) {
        let run = &mut f.run;
        run.method = match self.method {
            Method::Dopri5 => MethodSpec::Dopri5,
            Method::Dop853 => MethodSpec::Dop853,
            Method::Rosenbrock => MethodSpec::Rosenbrock,
            Method::Rk4 { step } => {
                run.fixed_step_s = Some(step);
                MethodSpec::Rk4
            }
        };
        run.rtol = self.rtol;
        run.atol = self.atol;
        run.max_step_s = self.max_step;
    }

    /// Method name as in the CSV files.
    pub fn method_name(&self) -> &'static str {
        match self.method {
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
            Method::Rosenbrock => "rosenbrock",
            Method::Rk4 { .. } => "rk4",
        }
    }

    /// `"rtol=1e-6 max_step=1e-3"` or `"h=1e-5"`.
    pub fn setting(&self) -> String {
        match self.method {
            Method::Rk4 { step } => format!("h={step:e}"),
            _ => format!("rtol={:e} max_step={:e}", self.rtol, self.max_step),
        }
    }
}

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
};
/// Second reference: its error against [`REFERENCE`] is the error floor.
pub const SECOND_REFERENCE: Integration = Integration {
    method: Method::Dopri5,
    rtol: 1e-11,
    atol: 1e-14,
    max_step: WP_MAX_STEP,
};

/// What the work-precision study compares between two runs.
struct Measured {
    ex: Vec<f64>,
    ey: Vec<f64>,
    peak_force: f64,
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
/// Single-run wall time (s) above which a setting gets no wear ensemble.
pub const WP_ENSEMBLE_MAX_WALL: f64 = 4.0;

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
    pub integration: Integration,
    /// The ensemble wear error, where measured.
    pub ensemble: Option<EnsembleWearError>,
    /// Wall time of the 40 rotations (s), 0 on failure.
    pub wall_time: f64,
    pub stats: Stats,
    /// `None` when the run failed.
    pub errors: Option<Errors>,
    pub failure: Option<String>,
}

/// Result of [`work_precision`].
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecision {
    /// Every setting, the two references last.
    pub rows: Vec<WorkRow>,
    /// Error of [`SECOND_REFERENCE`] against [`REFERENCE`].
    pub floor: Errors,
    /// Default rtol by the module's rule; `None` if no Dopri5 setting meets it.
    pub default_rtol: Option<f64>,
}

fn standard() -> Result<SceneFile> {
    SceneFile::read(scene_path("standard"))
}

/// Step guard of each 40-rotation run but the reference's (which needs about 5e6 steps): the
/// other settings need at most 3e6, and a stalled RODAS3 run stops in under a minute.
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
    f.run.rotations = 1;
    f.run.record_rotations = 1;
    f.run.record_interval_s = WP_RECORD_INTERVAL;
    f.run.wear_snapshots.clear();
    let first = simulate(&f.build()?)?;
    let j = &first.recording.joints[0];
    let (_, wear) = wear_run_with("standard", 0, apply)?;
    Ok(Measured {
        ex: j.ex.clone(),
        ey: j.ey.clone(),
        peak_force: j.normal_force.iter().cloned().fold(0.0, f64::max),
        wear: wear.final_wear[0].clone(),
        wall_time: wear.wall_time,
        stats: wear.stats,
    })
}

fn errors(m: &Measured, r: &Measured) -> Errors {
    let orbit =
        m.ex.iter()
            .zip(&m.ey)
            .zip(r.ex.iter().zip(&r.ey))
            .map(|((x, y), (xr, yr))| (x - xr).hypot(y - yr))
            .fold(0.0, f64::max);
    let ms = m
        .wear
        .iter()
        .zip(&r.wear)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / r.wear.len() as f64;
    let depth = r.wear.iter().cloned().fold(0.0, f64::max);
    Errors {
        orbit_um: orbit * 1e6,
        force_rel: (m.peak_force - r.peak_force).abs() / r.peak_force,
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
        &[1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
    );
    s.extend(adaptive(Method::Dop853, &[1e-5, 1e-7, 1e-9, 1e-11]));
    s.push(Integration {
        max_step: WP_MAX_STEP,
        ..Integration::adaptive(Method::Dop853, 1e-7)
    });
    // RODAS3 costs ~50 s at 1e-5 already (order 3, a Jacobian per step): no tighter setting.
    s.extend(adaptive(Method::Rosenbrock, &[1e-3, 1e-4, 1e-5]));
    s.extend([1e-5, 5e-6, 2e-6, 1e-6].map(Integration::rk4));
    s
}

/// The work-precision study (see the module documentation); `progress` is told each setting.
/// Writes `data/work_precision.csv` and `figures/work_precision.png`.
pub fn work_precision(progress: impl Fn(&Integration)) -> Result<WorkPrecision> {
    progress(&REFERENCE);
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
    for int in work_precision_settings()
        .into_iter()
        .chain([SECOND_REFERENCE])
    {
        progress(&int);
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
    // the reference ensemble draws other offsets, so the two means are independent samples
    let reference = wear_ensemble(&SECOND_REFERENCE, 2)?;
    for r in rows.iter_mut().filter(|r| {
        r.failure.is_none() && r.wall_time <= WP_ENSEMBLE_MAX_WALL && r.integration != REFERENCE
    }) {
        progress(&r.integration);
        let e = wear_ensemble(&r.integration, 1)?;
        r.ensemble = Some(ensemble_error(&e, &reference));
    }
    let default_rtol = pick_default(&rows);
    write_work_precision(&rows)?;
    plot_work_precision(&rows, &floor)?;
    Ok(WorkPrecision {
        rows,
        floor,
        default_rtol,
    })
}

/// Per sector, the mean and sd of the 40-rotation wear profile over [`WP_MEMBERS`] members.
fn wear_ensemble(int: &Integration, seed: u64) -> Result<crate::statistics::Band> {
    let apply = |f: &mut SceneFile| {
        int.apply(f);
        f.run.max_steps = WP_MAX_STEPS;
    };
    let ensemble = crate::ensemble::EnsembleSettings {
        members: WP_MEMBERS,
        seed,
    };
    let needs = [crate::runs::Need::Wear("standard")];
    let runs = crate::runs::Runs::compute(&needs, ensemble, &apply, |_, _| {})?;
    Ok(runs.wear("standard")?.band())
}

/// The ensemble-mean wear error of `e` against `reference` (see the module documentation).
fn ensemble_error(
    e: &crate::statistics::Band,
    reference: &crate::statistics::Band,
) -> EnsembleWearError {
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

/// Largest first-rotation orbit error of the default tolerance (µm): 0.5 % of 20 µm.
pub const ORBIT_BOUND_UM: f64 = 0.1;
/// Largest relative peak-force error of the default tolerance.
pub const FORCE_BOUND: f64 = 1e-4;

/// The module's rule: loosest Dopri5 rtol from which on (tighter) the orbit and force errors
/// are within their bounds.
fn pick_default(rows: &[WorkRow]) -> Option<f64> {
    let mut sweep: Vec<&WorkRow> = rows
        .iter()
        .filter(|r| r.integration.method == Method::Dopri5 && r.integration != SECOND_REFERENCE)
        .collect();
    sweep.sort_by(|a, b| a.integration.rtol.total_cmp(&b.integration.rtol));
    // tightest first: walk towards looser while the bound holds
    sweep
        .iter()
        .take_while(|r| {
            r.errors
                .is_some_and(|e| e.orbit_um <= ORBIT_BOUND_UM && e.force_rel <= FORCE_BOUND)
        })
        .last()
        .map(|r| r.integration.rtol)
}

fn write_work_precision(rows: &[WorkRow]) -> Result<()> {
    let header = [
        "method",
        "setting",
        "wall_time_s",
        "steps",
        "rejected",
        "evaluations",
        "orbit_err_um",
        "force_err_rel",
        "wear_err_rel",
        "ensemble_wear_err_rel",
        "ensemble_wear_sampling_rel",
        "failure",
    ];
    let num = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4e}"));
    write_rows(
        &output_path("data", "work_precision.csv"),
        &header,
        rows.iter().map(|r| {
            let role = match r.integration {
                i if i == REFERENCE => " (reference)",
                i if i == SECOND_REFERENCE => " (second reference)",
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

/// log10 of an error, clamped so an exact zero (the reference itself) stays on the plot.
fn log_err(e: f64) -> f64 {
    e.max(1e-16).log10()
}

fn plot_work_precision(rows: &[WorkRow], floor: &Errors) -> Result<()> {
    type Pick = fn(&WorkRow) -> Option<f64>;
    let measures: [(&str, &str, Pick); 3] = [
        (
            "Journal orbit, first rotation",
            "log10 max orbit error (µm)",
            |r| r.errors.map(|e| e.orbit_um),
        ),
        (
            "Peak contact force, first rotation",
            "log10 relative peak-force error",
            |r| r.errors.map(|e| e.force_rel),
        ),
        (
            "Wear after 40 rotations, ensemble mean of 16",
            "log10 RMS error of the mean profile / max depth",
            |r| r.ensemble.map(|e| e.error),
        ),
    ];
    let methods = ["dopri5", "dop853", "rosenbrock", "rk4"];
    let measured = |r: &&WorkRow| r.integration != REFERENCE && r.integration != SECOND_REFERENCE;
    // [measure][method] = (log10 wall time, log10 error) of the completed sweep runs
    let series: Vec<Vec<(Vec<f64>, Vec<f64>)>> = measures
        .iter()
        .map(|(_, _, pick)| {
            methods
                .iter()
                .map(|m| {
                    rows.iter()
                        .filter(measured)
                        .filter(|r| r.integration.method_name() == *m)
                        .filter_map(|r| pick(r).map(|e| (r.wall_time.log10(), log_err(e))))
                        .unzip()
                })
                .collect()
        })
        .collect();
    let times: Vec<f64> = rows
        .iter()
        .filter(|r| r.errors.is_some())
        .map(|r| r.wall_time.log10())
        .collect();
    let span = [
        times.iter().cloned().fold(f64::INFINITY, f64::min),
        times.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
    ];
    // the floors: the second reference's error for one run, the sampling error for ensembles
    let sampling = crate::statistics::Distribution::of(
        rows.iter().filter_map(|r| r.ensemble.map(|e| e.sampling)),
    );
    let floors = [
        ("floor (reference disagreement)", log_err(floor.orbit_um)),
        ("floor (reference disagreement)", log_err(floor.force_rel)),
        (
            "sampling error of the difference (median)",
            log_err(sampling.median()),
        ),
    ]
    .map(|(l, y)| (l, [y; 2]));
    let panels: Vec<Axes> = measures
        .iter()
        .zip(&series)
        .zip(&floors)
        .map(|(((title, y, _), per_method), (label, fl))| {
            let mut s: Vec<Series> = methods
                .iter()
                .zip(per_method)
                .map(|(m, (x, y))| Series::new(*m, x, y, Style::Points))
                .collect();
            s.push(Series::new(*label, &span, fl, Style::Reference));
            Axes::new(*title, "log10 wall time of one 40-rotation run (s)", *y, s)
        })
        .collect();
    render(&output_path("figures", "work_precision.png"), &panels)
}

// ---------------------------------------------------------------------------------------------
// Accuracy dependence

/// Rotations recorded after settling, split into [`WINDOWS`] windows.
const WINDOW_ROTATIONS: u32 = 2;
const WINDOWS: u32 = 3;

/// The four integrations of the accuracy study: (label, `None` for the scene's own).
pub fn accuracy_settings() -> [(&'static str, Option<Integration>); 4] {
    [
        ("converged", None),
        (
            "ode45-defaults",
            Some(Integration {
                method: Method::Dopri5,
                rtol: 1e-3,
                atol: 1e-6,
                max_step: 1e-2,
            }),
        ),
        ("rk4-1e-5", Some(Integration::rk4(1e-5))),
        ("rk4-1e-4", Some(Integration::rk4(1e-4))),
    ]
}

/// What one case gave under one integration.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyRow {
    /// Scene name (a Table 3 case or `standard-wear`).
    pub case: String,
    pub setting: &'static str,
    /// Motion modes of the windows (Table 3 cases).
    pub modes: Vec<&'static str>,
    /// Dominant factor of each window.
    pub dominance: Vec<&'static str>,
    /// (min, max) of P-w and of s-w over the windows.
    pub pw: (f64, f64),
    pub sw: (f64, f64),
    /// Three deepest wear peaks (deg), for the wear case.
    pub peak_angles: Vec<f64>,
    pub wall_time: f64,
    /// The error (with its time) of a failed run.
    pub failure: Option<String>,
}

/// Whether one paper result depends on integration accuracy.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// e.g. `"speed_30rpm motion"`.
    pub result: String,
    /// The paper's value.
    pub paper: String,
    /// Holds for each setting of [`accuracy_settings`], in order.
    pub holds: [bool; 4],
}

impl Finding {
    pub fn holds_converged(&self) -> bool {
        self.holds[0]
    }

    /// Fails at converged accuracy but holds for an under-resolved integration.
    pub fn only_under_resolved(&self) -> bool {
        !self.holds[0] && self.holds[1..].iter().any(|&h| h)
    }
}

/// Result of [`accuracy_dependence`].
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyDependence {
    pub rows: Vec<AccuracyRow>,
    pub findings: Vec<Finding>,
}

/// Whether a row reproduces one paper result.
type Check<'a> = dyn Fn(&AccuracyRow) -> bool + 'a;

fn min_max(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

fn failed_row(case: &str, setting: &'static str, e: crate::Error) -> AccuracyRow {
    AccuracyRow {
        case: case.to_string(),
        setting,
        modes: Vec::new(),
        dominance: Vec::new(),
        pw: (f64::NAN, f64::NAN),
        sw: (f64::NAN, f64::NAN),
        peak_angles: Vec::new(),
        wall_time: 0.0,
        failure: Some(e.to_string()),
    }
}

/// Settles `name` under `int`, records 6 rotations and measures each window of 2.
fn windowed_case(name: &str, setting: &'static str, int: Option<Integration>) -> AccuracyRow {
    let run = || -> Result<RunOutput> {
        let mut f = SceneFile::read(scene_path(name))?;
        if let Some(i) = int {
            i.apply(&mut f);
        }
        f.run.settle = true;
        f.run.rotations = WINDOWS * WINDOW_ROTATIONS;
        f.run.record_rotations = f.run.rotations;
        f.run.wear_snapshots.clear();
        simulate(&f.build()?)
    };
    let out = match run() {
        Ok(o) => o,
        Err(e) => return failed_row(name, setting, e),
    };
    let rec = &out.recording;
    let j = &rec.joints[0];
    let dt = rec.time[1] - rec.time[0];
    let len = rec.time.len() / WINDOWS as usize;
    let windows: Vec<(Motion, Concordance)> = (0..WINDOWS as usize)
        .map(|w| {
            let r = w * len..(w + 1) * len;
            (
                Motion::classify(&j.delta[r.clone()], dt, WINDOW_ROTATIONS as f64),
                Concordance::of(
                    &j.pressure[r.clone()],
                    &j.sliding_velocity[r.clone()],
                    &j.wear_rate[r],
                    dt,
                ),
            )
        })
        .collect();
    AccuracyRow {
        case: name.to_string(),
        setting,
        modes: windows.iter().map(|(m, _)| m.mode()).collect(),
        dominance: windows.iter().map(|(_, c)| c.dominant()).collect(),
        pw: min_max(windows.iter().map(|(_, c)| c.pressure_wear)),
        sw: min_max(windows.iter().map(|(_, c)| c.sliding_wear)),
        peak_angles: Vec::new(),
        wall_time: out.wall_time,
        failure: None,
    }
}

fn wear_case(setting: &'static str, int: Option<Integration>) -> AccuracyRow {
    match wear_run_with("standard", 0, |f| {
        if let Some(i) = int {
            i.apply(f)
        }
    }) {
        Ok((_, out)) => AccuracyRow {
            peak_angles: peaks(&out.final_wear[0], PEAK_PROMINENCE)
                .iter()
                .take(3)
                .map(|p| p.angle_deg)
                .collect(),
            wall_time: out.wall_time,
            modes: Vec::new(),
            dominance: Vec::new(),
            pw: (f64::NAN, f64::NAN),
            sw: (f64::NAN, f64::NAN),
            case: "standard-wear".into(),
            setting,
            failure: None,
        },
        Err(e) => failed_row("standard-wear", setting, e),
    }
}

/// The accuracy-dependence study (see the module documentation); `progress` is told each run.
/// Writes `data/accuracy_dependence.csv`.
pub fn accuracy_dependence(progress: impl Fn(&str, &str)) -> Result<AccuracyDependence> {
    let golden = Golden::load()?;
    let settings = accuracy_settings();
    let mut rows = Vec::new();
    for (name, _, _) in CASES {
        for (label, int) in settings {
            progress(name, label);
            rows.push(windowed_case(name, label, int));
        }
    }
    for (label, int) in settings {
        progress("standard-wear", label);
        rows.push(wear_case(label, int));
    }
    let mut findings = Vec::new();
    let tol = golden.concordance_tolerance;
    let holds = |case: &str, test: &Check| -> [bool; 4] {
        settings.map(|(label, _)| {
            rows.iter()
                .find(|r| r.case == case && r.setting == label)
                .is_some_and(|r| r.failure.is_none() && test(r))
        })
    };
    for ((name, _, _), g) in CASES.iter().zip(&golden.table3) {
        let within = |v: (f64, f64), p: f64| (v.0 - p).abs() <= tol && (v.1 - p).abs() <= tol;
        let checks: [(&str, String, &Check); 4] = [
            ("motion", g.motion.clone(), &|r| {
                r.modes.iter().all(|m| *m == g.motion)
            }),
            ("dominance", g.dominant().to_string(), &|r| {
                r.dominance.iter().all(|d| *d == g.dominant())
            }),
            ("P-w", format!("{:.4} ± {tol}", g.pw), &|r| {
                within(r.pw, g.pw)
            }),
            ("s-w", format!("{:.4} ± {tol}", g.sw), &|r| {
                within(r.sw, g.sw)
            }),
        ];
        for (what, paper, test) in checks {
            findings.push(Finding {
                result: format!("{name} {what}"),
                paper,
                holds: holds(name, test),
            });
        }
    }
    let claim = &golden.standard_wear;
    let near = |a: f64, b: f64| angle_distance(a, b) <= claim.angle_tolerance_deg;
    findings.push(Finding {
        result: "standard wear regions".into(),
        paper: format!("{:?} deg", claim.peak_angles_deg),
        holds: holds("standard-wear", &|r| {
            claim
                .peak_angles_deg
                .iter()
                .all(|&p| r.peak_angles.iter().any(|&a| near(a, p)))
        }),
    });
    findings.push(Finding {
        result: "standard deepest wear region".into(),
        paper: format!("{} deg", claim.largest_peak_deg),
        holds: holds("standard-wear", &|r| {
            r.peak_angles
                .first()
                .is_some_and(|&a| near(a, claim.largest_peak_deg))
        }),
    });
    write_accuracy(&rows, &findings)?;
    Ok(AccuracyDependence { rows, findings })
}

fn write_accuracy(rows: &[AccuracyRow], findings: &[Finding]) -> Result<()> {
    let header = [
        "case",
        "setting",
        "motion_modes",
        "dominance",
        "pw_min",
        "pw_max",
        "sw_min",
        "sw_max",
        "peak_angles_deg",
        "wall_time_s",
        "failure",
    ];
    let num = |v: f64| {
        if v.is_nan() {
            String::new()
        } else {
            format!("{v:.4}")
        }
    };
    let runs = rows.iter().map(|r| {
        let angles: Vec<String> = r.peak_angles.iter().map(|a| format!("{a:.1}")).collect();
        vec![
            r.case.clone(),
            r.setting.to_string(),
            r.modes.join("; "),
            r.dominance.join("; "),
            num(r.pw.0),
            num(r.pw.1),
            num(r.sw.0),
            num(r.sw.1),
            angles.join("; "),
            format!("{:.2}", r.wall_time),
            r.failure.clone().unwrap_or_default(),
        ]
    });
    // Findings follow as rows whose `setting` says which integrations reproduce the paper.
    let verdicts = findings.iter().map(|f| {
        let holding: Vec<&str> = accuracy_settings()
            .iter()
            .zip(f.holds)
            .filter(|(_, h)| *h)
            .map(|((l, _), _)| *l)
            .collect();
        let mut row = vec![String::new(); header.len()];
        row[0] = format!("finding: {}", f.result);
        row[1] = format!("holds for: {}", holding.join("; "));
        row[2] = format!("paper: {}", f.paper);
        row[10] = if f.holds_converged() {
            "holds at converged accuracy".into()
        } else if f.only_under_resolved() {
            "appears only under under-resolved integration".into()
        } else {
            "not reproduced by any integration".into()
        };
        row
    });
    write_rows(
        &output_path("data", "accuracy_dependence.csv"),
        &header,
        runs.chain(verdicts),
    )
}

// ---------------------------------------------------------------------------------------------
// Stability

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
    pub rotations: u32,
    /// The error of a failed run (naming time and cause).
    pub failure: Option<String>,
    /// Whether state, wear and penetration stayed finite (false also for a failed run).
    pub finite: bool,
    /// Largest penetration over the clearance joints (m).
    pub max_penetration: f64,
    /// Smallest radial clearance of the scene (m).
    pub clearance: f64,
    /// Deepest wear over all joints (m).
    pub max_wear: f64,
    /// Energy-balance residual (relative to the driver work).
    pub energy_residual: f64,
    pub stats: Stats,
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
        max_penetration: f64::NAN,
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
                && out.max_penetration.iter().all(|p| p.is_finite());
            row.max_penetration = out.max_penetration.iter().cloned().fold(f64::MIN, f64::max);
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
pub fn stability(progress: impl Fn(&str)) -> Result<Vec<StabilityRow>> {
    let mut rows = Vec::new();
    for name in stability_cases()? {
        progress(&name);
        rows.push(stability_case(
            &name,
            STABILITY_ROTATIONS,
            STABILITY_MAX_STEPS,
        )?);
    }
    let header = [
        "case",
        "rotations",
        "completed",
        "finite",
        "max_penetration_um",
        "clearance_um",
        "max_wear_um",
        "energy_residual",
        "steps",
        "rejected",
        "evaluations",
        "wall_time_s",
        "failure",
    ];
    write_rows(
        &output_path("data", "stability.csv"),
        &header,
        rows.iter().map(|r| {
            vec![
                r.case.clone(),
                r.rotations.to_string(),
                r.failure.is_none().to_string(),
                r.finite.to_string(),
                format!("{:.4e}", r.max_penetration * 1e6),
                format!("{:.4e}", r.clearance * 1e6),
                format!("{:.4e}", r.max_wear * 1e6),
                format!("{:.3e}", r.energy_residual),
                r.stats.steps.to_string(),
                r.stats.rejected.to_string(),
                r.stats.evaluations.to_string(),
                format!("{:.3}", r.wall_time),
                r.failure.clone().unwrap_or_default(),
            ]
        }),
    )?;
    Ok(rows)
}
