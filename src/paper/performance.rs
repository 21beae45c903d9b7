//! Run-time measurements for the report.
//!
//! [`scaling_study`] measures the wall time of the standard scene's simulation (the run alone,
//! without loading and assembly) against the number of simulated crank rotations (1-40, the
//! coupled wear run of figure 6) and against the radial clearance (0.005-0.5 mm, a few rotations
//! each without wear), with the integrator's work counters; it writes `data/scaling.csv` and
//! `figures/scaling.png`. Wall times depend on the machine and its load: the counters
//! (steps, rejected steps, right-hand-side evaluations) are the reproducible part.
//! [`step_limit_study`], run with it, measures what sets the step of the 40-rotation run
//! (`data/step_limit.csv`).
//!
//! [`benchmark_summary`] collects criterion's estimates of `cargo bench` into
//! `data/benchmarks.csv`.

use crate::io::output::{write_csv, write_rows};
use crate::io::plot::{render, Axes, Series, Style};
use crate::mechanism::eigenvalues_by_modulus;
use crate::ode::Stats;
use crate::paper::cases::CASES;
use crate::paper::figures::output_path;
use crate::paper::provenance::{self, Inputs};
use crate::scene::{scene_path, SceneFile};
use crate::simulation::{simulate, Simulation};
use crate::{Error, Result};
use nalgebra::Complex;
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// Run-time targets of the hot paths: criterion bench and its budget (ns). The 40-rotation
/// run and its 16-member ensemble have the budgets users asked for: 0.1 s for the whole
/// `jointwear run` process (`process/run_standard_40` times it as a user starts it; the
/// run alone, `wear_run/standard_40`, has the same budget) and 0.6 s for the ensemble on 2 cores
/// (issue 22; it was 1 s before).
pub const TARGETS: [(&str, f64); 6] = [
    ("contact_force/hybrid", 20.0),
    ("contact_force/lankarani-nikravesh", 20.0),
    ("rhs/standard", 300.0),
    ("wear_run/standard_40", 0.1e9),
    ("ensemble/standard_40x16", 0.6e9),
    ("process/run_standard_40", 0.1e9),
];
/// Budget of the whole default `report` run on 2 cores (s; issue 22, 60 s before).
pub const REPORT_BUDGET_S: f64 = 40.0;

/// Rotation counts of the rotation sweep.
pub const ROTATIONS: [u32; 6] = [1, 2, 5, 10, 20, 40];
/// Radial clearances (mm) of the clearance sweep.
pub const CLEARANCES_MM: [f64; 5] = [0.005, 0.02, 0.1, 0.2, 0.5];
/// Rotations simulated per clearance.
pub const CLEARANCE_ROTATIONS: u32 = 3;

/// Which parameter a [`ScalingPoint`] varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// Simulated rotations of the coupled wear run.
    Rotations,
    /// Radial clearance (mm), no wear.
    Clearance,
}

impl Sweep {
    /// The name used in the `kind` column.
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Rotations => "rotations",
            Sweep::Clearance => "clearance_mm",
        }
    }
}

/// One measured run.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingPoint {
    /// Which sweep it belongs to.
    pub kind: Sweep,
    /// Rotations or clearance (mm), per `kind`.
    pub value: f64,
    /// Rotations simulated.
    pub rotations: u32,
    /// Wall time of the run (s).
    pub wall_time: f64,
    /// The integrator's work: steps, rejections by cause, evaluations.
    pub stats: Stats,
}

/// The scaling study's measurements, in sweep order; `Display` prints them as a table.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    /// Every measured run.
    pub points: Vec<ScalingPoint>,
}

impl Scaling {
    fn sweep(&self, kind: Sweep) -> impl Iterator<Item = &ScalingPoint> {
        self.points.iter().filter(move |p| p.kind == kind)
    }
}

impl fmt::Display for Scaling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:>12} {:>7} {:>9} {:>11} {:>8} {:>8} {:>11}  rejected after increase/repeated/restart/other",
            "kind", "value", "rotations", "wall (s)", "steps", "rejected", "evaluations"
        )?;
        for p in &self.points {
            let (s, by) = (p.stats, p.stats.rejections);
            writeln!(
                f,
                "{:>12} {:>7} {:>9} {:>11.4} {:>8} {:>8} {:>11}  {}/{}/{}/{}",
                p.kind.name(),
                p.value,
                p.rotations,
                p.wall_time,
                s.steps,
                s.rejected,
                s.evaluations,
                by.after_increase,
                by.repeated,
                by.after_restart,
                by.other
            )?;
        }
        Ok(())
    }
}

/// The scaling study's table under `data/`.
pub const SCALING_FILE: &str = "scaling.csv";

/// The scaling study's figure under `figures/`.
const SCALING_FIGURE: &str = "scaling.png";

/// What produced `data/scaling.csv` and `data/step_limit.csv` ([`provenance`]): the standard
/// scene, the rotations and clearances run and the step-limit sampling.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[SCALING_FILE, STEP_LIMIT_FILE],
    figures: &[SCALING_FIGURE],
    command: "cargo run --release --bin scaling",
    rerun_by_all: false,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            vec![CASES.standard.scene],
            false,
            (
                ROTATIONS,
                CLEARANCES_MM,
                CLEARANCE_ROTATIONS,
                STEP_LIMIT_EVERY,
            ),
        )
    },
};

/// Runs the scaling study and writes `data/scaling.csv`, `figures/scaling.png` and the step
/// limit's `data/step_limit.csv`, with their record ([`PROVENANCE`]).
pub fn scaling_study() -> Result<Scaling> {
    provenance::recorded(&PROVENANCE, &[], study)
}

/// The study itself ([`scaling_study`]).
fn study() -> Result<Scaling> {
    let standard = SceneFile::read(scene_path(CASES.standard.scene))?;
    let mut points = Vec::new();
    let mut measure = |kind: Sweep, value: f64, file: &SceneFile| -> Result<()> {
        let out = simulate(&file.build()?)?;
        points.push(ScalingPoint {
            kind,
            value,
            rotations: file.run.rotations,
            wall_time: out.wall_time,
            stats: out.stats,
        });
        Ok(())
    };
    for rotations in ROTATIONS {
        let mut f = standard.clone();
        f.run.rotations = rotations;
        f.run.record_rotations = 0;
        f.run.wear_snapshots.retain(|&r| r <= rotations);
        measure(Sweep::Rotations, rotations as f64, &f)?;
    }
    for clearance in CLEARANCES_MM {
        let mut f = standard.clone();
        f.run.rotations = CLEARANCE_ROTATIONS;
        f.run.record_rotations = 0;
        f.run.wear_snapshots.clear();
        for c in &mut f.clearance {
            c.clearance_mm = clearance;
            c.wear = None;
        }
        measure(Sweep::Clearance, clearance, &f)?;
    }
    let scaling = Scaling { points };
    write_scaling(&scaling)?;
    step_limit_study(&standard)?;
    Ok(scaling)
}

/// Accepted steps between two samples of [`step_limit_study`].
pub const STEP_LIMIT_EVERY: u64 = 50;

/// What limits the integrator's step on the standard scene's 40-rotation run (no time
/// series): at every [`STEP_LIMIT_EVERY`]th accepted step, the eigenvalues λᵢ of the
/// right-hand side's Jacobian ([`crate::mechanism::Mechanism::rhs_jacobian`]), the step h
/// just taken (as cut at onsets and rotation ends), and for each λᵢ in the left half-plane
/// `h|λᵢ|` over the method's stability boundary along λᵢ's direction
/// ([`crate::ode::Method::stability_boundary`]); the row keeps the binding one, the largest
/// such fraction. Near 1 the step is held by stability (an implicit method could take longer
/// ones), well below 1 by accuracy. A sample whose Jacobian has no eigenvalue in the left
/// half-plane or cannot be decomposed keeps NaN. Writes `data/step_limit.csv`, one row per
/// sample.
pub fn step_limit_study(standard: &SceneFile) -> Result<()> {
    let mut file = standard.clone();
    file.run.record_rotations = 0;
    let scene = file.build()?;
    let method = scene.run.method;
    let mut sim = Simulation::start(&scene)?;
    let mut ws = scene.mechanism.workspace();
    let mut columns: [Vec<f64>; 7] = Default::default();
    let mut steps = 0u64;
    while !sim.is_finished() {
        let start = sim.time();
        sim.advance_step()?;
        steps += 1;
        if !steps.is_multiple_of(STEP_LIMIT_EVERY) {
            continue;
        }
        let (t, y) = (sim.time(), sim.y());
        let step = t - start;
        let jacobian = scene.mechanism.rhs_jacobian(sim.state(), &mut ws, t, &y)?;
        // An eigenvalue with h|λ| < 1e-3 cannot bind: its fraction is at most about 1e-3 (the
        // smallest boundary in the left half-plane is about 1 for Dopri5, near the imaginary
        // axis), so its boundary is not searched.
        let binding = (eigenvalues_by_modulus(&jacobian)
            .unwrap_or_default()
            .into_iter())
        .filter(|l| l.re < 0.0 && step * l.norm() >= 1e-3)
        .filter_map(|l| {
            let boundary = method.stability_boundary(l.arg())?;
            Some((step * l.norm() / boundary, l, boundary))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
        let (fraction, lambda, boundary) =
            binding.unwrap_or((f64::NAN, Complex::new(f64::NAN, f64::NAN), f64::NAN));
        let penetration = (0..scene.mechanism.clearance_joints.len())
            .map(|k| scene.mechanism.penetration(sim.state(), k, &y))
            .fold(f64::NEG_INFINITY, f64::max);
        let row = [
            t,
            step,
            lambda.re,
            lambda.im,
            boundary,
            fraction,
            penetration,
        ];
        for (c, v) in columns.iter_mut().zip(row) {
            c.push(v);
        }
    }
    let columns: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
    write_csv(
        &output_path("data", STEP_LIMIT_FILE),
        &STEP_LIMIT_HEADER,
        &columns,
    )
}

/// File of [`step_limit_study`] under `data/`.
pub const STEP_LIMIT_FILE: &str = "step_limit.csv";

/// Columns of [`STEP_LIMIT_FILE`]: time, step, the binding eigenvalue, the stability boundary
/// along it, `h|λ|` over that boundary, and the largest penetration of the clearance joints.
pub const STEP_LIMIT_HEADER: [&str; 7] = [
    "t_s",
    "step_s",
    "lambda_re_per_s",
    "lambda_im_per_s",
    "stability_boundary",
    "fraction_of_stable_step",
    "max_penetration_m",
];

fn write_scaling(s: &Scaling) -> Result<()> {
    let column = |get: fn(&ScalingPoint) -> f64| s.points.iter().map(get).collect::<Vec<_>>();
    let labels: Vec<&str> = s.points.iter().map(|p| p.kind.name()).collect();
    write_rows(
        &output_path("data", SCALING_FILE),
        &[
            "kind",
            "value",
            "rotations",
            "wall_time_s",
            "steps",
            "rejected",
            "evaluations",
            "rejected_after_increase",
            "rejected_repeated",
            "rejected_after_restart",
            "rejected_other",
            "rejected_failed",
        ],
        labelled_rows(
            &labels,
            &[
                &column(|p| p.value),
                &column(|p| p.rotations as f64),
                &column(|p| p.wall_time),
                &column(|p| p.stats.steps as f64),
                &column(|p| p.stats.rejected as f64),
                &column(|p| p.stats.evaluations as f64),
                &column(|p| p.stats.rejections.after_increase as f64),
                &column(|p| p.stats.rejections.repeated as f64),
                &column(|p| p.stats.rejections.after_restart as f64),
                &column(|p| p.stats.rejections.other as f64),
                &column(|p| p.stats.rejections.failed as f64),
            ],
        ),
    )?;
    let xy = |kind: Sweep, y: fn(&ScalingPoint) -> f64| -> (Vec<f64>, Vec<f64>) {
        s.sweep(kind).map(|p| (p.value, y(p))).unzip()
    };
    let (rot, rot_time) = xy(Sweep::Rotations, |p| p.wall_time);
    let (_, rot_evals) = xy(Sweep::Rotations, |p| p.stats.evaluations as f64 * 1e-6);
    let (clr, clr_time) = xy(Sweep::Clearance, |p| p.wall_time / p.rotations as f64);
    let (_, clr_evals) = xy(Sweep::Clearance, |p| {
        p.stats.evaluations as f64 * 1e-3 / p.rotations as f64
    });
    render(
        &output_path("figures", SCALING_FIGURE),
        &[
            Axes {
                y2_label: Some("right-hand-side evaluations (millions)".into()),
                ..Axes::new(
                    "Coupled wear run of the standard scene",
                    "crank rotations",
                    "wall time (s)",
                    vec![
                        Series::new("wall time", &rot, &rot_time, Style::Line),
                        Series::new("evaluations", &rot, &rot_evals, Style::LineOnSecondaryAxis),
                    ],
                )
            },
            Axes {
                y2_label: Some("evaluations per rotation (thousands)".into()),
                ..Axes::new(
                    format!(
                        "Per rotation against clearance (no wear, {CLEARANCE_ROTATIONS} rotations)"
                    ),
                    "radial clearance (mm)",
                    "wall time per rotation (s)",
                    vec![
                        Series::new("wall time", &clr, &clr_time, Style::Line),
                        Series::new("evaluations", &clr, &clr_evals, Style::LineOnSecondaryAxis),
                    ],
                )
            },
        ],
    )
}

/// Rows of a CSV whose first column is a text label and the others numbers (written like
/// [`crate::io::output::write_csv`] does, in the shortest form that reads back identically).
fn labelled_rows<'a>(
    labels: &'a [&str],
    columns: &'a [&[f64]],
) -> impl Iterator<Item = Vec<String>> + 'a {
    labels.iter().enumerate().map(move |(i, label)| {
        std::iter::once(label.to_string())
            .chain(columns.iter().map(|c| crate::io::output::number(c[i])))
            .collect()
    })
}

/// The trimmed standard output of a command, or `unknown`.
pub fn command_output(program: &str, args: &[&str]) -> String {
    std::process::Command::new(program)
        .args(args)
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The CPU model named in `/proc/cpuinfo`, or `unknown`.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// The machine a measurement ran on, as the report and `data/benchmarks.csv` name it: the CPU
/// model and the threads available to this process.
pub fn machine() -> String {
    format!(
        "{} ({} threads)",
        cpu_model(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    )
}

/// Criterion's estimate of one bench (ns).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchEstimate {
    /// `group/bench`, as criterion names it.
    pub bench: String,
    /// Median (ns).
    pub median: f64,
    /// 95 % confidence interval of the median: lower end.
    pub ci_low: f64,
    /// 95 % confidence interval of the median: upper end.
    pub ci_high: f64,
    /// Median absolute deviation.
    pub mad: f64,
    /// When criterion measured it: its estimates' modification time, `YYYY-MM-DD HH:MM UTC`.
    pub measured: String,
}

#[derive(Deserialize)]
struct Estimates {
    median: Estimate,
    median_abs_dev: Estimate,
}

#[derive(Deserialize)]
struct Estimate {
    point_estimate: f64,
    confidence_interval: Interval,
}

#[derive(Deserialize)]
struct Interval {
    lower_bound: f64,
    upper_bound: f64,
}

/// Where criterion keeps its results, as criterion chooses it: `$CRITERION_HOME`, else
/// `$CARGO_TARGET_DIR/criterion`, else `target/criterion` under the crate root.
pub fn criterion_dir() -> PathBuf {
    let env = |name| std::env::var_os(name).map(PathBuf::from);
    env("CRITERION_HOME").unwrap_or_else(|| {
        env("CARGO_TARGET_DIR")
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target"))
            .join("criterion")
    })
}

/// Reads `<dir>/<group>/<bench>/new/estimates.json` of every bench, sorted by name, and
/// writes them to `data/benchmarks.csv`. Errors if `dir` holds no results.
pub fn benchmark_summary(dir: &Path) -> Result<Vec<BenchEstimate>> {
    let io = |path: &Path, source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let subdirs = |d: &Path| -> Result<Vec<PathBuf>> {
        let mut v = Vec::new();
        for entry in std::fs::read_dir(d).map_err(|e| io(d, e))? {
            let path = entry.map_err(|e| io(d, e))?.path();
            if path.is_dir() && path.file_name().is_some_and(|n| n != "report") {
                v.push(path);
            }
        }
        v.sort();
        Ok(v)
    };
    let missing = || {
        Error::invalid(
            "criterion results",
            format!("none in {}", dir.display()),
            "`cargo bench` run first (with the same CARGO_TARGET_DIR)",
        )
    };
    if !dir.is_dir() {
        return Err(missing());
    }
    let mut results = Vec::new();
    for group in subdirs(dir)? {
        for bench in subdirs(&group)? {
            let path = bench.join("new").join("estimates.json");
            if !path.is_file() {
                continue;
            }
            let text = std::fs::read_to_string(&path).map_err(|e| io(&path, e))?;
            let e: Estimates = serde_json::from_str(&text).map_err(|e| Error::Parse {
                path: path.clone(),
                message: e.to_string(),
            })?;
            let name = |p: &Path| {
                p.file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            };
            results.push(BenchEstimate {
                bench: format!("{}/{}", name(&group), name(&bench)),
                median: e.median.point_estimate,
                ci_low: e.median.confidence_interval.lower_bound,
                ci_high: e.median.confidence_interval.upper_bound,
                mad: e.median_abs_dev.point_estimate,
                measured: modified_utc(&path),
            });
        }
    }
    if results.is_empty() {
        return Err(missing());
    }
    let machine = machine();
    // Medians of different days or hosts are not comparable (paper.md section 7): each row says
    // when and where it was measured. `bench_summary` runs where `cargo bench` ran.
    let number = crate::io::output::number;
    let rows = results.iter().map(|r| {
        vec![
            r.bench.clone(),
            number(r.median),
            number(r.ci_low),
            number(r.ci_high),
            number(r.mad),
            r.measured.clone(),
            machine.clone(),
        ]
    });
    write_rows(
        &output_path("data", "benchmarks.csv"),
        &BENCHMARK_COLUMNS,
        rows,
    )?;
    Ok(results)
}

/// The columns of `data/benchmarks.csv`.
pub const BENCHMARK_COLUMNS: [&str; 7] = [
    "bench",
    "median_ns",
    "ci_low_ns",
    "ci_high_ns",
    "mad_ns",
    "measured_utc",
    "machine",
];

/// The modification time of `path` in UTC to the minute, or `unknown`.
fn modified_utc(path: &Path) -> String {
    let path = path.to_string_lossy();
    command_output("date", &["-u", "-r", &path, "+%Y-%m-%d %H:%M UTC"])
}
