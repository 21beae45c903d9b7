//! Parameter sweeps: a scene varied over the cartesian product of `--set KEY=V1,V2,..`
//! assignments, one summary row per case, shardable across independent jobs.
//!
//! * Keys are dotted paths into the scene's TOML document ([`crate::scene::set_dotted`]);
//!   values are TOML values (`0.02`, `"rk4"`, `[0.0, -9.81]`; a bare word is a string).
//! * Case `k` is numbered in the order of the product, the last key varying fastest; shard
//!   `I/N` (1-based) runs the cases with `k mod N = I − 1`, a slice that depends only on the
//!   assignments, so independent jobs of a batch array cover every case exactly once and
//!   [`crate::sweep::file::merge`] puts their files back in case order.
//! * Keys are canonical (an array index as its number) and each key is given once; the case
//!   count is at most [`MAX_CASES`].
//! * A row names the window of its recorded quantities ([`RECORD_COLUMNS`]: the rotations
//!   recorded and their sampling interval) before the joints' columns.
//! * Every value of every key is validated before any case runs (in the case that varies it
//!   alone): a bad value stops the sweep as invalid input. Cases are built as they run, so a
//!   large sweep starts at once in bounded memory; a case that fails to build (a combination
//!   of valid values that is not) or while running gets its error in the `error` column; the
//!   others go on.

pub mod file;

use crate::analysis::states::STATE_COLUMNS;
use crate::io::progress::{Cancellation, Progress};
use crate::scene::{reversal_note, set_dotted, SceneFile};
use crate::simulation::ensemble::EnsembleSettings;
use crate::simulation::simulate_with_progress;
use crate::simulation::summary::{
    joint_statistics, summarize, JointStatistics, JointSummary, JOINT_COLUMNS, SCALARS,
};
use crate::simulation::Scene;
use crate::sweep::file::{fingerprint, salted};
use crate::{Error, Result};
use rayon::prelude::*;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// One `--set KEY=V1,V2,..` argument.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    /// Dotted key into the scene document.
    pub key: String,
    /// The values as written.
    pub values: Vec<String>,
}

impl Assignment {
    /// Parses `KEY=V1,V2,..`; commas inside brackets or quotes belong to the value.
    pub fn parse(arg: &str) -> Result<Assignment> {
        let bad = |why: &str| Error::invalid("--set", arg, format!("KEY=VALUE[,VALUE..] ({why})"));
        let (key, list) = arg.split_once('=').ok_or_else(|| bad("no `=`"))?;
        let key = key.trim();
        if key.is_empty() || key.split('.').any(str::is_empty) {
            return Err(bad("empty key or key part"));
        }
        let mut values = Vec::new();
        let (mut depth, mut quoted, mut start) = (0i32, false, 0);
        for (i, ch) in list.char_indices() {
            match ch {
                '"' => quoted = !quoted,
                '[' | '{' if !quoted => depth += 1,
                ']' | '}' if !quoted => depth -= 1,
                ',' if !quoted && depth == 0 => {
                    values.push(list[start..i].trim().to_string());
                    start = i + 1;
                }
                _ => {}
            }
        }
        values.push(list[start..].trim().to_string());
        if values.iter().any(String::is_empty) {
            return Err(bad("empty value"));
        }
        Ok(Assignment {
            key: key.to_string(),
            values,
        })
    }
}

use crate::scene::variant::canonical_key;
pub use crate::scene::variant::parse_value;

/// Shard `index` of `count` (1-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard, 1-based.
    pub index: usize,
    /// Shards in all.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Parses `I/N` with 1 ≤ I ≤ N.
    pub fn parse(arg: &str) -> Result<Shard> {
        let bad = || Error::invalid("--shard", arg, "I/N with integers 1 <= I <= N");
        let (i, n) = arg.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether case `case` belongs to this shard.
    pub fn contains(&self, case: usize) -> bool {
        case % self.count == self.index - 1
    }
}

/// Why a sweep refuses `run.record_rotations = 0`: its row reports the recorded rotations. (It
/// used to record one rotation instead, silently, beside a `run.record_rotations` column of 0.)
pub const NO_RECORDED_ROTATIONS: &str = "at least 1 in a sweep: a sweep's row reports the \
    largest force and penetration, the motion mode, contact fraction and impacts of the \
    recorded rotations, which a run recording none does not have (set \
    run.record_rotations=1 or more)";

/// Most cases a sweep may have: its rows, each a run, would take years on any machine long
/// before the count could overflow.
pub const MAX_CASES: usize = 1_000_000;

/// Number of cases of the product (1 without assignments), refused beyond [`MAX_CASES`] with
/// the product spelled out; computed with checked multiplication, so it never wraps.
pub fn case_count(sets: &[Assignment]) -> Result<usize> {
    let count = (sets.iter()).try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
    match count {
        Some(n) if n <= MAX_CASES => Ok(n),
        _ => {
            let factors: Vec<String> = sets.iter().map(|a| a.values.len().to_string()).collect();
            let product = count.map_or("2^64 or more".into(), |n| n.to_string());
            Err(Error::invalid(
                "--set",
                format!("{} = {product} cases", factors.join(" x ")),
                format!("at most {MAX_CASES} cases"),
            ))
        }
    }
}

/// Cases of `total` that shard `shard` owns (case k belongs to shard (k mod N) + 1).
pub fn shard_cases(total: usize, shard: Shard) -> usize {
    match total.checked_sub(shard.index) {
        Some(rest) => rest / shard.count + 1,
        None => 0,
    }
}

/// The value of each assignment in case `case` (last key varying fastest).
pub fn case_values(sets: &[Assignment], case: usize) -> Vec<&str> {
    let mut rest = case;
    let mut values: Vec<&str> = sets
        .iter()
        .rev()
        .map(|a| {
            let v = &a.values[rest % a.values.len()];
            rest /= a.values.len();
            v.as_str()
        })
        .collect();
    values.reverse();
    values
}

/// `e` of case `case` (with `values` for the keys of `sets`): a bad value or scene names the
/// case and its assignments, as the `--set` lists spell them.
fn in_case(e: Error, case: usize, sets: &[Assignment], values: &[&str]) -> Error {
    let assigned: Vec<String> = (sets.iter().zip(values))
        .map(|(a, v)| format!("{}={v}", a.key))
        .collect();
    e.in_context(&format!("in case {case}: {}", assigned.join(", ")))
}

/// The scene document `doc` (read from `path`) with `values` assigned to the keys of `sets`,
/// built as a sweep's case ([`SceneFile::build_for`]: it needs recorded rotations).
pub fn vary(doc: &toml::Value, path: &Path, sets: &[Assignment], values: &[&str]) -> Result<Scene> {
    let mut doc = doc.clone();
    for (a, v) in sets.iter().zip(values) {
        set_dotted(&mut doc, &a.key, parse_value(v))?;
    }
    SceneFile::from_document(doc, path)?.build_for(true)
}

/// The columns of a sweep row that name the window of its `recorded` quantities (each joint's
/// largest recorded force and penetration, motion mode, contact fraction and impacts per
/// rotation): `record_rotations`, the last rotations recorded, and `record_interval_s`, the
/// grid they were sampled on (s). A recorded maximum is the largest sample: the standard
/// scene's largest contact force of its first rotation reads 3223 N sampled every 1e-5 s and
/// 497 N every 8e-4 s (of its last two of 40, 671 N and 600 N).
/// After the set values (and an ensemble's `members`), before the joints' columns.
pub const RECORD_COLUMNS: [&str; 2] = ["record_rotations", "record_interval_s"];

/// The recorded window of a case's run (every member's, in an ensemble): the values of
/// [`RECORD_COLUMNS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recorded {
    /// Rotations recorded, the last of the run (`run.record_rotations`).
    pub rotations: u32,
    /// Sampling interval of the recording (s; `run.record_interval_s`).
    pub interval_s: f64,
}

impl Recorded {
    /// The recorded window of a run of `scene`.
    pub fn of(scene: &Scene) -> Recorded {
        Recorded {
            rotations: scene.run.record_rotations,
            interval_s: scene.run.record_interval,
        }
    }

    /// The [`RECORD_COLUMNS`] cells: the rotations, and the interval as
    /// [`number_or_empty`](crate::io::output::number_or_empty) writes it.
    pub fn cells(&self) -> [String; 2] {
        let interval = crate::io::output::number_or_empty(self.interval_s);
        [self.rotations.to_string(), interval]
    }
}

/// Header of a sweep CSV.
pub fn header(sets: &[Assignment], joints: &[String]) -> Vec<String> {
    let mut h = vec!["case".to_string()];
    h.extend(sets.iter().map(|a| a.key.clone()));
    h.extend(RECORD_COLUMNS.map(String::from));
    for j in joints {
        h.extend(JOINT_COLUMNS.iter().map(|c| format!("{j}.{c}")));
    }
    h.extend(["wall_time_s".to_string(), "error".to_string()]);
    h
}

/// Header of a sweep CSV whose cases run as ensembles: after the set values the member count
/// and the recorded window ([`RECORD_COLUMNS`]), then per joint and scalar of [`JointSummary::scalars`] [`ENSEMBLE_COLUMNS`]: the members
/// where it is defined, its mean and sd, and the states the members fall into (a pooled mean
/// of two states is no member's value).
pub fn ensemble_header(sets: &[Assignment], joints: &[String]) -> Vec<String> {
    let mut h = vec!["case".to_string()];
    h.extend(sets.iter().map(|a| a.key.clone()));
    h.push("members".into());
    h.extend(RECORD_COLUMNS.map(String::from));
    for j in joints {
        for name in SCALARS {
            h.extend(ENSEMBLE_COLUMNS.iter().map(|c| format!("{j}.{name}.{c}")));
        }
    }
    h.extend(["wall_time_s".to_string(), "error".to_string()]);
    h
}

/// The columns of each scalar of an ensemble case ([`ensemble_header`]): `n` (members with a
/// finite value), `mean`, `sd`, then [`STATE_COLUMNS`].
pub const ENSEMBLE_COLUMNS: [&str; 10] = [
    "n",
    "mean",
    "sd",
    STATE_COLUMNS[0],
    STATE_COLUMNS[1],
    STATE_COLUMNS[2],
    STATE_COLUMNS[3],
    STATE_COLUMNS[4],
    STATE_COLUMNS[5],
    STATE_COLUMNS[6],
];

/// What a case measured: one run's joint summaries, or an ensemble's joint statistics.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// One run.
    Run(Vec<JointSummary>),
    /// An ensemble of this many members.
    Ensemble(usize, Vec<JointStatistics>),
}

/// One case's outcome.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// Case number in the whole sweep.
    pub case: usize,
    /// The set values of the case, as written.
    pub values: Vec<String>,
    /// What the case measured, its recorded window and the wall time, or the error of the run.
    pub outcome: std::result::Result<(Outcome, Recorded, f64), String>,
}

impl CaseResult {
    /// The CSV record under the sweep's header, which has `cells` columns between the set
    /// values and the wall time ([`Sweep::cells`]).
    pub fn record(&self, cells: usize) -> Vec<String> {
        let mut r = vec![self.case.to_string()];
        r.extend(self.values.iter().cloned());
        let number = crate::io::output::number_or_empty;
        match &self.outcome {
            Ok((Outcome::Ensemble(members, stats), recorded, wall)) => {
                r.push(members.to_string());
                r.extend(recorded.cells());
                for j in stats {
                    for (_, states) in &j.quantities {
                        let d = &states.pooled;
                        r.extend([d.n.to_string(), number(d.mean), number(d.sd)]);
                        r.extend(states.cells(number));
                    }
                }
                r.extend([number(*wall), String::new()]);
            }
            Ok((Outcome::Run(summaries), recorded, wall)) => {
                r.extend(recorded.cells());
                r.extend(summaries.iter().flat_map(JointSummary::cells));
                r.extend([number(*wall), String::new()]);
            }
            Err(e) => {
                r.extend(std::iter::repeat_n(String::new(), cells + 1));
                r.push(e.clone());
            }
        }
        r
    }
}

/// A sweep ready to run: its assignments checked, every value of every key validated, and
/// the shard's cases built one at a time as they run.
pub struct Sweep {
    /// The `--set` assignments, keys canonical ([`canonical_sets`]).
    pub sets: Vec<Assignment>,
    /// Clearance joint names (identical in every case).
    pub joints: Vec<String>,
    /// The sweep definition's fingerprint ([`crate::sweep::file::fingerprint`]).
    pub fingerprint: String,
    /// The part of the sweep this one runs.
    pub shard: Shard,
    /// Cases of the whole sweep ([`case_count`]).
    pub total: usize,
    /// Run every case as an ensemble of this size and seed.
    pub ensemble: Option<EnsembleSettings>,
    doc: toml::Value,
    path: PathBuf,
    /// Cases of the shard not to run (a resumed sweep's finished ones).
    skipped: HashSet<usize>,
    /// A note for each swept value that turns the driver the other way than the scene
    /// ([`reversal_note`]), for the caller to show where its user sees it: the program on
    /// stderr, Python on `sys.stderr` (a notebook's, which a write to the process's stderr
    /// does not reach).
    pub notes: Vec<String>,
}

impl Sweep {
    /// The sweep of `shard` of the scene file at `path` varied by `sets` ([`Sweep::from_document`]).
    pub fn new(path: &Path, sets: Vec<Assignment>, shard: Shard) -> Result<Sweep> {
        Sweep::from_document(&SceneFile::read_document(path)?, path, sets, shard)
    }

    /// The sweep of `shard` of a scene document (with `extends` resolved); `path` names it in
    /// messages. Keys are made canonical and a key given twice refused ([`canonical_sets`]),
    /// the case count bounded ([`case_count`]), and every value of every key validated in the
    /// case that varies it alone (the other keys at their first value): a bad value stops the
    /// sweep as invalid input before any case runs, in every shard alike. The product is not
    /// built: each case is built when it runs ([`Sweep::run`]), and one whose combination of
    /// values fails to build gets its error in the `error` column.
    pub fn from_document(
        doc: &toml::Value,
        path: &Path,
        sets: Vec<Assignment>,
        shard: Shard,
    ) -> Result<Sweep> {
        let sets = canonical_sets(doc, sets)?;
        let total = case_count(&sets)?;
        let notes = (sets.iter())
            .flat_map(|a| a.values.iter().map(move |v| (&a.key, v)))
            .filter_map(|(key, v)| reversal_note(doc, key, &parse_value(v)))
            .collect();
        let mut sweep = Sweep {
            notes,
            fingerprint: fingerprint(doc, &sets),
            total,
            sets,
            joints: Vec::new(),
            shard,
            ensemble: None,
            doc: doc.clone(),
            path: path.to_path_buf(),
            skipped: HashSet::new(),
        };
        sweep.joints = joint_names(&sweep.build(0)?);
        // Case k's value of key i is digit i of k in the mixed radix of the value counts.
        let mut stride = 1;
        for a in sweep.sets.iter().rev() {
            for j in 1..a.values.len() {
                sweep.build(j * stride)?;
            }
            stride *= a.values.len();
        }
        Ok(sweep)
    }

    /// Case `case` built and checked ([`vary`]): at least one rotation recorded
    /// ([`NO_RECORDED_ROTATIONS`]), its loop closed, the sweep's clearance joints.
    fn build(&self, case: usize) -> Result<Scene> {
        let values = case_values(&self.sets, case);
        let in_this = |e| in_case(e, case, &self.sets, &values);
        let scene = vary(&self.doc, &self.path, &self.sets, &values).map_err(in_this)?;
        if scene.run.record_rotations == 0 {
            return Err(in_this(Error::invalid(
                "run.record_rotations",
                0,
                NO_RECORDED_ROTATIONS,
            )));
        }
        scene.mechanism.assemble(&scene.guess).map_err(in_this)?;
        let names = joint_names(&scene);
        if !self.joints.is_empty() && names != self.joints {
            return Err(Error::invalid(
                "--set",
                format!("case {case} ({})", values.join(", ")),
                "the same clearance joints in every case",
            ));
        }
        Ok(scene)
    }

    /// Runs every case as an ensemble; a different sweep, so it has its own fingerprint.
    pub fn with_ensemble(mut self, ensemble: EnsembleSettings) -> Result<Sweep> {
        ensemble.validate()?;
        let salt = format!("ensemble {} seed {}", ensemble.members, ensemble.seed);
        self.fingerprint = salted(&self.fingerprint, &salt);
        self.ensemble = Some(ensemble);
        Ok(self)
    }

    /// The header of this sweep's file.
    pub fn header(&self) -> Vec<String> {
        match self.ensemble {
            Some(_) => ensemble_header(&self.sets, &self.joints),
            None => header(&self.sets, &self.joints),
        }
    }

    /// Columns between the set values and the wall time.
    pub fn cells(&self) -> usize {
        self.header().len() - self.sets.len() - 3
    }

    /// Skips the shard's cases in `finished` (a resumed sweep's).
    pub fn skip(&mut self, finished: HashSet<usize>) {
        self.skipped = finished;
    }

    /// Cases of the shard.
    fn shard_cases(&self) -> usize {
        shard_cases(self.total, self.shard)
    }

    /// Cases left to run.
    pub fn len(&self) -> usize {
        let skipped = (self.skipped.iter()).filter(|&&k| k < self.total && self.shard.contains(k));
        self.shard_cases() - skipped.count()
    }

    /// Whether no case is left to run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Runs the cases left in parallel, each built as it starts, calling `done` with each
    /// result as it finishes (in no particular order). Memory does not grow with the number
    /// of cases. Once `cancel` asks to stop, running cases stop with [`Error::Cancelled`] and
    /// no other starts (its counts are not told).
    pub fn run(&self, done: impl Fn(CaseResult) + Sync, cancel: &dyn Progress) {
        let cancel = Cancellation(cancel);
        let (first, every) = (self.shard.index - 1, self.shard.count);
        (0..self.shard_cases())
            .into_par_iter()
            .map(|i| first + i * every)
            .filter(|case| !self.skipped.contains(case))
            .for_each(|case| {
                if !cancel.cancelled() {
                    done(self.run_case(case, &cancel));
                }
            });
    }

    /// Builds and runs case `case` of the whole sweep (whatever the shard), on this thread but
    /// for an ensemble's members; stops with [`Error::Cancelled`] once `cancel` asks to (its
    /// counts are not told). What [`Sweep::run`] runs per case, and what a Python executor's
    /// worker runs.
    pub fn run_case(&self, case: usize, cancel: &dyn Progress) -> CaseResult {
        let cancel = &Cancellation(cancel);
        let outcome = self.build(case).and_then(|scene| {
            let (outcome, wall) = match &self.ensemble {
                None => simulate_with_progress(&scene, cancel)
                    .map(|out| (Outcome::Run(summarize(&scene, &out)), out.wall_time))?,
                Some(e) => run_ensemble(&scene, e, cancel)?,
            };
            Ok((outcome, Recorded::of(&scene), wall))
        });
        let values = case_values(&self.sets, case);
        CaseResult {
            case,
            values: values.iter().map(|v| v.to_string()).collect(),
            outcome: outcome.map_err(|e| e.to_string()),
        }
    }
}

/// The clearance joint names of `scene`.
fn joint_names(scene: &Scene) -> Vec<String> {
    (scene.mechanism.clearance_joints.iter())
        .map(|cj| cj.name.clone())
        .collect()
}

/// `sets` with every key in its canonical spelling: an array index as its number
/// (`clearance.00.x` and `clearance.+0.x` are `clearance.0.x`), found by walking `doc` as
/// [`set_dotted`] does; a key whose canonical spelling is given twice is refused, naming both
/// spellings (the rows would be labelled with one value while the cases ran with the other),
/// and so is a value given twice for one key (an integer and a float of one number alike; its
/// cases would run twice).
pub fn canonical_sets(doc: &toml::Value, sets: Vec<Assignment>) -> Result<Vec<Assignment>> {
    let mut out: Vec<Assignment> = Vec::with_capacity(sets.len());
    for a in sets {
        let key = canonical_key(doc, &a.key);
        let values: Vec<toml::Value> = a.values.iter().map(|v| parse_value(v)).collect();
        for (j, v) in values.iter().enumerate() {
            if let Some(i) = values[..j].iter().position(|u| same_value(u, v)) {
                return Err(Error::invalid(
                    "--set",
                    &key,
                    format!(
                        "each value once: given twice (as `{}` and as `{}`), which runs the \
                         same case twice",
                        a.values[i], a.values[j]
                    ),
                ));
            }
        }
        if let Some(other) = out.iter().find(|b| b.key == key) {
            return Err(Error::invalid(
                "--set",
                &key,
                format!(
                    "each key once: given twice (as `{}` and as `{}`)",
                    other.values.join(","),
                    a.values.join(",")
                ),
            ));
        }
        out.push(Assignment { key, ..a });
    }
    Ok(out)
}

/// Whether two values of a key are one: equal TOML values, or an integer and a float of one
/// number (`0` and `0.0`, which a key of a float reads alike).
fn same_value(a: &toml::Value, b: &toml::Value) -> bool {
    let number = |v: &toml::Value| match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(x) => Some(*x),
        _ => None,
    };
    match (number(a), number(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// An ensemble of one case: its joint statistics and wall time.
fn run_ensemble(
    scene: &Scene,
    settings: &EnsembleSettings,
    cancel: &dyn Progress,
) -> Result<(Outcome, f64)> {
    let clock = std::time::Instant::now();
    let members = crate::simulation::ensemble::run(
        scene,
        settings,
        |_, out| (summarize(scene, &out), out.final_wear),
        cancel,
    )?;
    let stats = joint_statistics(scene, &members);
    Ok((
        Outcome::Ensemble(settings.members, stats),
        clock.elapsed().as_secs_f64(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignments_split_on_top_level_commas() {
        let a = Assignment::parse("gravity_m_s2=[0.0, -9.81],[0.0, 0.0]").unwrap();
        assert_eq!(a.values, vec!["[0.0, -9.81]", "[0.0, 0.0]"]);
        let a = Assignment::parse("clearance.0.clearance_mm=0.02,0.1, 0.5").unwrap();
        assert_eq!(a.key, "clearance.0.clearance_mm");
        assert_eq!(a.values, vec!["0.02", "0.1", "0.5"]);
        for bad in ["novalue", "=1", "a..b=1", "a=1,,2", "a="] {
            assert!(Assignment::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn product_order_and_shards_cover_every_case_once() {
        let sets = vec![
            Assignment::parse("a=1,2,3").unwrap(),
            Assignment::parse("b=x,y").unwrap(),
        ];
        assert_eq!(case_count(&sets).unwrap(), 6);
        assert_eq!(case_values(&sets, 0), vec!["1", "x"]);
        assert_eq!(case_values(&sets, 1), vec!["1", "y"]);
        assert_eq!(case_values(&sets, 5), vec!["3", "y"]);
        let shards: Vec<Shard> = (1..=4)
            .map(|i| Shard::parse(&format!("{i}/4")).unwrap())
            .collect();
        for k in 0..6 {
            assert_eq!(shards.iter().filter(|s| s.contains(k)).count(), 1);
        }
        for bad in ["0/3", "4/3", "1", "a/b", "1/0"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn values_are_toml_or_bare_strings() {
        assert_eq!(parse_value("0.5"), toml::Value::Float(0.5));
        assert_eq!(parse_value("600"), toml::Value::Integer(600));
        assert_eq!(parse_value("rk4"), toml::Value::String("rk4".into()));
        assert_eq!(parse_value("\"rk4\""), toml::Value::String("rk4".into()));
    }
}
