//! The accuracy-dependence study: whether the paper's results (Table 3 and the severe wear
//! regions of figures 5-6) depend on how accurately the model is integrated (section 5 of
//! `paper.md`).
//!
//! Every Table 3 case (settled, then 6 rotations recorded and split into 3 windows of 2) and
//! the 40-rotation standard wear profile are computed with four integrations: the scene's own
//! converged settings, an ode45-like Dopri5 at its defaults (rtol 1e-3, atol 1e-6, max step
//! 1e-2 s), and RK4 at 1e-5 s and 1e-4 s. A failed run is recorded with its error (time and
//! cause). A paper result *holds* for an integration when every window (or the wear profile)
//! reproduces it: the motion mode, the dominant factor (P-w or s-w), each concordance within
//! the golden tolerance, the three severe wear regions within the golden angle tolerance and
//! the deepest at 180°. A result *appears only under under-resolved integration* when it fails
//! at converged settings but holds for one of the other three.

use super::integration::Integration;
use crate::analysis::concordance::Concordance;
use crate::analysis::regions::wear_regions;
use crate::analysis::Motion;
use crate::io::output::write_rows;
use crate::io::progress::Progress;
use crate::ode::Method;
use crate::paper::cases::{wear_run_with, Case, SteadyMember, CASES};
use crate::paper::figures::output_path;
use crate::paper::golden::{angle_distance, Golden, Table3Golden};
use crate::scene::StepControlSpec;
use crate::scene::{scene_path, SceneFile};
use crate::simulation::{simulate, RunOutput};
use crate::Result;

/// Rotations recorded after settling, split into [`WINDOWS`] windows.
pub const WINDOW_ROTATIONS: u32 = 2;
/// Windows of each Table 3 case.
pub const WINDOWS: u32 = 3;

/// The four integrations of the accuracy study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// The scene's own converged settings.
    Converged,
    /// An ode45-like Dopri5 at its defaults: rtol 1e-3, atol 1e-6, max step 1e-2 s.
    Ode45Defaults,
    /// RK4 at a fixed 1e-5 s.
    Rk4Fine,
    /// RK4 at a fixed 1e-4 s.
    Rk4Coarse,
}

impl Setting {
    /// Every setting, in the order of [`Finding::holds`].
    pub const ALL: [Setting; 4] = [
        Setting::Converged,
        Setting::Ode45Defaults,
        Setting::Rk4Fine,
        Setting::Rk4Coarse,
    ];

    /// Its name in `data/accuracy_dependence.csv`.
    pub fn label(self) -> &'static str {
        match self {
            Setting::Converged => "converged",
            Setting::Ode45Defaults => "ode45-defaults",
            Setting::Rk4Fine => "rk4-1e-5",
            Setting::Rk4Coarse => "rk4-1e-4",
        }
    }

    /// The integration applied to the scene; `None` for the scene's own.
    pub fn integration(self) -> Option<Integration> {
        match self {
            Setting::Converged => None,
            Setting::Ode45Defaults => Some(Integration {
                method: Method::Dopri5,
                rtol: 1e-3,
                atol: 1e-6,
                max_step: 1e-2,
                control: StepControlSpec::I,
            }),
            Setting::Rk4Fine => Some(Integration::rk4(1e-5)),
            Setting::Rk4Coarse => Some(Integration::rk4(1e-4)),
        }
    }
}

/// The four integrations of the accuracy study: (label, `None` for the scene's own).
pub fn accuracy_settings() -> [(&'static str, Option<Integration>); 4] {
    Setting::ALL.map(|s| (s.label(), s.integration()))
}

/// What an accuracy run measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subject {
    /// A Table 3 case: motion and concordances of three recorded windows.
    Steady(Case),
    /// The 40-rotation wear profile of the standard case: its severe regions.
    StandardWear,
}

impl Subject {
    /// Its name in `data/accuracy_dependence.csv`: the case's scene, or `standard-wear`.
    pub fn name(self) -> &'static str {
        match self {
            Subject::Steady(c) => c.scene,
            Subject::StandardWear => "standard-wear",
        }
    }
}

/// What one case gave under one integration.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyRow {
    /// What was run.
    pub case: Subject,
    /// How it was integrated.
    pub setting: Setting,
    /// Motion modes of the windows (Table 3 cases).
    pub modes: Vec<&'static str>,
    /// Dominant factor of each window.
    pub dominance: Vec<&'static str>,
    /// (min, max) of P-w over the windows.
    pub pw: (f64, f64),
    /// (min, max) of s-w over the windows.
    pub sw: (f64, f64),
    /// Angles of the three most prominent wear regions (deg), for the wear case.
    pub region_angles: Vec<f64>,
    /// Wall time of the run (s).
    pub wall_time: f64,
    /// The error (with its time) of a failed run.
    pub failure: Option<String>,
}

/// A number of `data/accuracy_dependence.csv`: 4 decimals, empty for NaN (not measured).
pub fn csv_number(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v:.4}")
    }
}

/// Columns of `data/accuracy_dependence.csv`.
pub const ACCURACY_HEADER: [&str; 11] = [
    "case",
    "setting",
    "motion_modes",
    "dominance",
    "pw_min",
    "pw_max",
    "sw_min",
    "sw_max",
    "region_angles_deg",
    "wall_time_s",
    "failure",
];

impl AccuracyRow {
    /// A row of `subject` under `setting` that measured nothing yet.
    fn empty(case: Subject, setting: Setting) -> AccuracyRow {
        AccuracyRow {
            case,
            setting,
            modes: Vec::new(),
            dominance: Vec::new(),
            pw: (f64::NAN, f64::NAN),
            sw: (f64::NAN, f64::NAN),
            region_angles: Vec::new(),
            wall_time: 0.0,
            failure: None,
        }
    }

    /// A failed run, with its error.
    fn failed(case: Subject, setting: Setting, e: crate::Error) -> AccuracyRow {
        AccuracyRow {
            failure: Some(e.to_string()),
            ..AccuracyRow::empty(case, setting)
        }
    }

    /// Its row of `data/accuracy_dependence.csv` (columns [`ACCURACY_HEADER`]).
    pub fn csv_row(&self) -> Vec<String> {
        let angles: Vec<String> = self
            .region_angles
            .iter()
            .map(|a| format!("{a:.1}"))
            .collect();
        vec![
            self.case.name().to_string(),
            self.setting.label().to_string(),
            self.modes.join("; "),
            self.dominance.join("; "),
            csv_number(self.pw.0),
            csv_number(self.pw.1),
            csv_number(self.sw.0),
            csv_number(self.sw.1),
            angles.join("; "),
            format!("{:.2}", self.wall_time),
            self.failure.clone().unwrap_or_default(),
        ]
    }
}

/// Whether one paper result depends on integration accuracy.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// e.g. `"speed_30rpm motion"`.
    pub result: String,
    /// The paper's value.
    pub paper: String,
    /// Holds for each setting of [`Setting::ALL`], in order.
    pub holds: [bool; 4],
}

impl Finding {
    /// Holds at the scene's converged settings.
    pub fn holds_converged(&self) -> bool {
        self.holds[0]
    }

    /// Fails at converged accuracy but holds for an under-resolved integration.
    pub fn only_under_resolved(&self) -> bool {
        !self.holds[0] && self.holds[1..].iter().any(|&h| h)
    }

    /// Labels of the settings it holds for, `"converged; rk4-1e-5"`.
    pub fn holding(&self) -> String {
        let holding: Vec<&str> = Setting::ALL
            .iter()
            .zip(self.holds)
            .filter(|(_, h)| *h)
            .map(|(s, _)| s.label())
            .collect();
        holding.join("; ")
    }

    /// What it says about the paper's result.
    pub fn verdict(&self) -> &'static str {
        if self.holds_converged() {
            "holds at converged accuracy"
        } else if self.only_under_resolved() {
            "appears only under under-resolved integration"
        } else {
            "not reproduced by any integration"
        }
    }

    /// Its row of `data/accuracy_dependence.csv`: `setting` says which integrations
    /// reproduce the paper, `failure` the verdict.
    pub fn csv_row(&self) -> Vec<String> {
        let mut row = vec![String::new(); ACCURACY_HEADER.len()];
        row[0] = format!("finding: {}", self.result);
        row[1] = format!("holds for: {}", self.holding());
        row[2] = format!("paper: {}", self.paper);
        row[10] = self.verdict().into();
        row
    }
}

/// Result of [`accuracy_dependence`].
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyDependence {
    /// Every run: each Table 3 case, then the standard wear case, under each setting.
    pub rows: Vec<AccuracyRow>,
    /// Whether each paper result holds under each setting.
    pub findings: Vec<Finding>,
}

impl AccuracyDependence {
    /// The run of `case` under `setting`.
    pub fn row(&self, case: Subject, setting: Setting) -> Option<&AccuracyRow> {
        row_of(&self.rows, case, setting)
    }
}

/// The run of `case` under `setting` among `rows`.
fn row_of(rows: &[AccuracyRow], case: Subject, setting: Setting) -> Option<&AccuracyRow> {
    rows.iter().find(|r| r.case == case && r.setting == setting)
}

/// Whether a row reproduces one paper result.
type Check<'a> = dyn Fn(&AccuracyRow) -> bool + 'a;
type MemberCheck<'a> = dyn Fn(&SteadyMember) -> bool + 'a;

/// The paper's Table 3 results of one case as tests of one window's (or one member's) value:
/// a window run reproduces a result when all its windows pass, an ensemble member when it does.
pub(crate) struct Table3Test<'a> {
    paper: &'a Table3Golden,
    tol: f64,
}

impl<'a> Table3Test<'a> {
    /// The tests of `paper` at `golden`'s concordance tolerance.
    pub fn new(paper: &'a Table3Golden, golden: &Golden) -> Self {
        Table3Test {
            paper,
            tol: golden.concordance_tolerance,
        }
    }

    /// The paper's motion mode.
    pub fn motion(&self, mode: &str) -> bool {
        mode == self.paper.motion
    }

    /// The paper's dominant driver.
    pub fn dominance(&self, dominant: &str) -> bool {
        dominant == self.paper.dominant()
    }

    /// A P-w concordance within the tolerance of the paper's.
    pub fn pw(&self, v: f64) -> bool {
        (v - self.paper.pw).abs() <= self.tol
    }

    /// An s-w concordance within the tolerance of the paper's.
    pub fn sw(&self, v: f64) -> bool {
        (v - self.paper.sw).abs() <= self.tol
    }
}

/// How many members of a converged ensemble of one case reproduce one Table 3 result of the
/// findings, checked member by member with the findings' own test.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleCheck {
    /// The result as [`Finding::result`] names it: `"clearance_0.2mm P-w"`.
    pub result: String,
    /// Members reproducing it.
    pub count: usize,
    /// Members checked.
    pub members: usize,
}

/// The Table 3 results of `case` checked in each of `members` (its converged ensemble) with
/// the test the findings apply to each window.
pub fn ensemble_checks(
    case: &Case,
    members: &[SteadyMember],
    golden: &Golden,
) -> Vec<EnsembleCheck> {
    let Some(g) = golden
        .table3
        .list()
        .into_iter()
        .find(|g| g.scene == case.scene)
    else {
        return Vec::new();
    };
    let t = Table3Test::new(g, golden);
    let tests: [(&str, &MemberCheck); 4] = [
        ("motion", &|m| t.motion(m.motion.mode())),
        ("dominance", &|m| t.dominance(m.concordance.dominant())),
        ("P-w", &|m| t.pw(m.concordance.pressure_wear)),
        ("s-w", &|m| t.sw(m.concordance.sliding_wear)),
    ];
    tests
        .into_iter()
        .map(|(what, test)| EnsembleCheck {
            result: format!("{} {what}", case.scene),
            count: members.iter().filter(|m| test(m)).count(),
            members: members.len(),
        })
        .collect()
}

fn min_max(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

/// Settles `case` under `setting`, records 6 rotations and measures each window of 2.
fn windowed_case(case: Case, setting: Setting) -> AccuracyRow {
    let subject = Subject::Steady(case);
    let run = || -> Result<RunOutput> {
        let mut f = SceneFile::read(scene_path(case.scene))?;
        if let Some(i) = setting.integration() {
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
        Err(e) => return AccuracyRow::failed(subject, setting, e),
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
        modes: windows.iter().map(|(m, _)| m.mode()).collect(),
        dominance: windows.iter().map(|(_, c)| c.dominant()).collect(),
        pw: min_max(windows.iter().map(|(_, c)| c.pressure_wear)),
        sw: min_max(windows.iter().map(|(_, c)| c.sliding_wear)),
        wall_time: out.wall_time,
        ..AccuracyRow::empty(subject, setting)
    }
}

/// The standard case's 40-rotation wear profile under `setting`: its three most prominent
/// regions.
fn wear_case(setting: Setting) -> AccuracyRow {
    let subject = Subject::StandardWear;
    match wear_run_with(CASES.standard.scene, 0, |f| {
        if let Some(i) = setting.integration() {
            i.apply(f)
        }
    }) {
        Ok((_, out)) => AccuracyRow {
            region_angles: wear_regions(&out.final_wear[0])
                .iter()
                .take(3)
                .map(|p| p.angle_deg)
                .collect(),
            wall_time: out.wall_time,
            ..AccuracyRow::empty(subject, setting)
        },
        Err(e) => AccuracyRow::failed(subject, setting, e),
    }
}

/// The accuracy-dependence study (see the module documentation); `progress` is told each run.
/// Writes `data/accuracy_dependence.csv`.
pub fn accuracy_dependence(progress: &dyn Progress) -> Result<AccuracyDependence> {
    let golden = Golden::load()?;
    let total = Some((Setting::ALL.len() * (CASES.list().len() + 1)) as u64);
    let mut rows = Vec::new();
    let mut run = |subject: &str, setting: Setting, row: &dyn Fn() -> AccuracyRow| {
        progress.observe(rows.len() as u64, total);
        progress.stage(&format!("{subject} {}", setting.label()));
        rows.push(row());
    };
    for case in CASES.list() {
        for setting in Setting::ALL {
            run(case.scene, setting, &|| windowed_case(*case, setting));
        }
    }
    for setting in Setting::ALL {
        run(Subject::StandardWear.name(), setting, &|| {
            wear_case(setting)
        });
    }
    progress.observe(rows.len() as u64, total);
    let mut findings = Vec::new();
    let tol = golden.concordance_tolerance;
    let holds = |case: Subject, test: &Check| -> [bool; 4] {
        Setting::ALL.map(|setting| {
            row_of(&rows, case, setting).is_some_and(|r| r.failure.is_none() && test(r))
        })
    };
    for &(case, g) in CASES.zip(&golden.table3).list() {
        let t = Table3Test::new(g, &golden);
        let checks: [(&str, String, &Check); 4] = [
            ("motion", g.motion.clone(), &|r| {
                r.modes.iter().all(|m| t.motion(m))
            }),
            ("dominance", g.dominant().to_string(), &|r| {
                r.dominance.iter().all(|d| t.dominance(d))
            }),
            ("P-w", format!("{:.4} ± {tol}", g.pw), &|r| {
                t.pw(r.pw.0) && t.pw(r.pw.1)
            }),
            ("s-w", format!("{:.4} ± {tol}", g.sw), &|r| {
                t.sw(r.sw.0) && t.sw(r.sw.1)
            }),
        ];
        for (what, paper, test) in checks {
            findings.push(Finding {
                result: format!("{} {what}", case.scene),
                paper,
                holds: holds(Subject::Steady(*case), test),
            });
        }
    }
    let claim = &golden.standard_wear;
    let near = |a: f64, b: f64| angle_distance(a, b) <= claim.angle_tolerance_deg;
    findings.push(Finding {
        result: "standard wear regions".into(),
        paper: format!(
            "{} deg",
            claim
                .peak_angles_deg
                .iter()
                .map(|a| a.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        holds: holds(Subject::StandardWear, &|r| {
            claim
                .peak_angles_deg
                .iter()
                .all(|&p| r.region_angles.iter().any(|&a| near(a, p)))
        }),
    });
    findings.push(Finding {
        result: "standard deepest wear region".into(),
        paper: format!("{} deg", claim.largest_peak_deg),
        holds: holds(Subject::StandardWear, &|r| {
            r.region_angles
                .first()
                .is_some_and(|&a| near(a, claim.largest_peak_deg))
        }),
    });
    write_rows(
        &output_path("data", "accuracy_dependence.csv"),
        &ACCURACY_HEADER,
        rows.iter()
            .map(AccuracyRow::csv_row)
            .chain(findings.iter().map(Finding::csv_row)),
    )?;
    Ok(AccuracyDependence { rows, findings })
}
