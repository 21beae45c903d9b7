//! Sweep CSV files that lose no work.
//!
//! A sweep file is plain CSV, the header then one row per finished case; the name of its last
//! column names the sweep, and that column holds each row's label check (a hash of the
//! fingerprint and of every cell but the measured wall time: the case number, the set values
//! and the results, which a row relabelled or edited by hand fails):
//! ```text
//! case,clearance.0.clearance_mm,…,wall_time_s,error,jointwear sweep fingerprint=5f1c0a9e3b7d2c41 shard=2/4 cases=3 total=12
//! ```
//! So `pandas.read_csv(path)` reads it as it is, and a shard without finished cases still says
//! which sweep and shard it is (the name used to be a `#` line above the header, which CSV
//! readers took for a row).
//! * Rows are appended as cases finish, one write each, so an interrupted or killed sweep
//!   keeps every finished case: the partial file is CSV under its header, and
//!   `jointwear sweep --resume` skips the cases it holds. A line
//!   cut by a kill (no final newline) is dropped when the file is read back. A sweep that
//!   finishes rewrites its file in case order, atomically.
//! * The fingerprint is a hash (64-bit FNV-1a) of the scene document, `extends` resolved, of
//!   the `--set` assignments and of the program's arithmetic version: a file of another sweep
//!   is recognised when resuming or merging. `shard=I/N` and `cases` (rows the shard holds
//!   when complete) let [`merge`] refuse a missing, repeated or unfinished shard; `total` is
//!   the whole sweep's case count.
//! * A file of an earlier version, whose rows do not name their recorded window
//!   ([`crate::sweep::RECORD_COLUMNS`]), is refused when read, saying so: its sweep is run
//!   again into another file.

use crate::analysis::{CONTINUOUS_CONTACT_FRACTION, MOTION_MODES};
use crate::io::output::{
    fnv1a, number, parse_rows, read_bounded_text, write_table, GrowingTable,
    SWEEP_COLUMN_PREFIX as PREFIX,
};
use crate::io::progress::{Counter, Progress};
use crate::scene::{MAX_ROTATIONS, MAX_SETTLING_ROTATIONS};
use crate::simulation::checkpoint::ARITHMETIC;
use crate::simulation::ensemble::MAX_MEMBERS;
use crate::simulation::summary::{JOINT_COLUMNS, SCALARS};
use crate::simulation::RunSettings;
use crate::sweep::{
    case_values, shard_cases, Assignment, Shard, Sweep, ENSEMBLE_COLUMNS, MAX_CASES, RECORD_COLUMNS,
};
use crate::{Error, Result};
use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;
use std::sync::Mutex;

/// What sweep, and which part of it, a sweep file holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SweepId {
    /// Hash of the sweep definition (16 hex digits).
    pub fingerprint: String,
    /// The shard the file holds.
    pub shard: Shard,
    /// Cases of the shard (rows of the complete file).
    pub cases: usize,
    /// Cases of the whole sweep.
    pub total: usize,
}

/// Largest sweep file read back (bytes): a header and [`MAX_CASES`] rows of up to 8 KiB. A
/// number takes at most 25 bytes with its comma (the longest shortest round-trip `f64`,
/// `-2.2250738585072014e-308`, has 24 characters), so a clearance joint's cells take at most
/// 225 bytes of a run's row and 2 250 of an ensemble's (9 quantities of 10 cells: n, mean, sd
/// and the states); an error row holds its message instead (under 1 kB), and the set values are
/// as typed. 8 KiB a row holds three joints' ensemble statistics at their longest (the standard
/// scene's rows are under 200 and 1 000 bytes); the header, column names of up to 100 bytes,
/// gets 64 KiB. A larger file is not a sweep's, and reading it whole would only fill the
/// memory (`sweep-merge /dev/zero` did).
pub const MAX_SWEEP_FILE_BYTES: u64 = MAX_CASES as u64 * 8192 + 65536;

impl SweepId {
    /// The name of the last column of a sweep file.
    pub fn column_name(&self) -> String {
        format!(
            "{PREFIX}fingerprint={} shard={}/{} cases={} total={}",
            self.fingerprint, self.shard.index, self.shard.count, self.cases, self.total
        )
    }

    /// Parses [`SweepId::column_name`].
    pub fn parse(line: &str) -> Option<SweepId> {
        let fields = line.strip_prefix(PREFIX)?;
        let value = |key: &str| {
            fields
                .split_whitespace()
                .find_map(|f| f.strip_prefix(key)?.strip_prefix('='))
        };
        Some(SweepId {
            fingerprint: value("fingerprint")?.to_string(),
            shard: Shard::parse(value("shard")?).ok()?,
            cases: value("cases")?.parse().ok()?,
            total: value("total")?.parse().ok()?,
        })
    }

    /// Why this id cannot be of a sweep this program wrote, if it cannot: the whole sweep
    /// within [`MAX_CASES`], and the shard's case count the one its number and the whole
    /// sweep's give. Checked before any number read is used.
    fn misfit(&self) -> Option<String> {
        if self.total > MAX_CASES {
            return Some(format!("total={}: at most {MAX_CASES} cases", self.total));
        }
        let owned = shard_cases(self.total, self.shard);
        (self.cases != owned).then(|| {
            format!(
                "cases={}: shard {}/{} of {} cases owns {owned}",
                self.cases, self.shard.index, self.shard.count, self.total
            )
        })
    }

    /// The id of the whole sweep this shard belongs to.
    fn whole(&self) -> SweepId {
        SweepId {
            shard: Shard::ALL,
            cases: self.total,
            ..self.clone()
        }
    }
}

/// Fingerprint of a sweep: the scene document (`extends` resolved), the assignments
/// ([`crate::scene::variant::fingerprint`]) and the program's [`ARITHMETIC`]: shards run by
/// programs whose runs differ by rounding are not one sweep, and are not merged or resumed
/// into one.
pub fn fingerprint(doc: &toml::Value, sets: &[Assignment]) -> String {
    fingerprint_of(doc, sets, ARITHMETIC)
}

/// [`fingerprint`] for the program whose arithmetic version is `arithmetic`.
fn fingerprint_of(doc: &toml::Value, sets: &[Assignment], arithmetic: u32) -> String {
    let definition = crate::scene::variant::fingerprint(
        doc,
        sets.iter().map(|a| (a.key.as_str(), &a.values[..])),
    );
    salted(&definition, &format!("arithmetic={arithmetic}"))
}

/// A fingerprint combined with more of a sweep's definition (e.g. its ensemble size).
pub fn salted(fingerprint: &str, salt: &str) -> String {
    format!(
        "{:016x}",
        fnv1a(format!("{fingerprint}\u{1f}{salt}").as_bytes())
    )
}

impl Sweep {
    /// The id of this sweep's file.
    pub fn id(&self) -> SweepId {
        SweepId {
            fingerprint: self.fingerprint.clone(),
            shard: self.shard,
            cases: self.shard_cases(),
            total: self.total,
        }
    }
}

/// A sweep file read back.
#[derive(Clone, Debug)]
pub struct SweepFile {
    /// What sweep and shard the file holds.
    pub id: SweepId,
    /// The CSV header.
    pub header: Vec<String>,
    /// Complete rows, in file order.
    pub rows: Vec<Vec<String>>,
}

fn parse_error(path: &Path, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        message,
    }
}

/// The case number of a row.
fn case_of(path: &Path, row: &[String]) -> Result<usize> {
    row[0].parse().map_err(|_| {
        parse_error(
            path,
            format!(
                "case `{}` is not an integer (row {})",
                row[0],
                row.join(",")
            ),
        )
    })
}

impl SweepFile {
    /// Reads a sweep file; a last line without its newline (cut by a kill) is dropped.
    pub fn read(path: &Path) -> Result<SweepFile> {
        let text = read_bounded_text(
            path,
            MAX_SWEEP_FILE_BYTES,
            "a sweep file",
            "a million cases of rows up to 8 KiB",
        )?;
        let complete = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
        let (mut header, all) = parse_rows(path, complete)?;
        let id = header
            .pop()
            .as_deref()
            .and_then(SweepId::parse)
            .ok_or_else(|| {
                parse_error(
                    path,
                    format!(
                        "not a sweep file: the name of its header's last column is not \
                     `{PREFIX}fingerprint=… shard=I/N cases=K total=T`"
                    ),
                )
            })?;
        if let Some(why) = id.misfit() {
            return Err(parse_error(
                path,
                format!("its sweep header line does not add up: {why}"),
            ));
        }
        if header.first().map(String::as_str) != Some("case") {
            return Err(parse_error(
                path,
                format!("header `{}` does not start with `case`", header.join(",")),
            ));
        }
        let cells = cell_kinds(&header).ok_or_else(|| {
            let earlier = if header.iter().any(|h| h == RECORD_COLUMNS[1]) {
                ""
            } else {
                "; likely cause: a file written by an earlier version, whose rows do not say \
                 the recorded window (record_rotations) nor the sampling interval \
                 (record_interval_s) of their recorded maxima and motion, so that this version \
                 cannot keep them beside its own (run its sweep again into another --out, or \
                 remove the file)"
            };
            parse_error(
                path,
                format!(
                    "header `{}` is not a sweep's: `case`, the set keys, `members` for an \
                     ensemble sweep, `{}`, per clearance joint its summary columns (or per \
                     quantity its n, mean, sd and states), `wall_time_s`, `error`{earlier}",
                    header.join(","),
                    RECORD_COLUMNS.join("`, `"),
                ),
            )
        })?;
        let mut rows = Vec::new();
        let mut seen = HashSet::new();
        let wall = wall_column(&header);
        // Every line here ends with its newline (a line cut by a kill was dropped above), so a
        // row of another length was edited: dropping it would lose a case without a word.
        for (k, mut row) in all.into_iter().enumerate() {
            if row.len() != header.len() + 1 {
                return Err(parse_error(
                    path,
                    format!(
                        "row {} has {} cells where the header has {} (`{}`); likely cause: \
                         the file was edited (remove the row and resume the sweep to run its \
                         case again)",
                        k + 1,
                        row.len(),
                        header.len() + 1,
                        row.join(",")
                    ),
                ));
            }
            let check = row.pop().unwrap_or_default();
            let case = case_of(path, &row)?;
            if case >= id.total || !id.shard.contains(case) || !seen.insert(case) {
                return Err(parse_error(
                    path,
                    format!(
                        "case {case} is not a case of shard {}/{} of this {}-case sweep, or \
                         appears twice (row {})",
                        id.shard.index,
                        id.shard.count,
                        id.total,
                        row.join(",")
                    ),
                ));
            }
            // (A cell's misfit, else the label check's, each with its likely cause.)
            let expected = label_check(&id.fingerprint, &row, wall);
            let misfit = misfit_cell(&cells, &row)
                .map(|(column, value, writes)| {
                    let cause = "the file was edited (remove the row and resume the sweep to \
                                 run its case again)";
                    (header[column].clone(), value, writes, cause)
                })
                .or_else(|| {
                    let writes = "the label check of its case, set values and results".to_string();
                    let cause = "the file was edited: a cell of the row (its case number, a set \
                                 value or a result) is not the one the sweep wrote, and merged or \
                                 resumed the row would be kept as the sweep's, its results perhaps \
                                 filed under another case (a spreadsheet that saved the file \
                                 rounds its numbers) (remove the row and resume the sweep to run \
                                 its case again)";
                    (check != expected).then(|| (id.column_name(), check, writes, cause))
                });
            if let Some((name, value, writes, cause)) = misfit {
                return Err(parse_error(
                    path,
                    format!(
                        "row {} (case {case}), column `{name}`: `{value}` where a sweep writes \
                         {writes}; likely cause: {cause}",
                        k + 1
                    ),
                ));
            }
            rows.push(row);
        }
        Ok(SweepFile { id, header, rows })
    }

    /// What this file holds, if not the sweep `id` under `header`: `fingerprint F, shard I/N`
    /// and, for another header, `, another header`.
    fn another(&self, id: &SweepId, header: &[String]) -> Option<String> {
        let ours = self.id.fingerprint == id.fingerprint && self.id.shard == id.shard;
        (!ours || self.header != header).then(|| {
            format!(
                "fingerprint {}, shard {}/{}{}",
                self.id.fingerprint,
                self.id.shard.index,
                self.id.shard.count,
                if self.header != header {
                    ", another header"
                } else {
                    ""
                }
            )
        })
    }
}

/// What a cell of a sweep row holds, as [`crate::sweep::CaseResult::record`] writes it.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cell {
    /// The case number (checked by [`case_of`]).
    Case,
    /// A set value as typed: never empty.
    Value,
    /// An ensemble's member count.
    Members,
    /// A number in its range, always written: the whole run's largest penetration, the wall time.
    Number(Range),
    /// A number in its range, or empty where nothing was measured (NaN is written empty).
    Measured(Range),
    /// A run's rotations simulated: an integer in [1, [`MAX_ROTATIONS_SIMULATED`]], always
    /// written.
    Rotations,
    /// The rotations recorded (`record_rotations`): an integer in [1, [`MAX_ROTATIONS`]] (a
    /// sweep records at least one), always written.
    RecordRotations,
    /// Members of an ensemble quantity or of one of its states (`n`, `low_n`, `high_n`): an
    /// integer from 0 to the row's member count, or empty where there is no such state.
    Count,
    /// An ensemble quantity's state count: 1 or 2, or empty where no member has a value.
    States,
    /// A motion mode, or empty where nothing was recorded: [`MOTION_MODES`]`[0]` exactly where
    /// the joint's contact fraction, this many cells further, is at least
    /// [`CONTINUOUS_CONTACT_FRACTION`] ([`crate::analysis::Motion::mode`]), empty where it is.
    Mode(usize),
    /// Whether a settling run settled: `true`, `false`, or empty for a scene that does not settle.
    Settled,
    /// The error of a failed case, empty for a case that ran.
    Error,
}

/// Most rotations a run simulates: [`MAX_ROTATIONS`] and at most [`MAX_SETTLING_ROTATIONS`]
/// settling.
const MAX_ROTATIONS_SIMULATED: u32 = MAX_ROTATIONS + MAX_SETTLING_ROTATIONS;

/// The values a measured quantity takes (a cell out of its range was edited: `-5` m of wear
/// depth, a contact fraction of 7).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Range {
    /// Any finite number: a penetration (negative where the journal kept clear).
    Any,
    /// A finite number ≥ 0: a force, a wear depth, impacts per rotation, a time, an sd.
    NonNegative,
    /// A fraction in [0, 1]: the contact fraction, an ensemble's share of members (in
    /// continuous contact, settled).
    Fraction,
    /// An angle in [0, 360) degrees (an ensemble's angles are wrapped back into it).
    Angle,
    /// Rotations simulated, or their mean: in [1, [`MAX_ROTATIONS_SIMULATED`]].
    Rotations,
    /// A sampling interval (s): in (0, 1], as `run.record_interval_s` takes it.
    Interval,
}

impl Range {
    /// The range of the quantity `name` (of [`JOINT_COLUMNS`] or [`SCALARS`]).
    fn of(name: &str) -> Range {
        match name {
            "max_penetration_recorded_m" | "max_penetration_whole_run_m" => Range::Any,
            "max_wear_angle_deg" => Range::Angle,
            "contact_fraction" | "continuous_contact" | "settled" => Range::Fraction,
            "rotations_simulated" => Range::Rotations,
            _ => Range::NonNegative,
        }
    }

    /// Whether `x` lies in the range.
    fn contains(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                Range::Any => true,
                Range::NonNegative => x >= 0.0,
                Range::Fraction => (0.0..=1.0).contains(&x),
                Range::Angle => (0.0..360.0).contains(&x),
                Range::Rotations => (1.0..=f64::from(MAX_ROTATIONS_SIMULATED)).contains(&x),
                Range::Interval => x > 0.0 && x <= 1.0,
            }
    }

    /// The range in words.
    fn describe(self) -> String {
        match self {
            Range::Any => "a finite number".into(),
            Range::NonNegative => "a finite number >= 0".into(),
            Range::Fraction => "a number in [0, 1]".into(),
            Range::Angle => "an angle in [0, 360) degrees".into(),
            Range::Rotations => format!("a number in [1, {MAX_ROTATIONS_SIMULATED}]"),
            Range::Interval => "a sampling interval in (0, 1] s".into(),
        }
    }
}

/// The cells of a row under `header` (without the id column), or None if it is not a sweep's:
/// `case`, the set values, then (after `members`, for an ensemble's) [`RECORD_COLUMNS`], then
/// per clearance joint its [`JOINT_COLUMNS`] (a run's) or the [`ENSEMBLE_COLUMNS`] of each of
/// [`SCALARS`] (an ensemble's), then `wall_time_s` and `error` ([`crate::sweep::header`],
/// [`crate::sweep::ensemble_header`]).
/// Joints are matched from the end, a group of columns at a time sharing the joint's name; a
/// joint's column outside its group makes the header not a sweep's.
fn cell_kinds(header: &[String]) -> Option<Vec<Cell>> {
    let [first, middle @ .., wall, error] = header else {
        return None;
    };
    if (first.as_str(), wall.as_str(), error.as_str()) != ("case", "wall_time_s", "error") {
        return None;
    }
    let at = |name| JOINT_COLUMNS.iter().position(|&c| c == name);
    let fraction_after_mode = at("contact_fraction")? - at("motion_mode")?;
    let run: Vec<(String, Cell)> = (JOINT_COLUMNS.iter())
        .map(|&c| {
            let cell = match c {
                "max_penetration_whole_run_m" => Cell::Number(Range::Any),
                "motion_mode" => Cell::Mode(fraction_after_mode),
                "rotations_simulated" => Cell::Rotations,
                "settled" => Cell::Settled,
                _ => Cell::Measured(Range::of(c)),
            };
            (format!(".{c}"), cell)
        })
        .collect();
    let ensemble: Vec<(String, Cell)> = (SCALARS.iter())
        .flat_map(|&s| {
            ENSEMBLE_COLUMNS.iter().map(move |&c| {
                let cell = match c {
                    "n" | "low_n" | "high_n" => Cell::Count,
                    "states" => Cell::States,
                    _ if c.ends_with("sd") => Cell::Measured(Range::NonNegative),
                    _ => Cell::Measured(Range::of(s)),
                };
                (format!(".{s}.{c}"), cell)
            })
        })
        .collect();
    // The columns before the joints' groups, and the groups' cells.
    let strip = |group: &[(String, Cell)]| {
        let mut rest = middle;
        let mut joints = Vec::new();
        while let Some(split) = rest.len().checked_sub(group.len()) {
            let (before, last) = rest.split_at(split);
            let prefixes: Option<Vec<&str>> = (last.iter().zip(group))
                .map(|(name, (suffix, _))| name.strip_suffix(suffix.as_str()))
                .collect();
            match prefixes {
                Some(p) if p.iter().all(|&joint| joint == p[0]) => {
                    joints.extend(group.iter().map(|(_, cell)| *cell));
                    rest = before;
                }
                _ => break,
            }
        }
        (rest, joints)
    };
    let window = [Cell::RecordRotations, Cell::Number(Range::Interval)];
    let ensemble_tail = ["members", RECORD_COLUMNS[0], RECORD_COLUMNS[1]];
    let (rest, joints) = match strip(&ensemble) {
        (rest, joints) if without_tail(rest, &ensemble_tail).is_some() => (rest, joints),
        _ => strip(&run),
    };
    let rest = without_tail(rest, &RECORD_COLUMNS)?;
    let (sets, before_joints) = match rest.split_last() {
        Some((last, sets)) if last == "members" => (sets, vec![Cell::Members]),
        _ => (rest, Vec::new()),
    };
    // A joint's column, or a window's, left among the set keys: a group was edited.
    let joint_column = |name: &String| {
        name == "members"
            || RECORD_COLUMNS.contains(&name.as_str())
            || (run.iter().chain(&ensemble)).any(|(s, _)| name.ends_with(s.as_str()))
    };
    if sets.iter().any(joint_column) {
        return None;
    }
    let mut cells = vec![Cell::Case];
    cells.extend(sets.iter().map(|_| Cell::Value));
    cells.extend(before_joints);
    cells.extend(window);
    cells.extend(joints);
    cells.extend([Cell::Number(Range::NonNegative), Cell::Error]);
    Some(cells)
}

/// `names` without its last names `tail`, if it ends with them.
fn without_tail<'a>(names: &'a [String], tail: &[&str]) -> Option<&'a [String]> {
    let (head, last) = names.split_at(names.len().checked_sub(tail.len())?);
    (last.iter().zip(tail)).all(|(n, t)| n == t).then_some(head)
}

/// The first cell of `row` (of `cells`) that a sweep does not write, as (column, value, what
/// it writes there). A failed case's row holds its set values and its error, every other cell
/// empty; a finished case's row an empty error and each measured value in its range.
fn misfit_cell(cells: &[Cell], row: &[String]) -> Option<(usize, String, String)> {
    let failed = failed(row);
    let number = |v: &str| v.parse::<f64>().ok();
    let members = (cells.iter().position(|&c| c == Cell::Members))
        .and_then(|m| row.get(m)?.parse::<usize>().ok())
        .unwrap_or(0);
    let count = |v: &str, range: std::ops::RangeInclusive<usize>| {
        v.parse::<usize>().is_ok_and(|n| range.contains(&n))
    };
    cells
        .iter()
        .zip(row)
        .enumerate()
        .find_map(|(column, (&cell, value))| {
            let v = value.as_str();
            let fits = match cell {
                Cell::Case | Cell::Error => true,
                Cell::Value => !v.is_empty(),
                _ if failed => v.is_empty(),
                Cell::Members => count(v, 1..=MAX_MEMBERS),
                Cell::Number(r) => number(v).is_some_and(|x| r.contains(x)),
                Cell::Measured(r) => v.is_empty() || number(v).is_some_and(|x| r.contains(x)),
                Cell::Rotations => v
                    .parse::<u32>()
                    .is_ok_and(|n| (1..=MAX_ROTATIONS_SIMULATED).contains(&n)),
                Cell::RecordRotations => v
                    .parse::<u32>()
                    .is_ok_and(|n| (1..=MAX_ROTATIONS).contains(&n)),
                Cell::Count => v.is_empty() || count(v, 0..=members),
                Cell::States => v.is_empty() || count(v, 1..=2),
                Cell::Mode(after) => {
                    let fraction = row.get(column + after).map_or("", String::as_str);
                    match (v, number(fraction)) {
                        ("", _) => fraction.is_empty(),
                        (_, Some(f)) => {
                            v == MOTION_MODES[usize::from(f < CONTINUOUS_CONTACT_FRACTION)]
                        }
                        (_, None) => false,
                    }
                }
                Cell::Settled => matches!(v, "" | "true" | "false"),
            };
            (!fits).then(|| {
                let expected = match cell {
                    Cell::Value => "a set value (never empty)".to_string(),
                    _ if failed => "an empty cell in the row of a failed case (its error is in \
                                the last column)"
                        .to_string(),
                    Cell::Members => format!("a member count in [1, {MAX_MEMBERS}]"),
                    Cell::Number(r) => r.describe(),
                    Cell::Measured(r) => {
                        format!(
                            "{}, or an empty cell where nothing was measured",
                            r.describe()
                        )
                    }
                    Cell::Rotations => {
                        format!("a whole number of rotations in [1, {MAX_ROTATIONS_SIMULATED}]")
                    }
                    Cell::RecordRotations => {
                        format!("a whole number of rotations in [1, {MAX_ROTATIONS}]")
                    }
                    Cell::Count => format!(
                        "a whole number of members in [0, {members}] (the row's members), or \
                         an empty cell"
                    ),
                    Cell::States => {
                        "a state count, 1 or 2, or an empty cell where no member has a value"
                            .to_string()
                    }
                    Cell::Settled => "`true`, `false` or an empty cell".to_string(),
                    Cell::Mode(after) => format!(
                        "`{}` where the joint's contact_fraction is at least \
                         {CONTINUOUS_CONTACT_FRACTION}, `{}` where it is below, an empty cell \
                         where it is empty (here it is `{}`)",
                        MOTION_MODES[0],
                        MOTION_MODES[1],
                        row.get(column + after).map_or("", String::as_str)
                    ),
                    Cell::Case | Cell::Error => String::new(),
                };
                (column, value.clone(), expected)
            })
        })
}

/// Writes a sweep file atomically: the header with the id column, the rows with their label
/// checks.
fn write_file(path: &Path, id: &SweepId, header: &[String], rows: Vec<Vec<String>>) -> Result<()> {
    let wall = wall_column(header);
    write_table(
        path,
        None,
        &with_id(header, id),
        rows.into_iter()
            .map(|r| with_check(r, &id.fingerprint, wall)),
    )
}

/// The cell of a row under `header` that its label check leaves out: `wall_time_s`, measured,
/// so that two runs of a case (a sweep and the merge of its shards) write the same check.
fn wall_column(header: &[String]) -> usize {
    header
        .iter()
        .position(|h| h == "wall_time_s")
        .unwrap_or(header.len())
}

/// Why a file may hold another sweep's rows, for the messages that refuse it.
const ANOTHER_SWEEP: &str = "another scene, other --set values, another shard or another \
                             program version's arithmetic";

/// The label check of a row in a file of the sweep `fingerprint`: the hash of its cells but
/// cell `wall` (the measured wall time, `wall_time_s`), written in the row's cell of the id
/// column. A row relabelled by hand (its case number, or a set value turned into another valid
/// one) no longer matches it, so that no merge or resume files its results under another
/// case; nor does one whose results were edited (a spreadsheet that saved the file rounds
/// them), so that none is kept as the sweep's.
pub fn label_check(fingerprint: &str, row: &[String], wall: usize) -> String {
    let cells: Vec<&str> = (row.iter().enumerate())
        .filter(|&(k, _)| k != wall)
        .map(|(_, c)| c.as_str())
        .collect();
    // (Prefixed, so that CSV readers never take the hex digits for a number.)
    format!("label-{}", salted(fingerprint, &cells.join("\u{1f}")))
}

/// `row` and its label check in the cell of the id column.
fn with_check(mut row: Vec<String>, fingerprint: &str, wall: usize) -> Vec<String> {
    row.push(label_check(fingerprint, &row, wall));
    row
}

/// `header` and the name of the id column.
fn with_id(header: &[String], id: &SweepId) -> Vec<String> {
    header.iter().cloned().chain([id.column_name()]).collect()
}

/// Writes a sweep file with `rows` in case order, atomically.
pub fn write_sweep_file(
    path: &Path,
    id: &SweepId,
    header: &[String],
    mut rows: Vec<Vec<String>>,
) -> Result<()> {
    rows.sort_by_key(|r| r[0].parse::<usize>().unwrap_or(usize::MAX));
    write_file(path, id, header, rows)
}

/// A sweep file that receives each case's row as it finishes.
#[derive(Debug)]
pub struct Journal {
    table: GrowingTable,
    /// The sweep's fingerprint and its rows' wall time cell, for their checks.
    fingerprint: String,
    wall: usize,
}

impl Journal {
    /// Starts the file at `path` with `kept` rows (a resumed sweep's finished cases).
    pub fn create(
        path: &Path,
        id: &SweepId,
        header: &[String],
        kept: &[Vec<String>],
    ) -> Result<Journal> {
        let (fingerprint, wall) = (id.fingerprint.clone(), wall_column(header));
        let kept = (kept.iter().cloned()).map(|r| with_check(r, &fingerprint, wall));
        let table = GrowingTable::create(path, None, &with_id(header, id), kept)?;
        Ok(Journal {
            table,
            fingerprint,
            wall,
        })
    }

    /// Appends one row in a single write, so that rows of parallel cases never interleave.
    pub fn append(&self, row: &[String]) -> Result<()> {
        let row = with_check(row.to_vec(), &self.fingerprint, self.wall);
        self.table.append(&row)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// Rewrites the file with `rows` in case order, atomically (the sweep finished).
    pub fn finish(self, id: &SweepId, header: &[String], rows: Vec<Vec<String>>) -> Result<()> {
        let path = self.table.path().to_path_buf();
        drop(self.table);
        write_sweep_file(&path, id, header, rows)
    }
}

/// A sweep whose cases are appended to its file as they finish.
pub struct JournaledSweep<'a> {
    sweep: &'a mut Sweep,
    id: SweepId,
    header: Vec<String>,
    /// Cases finished before (a resumed sweep).
    finished: usize,
    journal: Journal,
}

impl<'a> JournaledSweep<'a> {
    /// Starts the file `out` of `sweep`; with `resume`, keeps the rows the file holds of the
    /// same sweep and shard (an error if it holds another) and skips their cases in `sweep`.
    /// Without it, an unfinished sweep file (of this sweep and shard, or of another), one
    /// that cannot be read back, or a file that is not a sweep's (`unfinished`) is an error
    /// rather than started over: its finished cases would be lost to a rerun that forgot
    /// `--resume`, or to another sweep into the same file, and what another file holds to the
    /// sweep's CSV.
    pub fn open(sweep: &'a mut Sweep, out: &Path, resume: bool) -> Result<JournaledSweep<'a>> {
        let id = sweep.id();
        let header = sweep.header();
        let kept = if resume {
            resume_rows(out, &id, &header)?
        } else {
            if let Some(file) = unfinished(out)? {
                let ours = file.id == id && file.header == header;
                return Err(if ours {
                    Error::invalid(
                        "--resume",
                        "not given",
                        format!(
                            "--resume with {}, which holds the rows of {} of the {} cases of \
                             this sweep and shard, finished before it stopped: --resume keeps \
                             them and runs the rest; to start over, remove the file",
                            out.display(),
                            file.rows.len(),
                            file.id.cases
                        ),
                    )
                } else {
                    refuse_unfinished(
                        out,
                        &file,
                        &format!("another sweep or shard ({ANOTHER_SWEEP})"),
                        "sweep",
                    )
                });
            }
            Vec::new()
        };
        // (A kept row's set values are its case's: its label check says so, `SweepFile::read`.)
        let mut finished = HashSet::new();
        // A case's run settings, built once per distinct value of the sweep's `run.*` keys
        // (those alone set them): a row per case would build every case's scene again.
        let mut runs: HashMap<Vec<String>, RunSettings> = HashMap::new();
        for (k, row) in kept.iter().enumerate() {
            let case = case_of(out, row)?;
            // (A case that failed, perhaps to build, has nothing to check.)
            if !failed(row) {
                let values = case_values(&sweep.sets, case);
                let key: Vec<String> = (sweep.sets.iter().zip(values))
                    .filter(|(a, _)| a.key.starts_with("run."))
                    .map(|(_, v)| v.to_string())
                    .collect();
                let run = match runs.entry(key) {
                    Entry::Occupied(e) => e.into_mut(),
                    Entry::Vacant(e) => e.insert(sweep.build(case)?.run),
                };
                check_run(out, (k, case), &header, row, run)?;
            }
            finished.insert(case);
        }
        sweep.skip(finished);
        let journal = Journal::create(out, &id, &header, &kept)?;
        Ok(JournaledSweep {
            sweep,
            id,
            header,
            finished: kept.len(),
            journal,
        })
    }

    /// The sweep file's id.
    pub fn id(&self) -> SweepId {
        self.id.clone()
    }

    /// Cases already finished before this run.
    pub fn finished(&self) -> usize {
        self.finished
    }

    /// Runs the remaining cases in parallel, appending each row as its case finishes and
    /// telling `progress` the cases finished, then rewrites the file in case order from the
    /// rows it holds. Returns the number of rows and the cases that failed (an error in their
    /// last column). A row that cannot be appended does not stop the sweep: the final rewrite
    /// holds it, and the first such error is returned after it. A file that then holds fewer
    /// rows than the shard's cases lost some while the sweep ran (another program truncated,
    /// edited or replaced it): rewritten with what it holds, it is an error, never a finished
    /// sweep; and one that is another sweep's (another program moved it into its place) is an
    /// error, left as it is.
    pub fn run(self, progress: &dyn Progress) -> Result<(usize, Vec<usize>)> {
        let JournaledSweep {
            sweep,
            id,
            header,
            journal,
            ..
        } = self;
        let cells = sweep.cells();
        // The first append error and the rows it could not append.
        let unappended = Mutex::new((None, Vec::new()));
        let done = Counter::new(progress, sweep.len());
        sweep.run(
            |r| {
                let row = r.record(cells);
                if let Err(e) = journal.append(&row) {
                    let mut lost = unappended.lock().unwrap_or_else(|e| e.into_inner());
                    lost.0.get_or_insert(e);
                    lost.1.push(row);
                }
                done.finish_one();
            },
            progress,
        );
        let (append_error, lost) = unappended.into_inner().unwrap_or_else(|e| e.into_inner());
        let path = journal.path().to_path_buf();
        let file = SweepFile::read(&path)?;
        if let Some(theirs) = file.another(&id, &header) {
            // (Left as it is: it may be another sweep's own file.)
            return Err(parse_error(
                &path,
                format!(
                    "no longer the file of this sweep (fingerprint {}, shard {}/{}): it holds \
                     {theirs}, whose rows this sweep would write as its own; likely cause: \
                     another program replaced it while the sweep ran, and the rows this sweep \
                     appended went with the file it replaced (run the sweep again into another \
                     --out)",
                    id.fingerprint, id.shard.index, id.shard.count,
                ),
            ));
        }
        let mut rows = file.rows;
        rows.extend(lost);
        let mut failed: Vec<usize> = (rows.iter())
            .filter(|r| failed(r))
            .filter_map(|r| r[0].parse().ok())
            .collect();
        failed.sort_unstable();
        let count = rows.len();
        journal.finish(&id, &header, rows)?;
        if count != id.cases {
            return Err(parse_error(
                &path,
                format!(
                    "holds {count} of the {} cases of shard {}/{} after every one ran: rows \
                     were lost while the sweep ran; likely cause: the file was truncated, \
                     edited or replaced by another program meanwhile (resume the sweep with \
                     --resume to run the missing cases again)",
                    id.cases, id.shard.index, id.shard.count
                ),
            ));
        }
        match append_error {
            Some(e) => Err(e),
            None => Ok((count, failed)),
        }
    }
}

/// Checks row `k` (of case `case`) of the sweep file at `path`, under `header`, against the
/// case's run settings `run`: the recorded window ([`RECORD_COLUMNS`]) is the case's
/// `run.record_rotations` and `run.record_interval_s`, each joint's rotations simulated (a
/// run's, or an ensemble's mean) is what the case runs, `run.rotations` plus at most
/// `steady_state.max_rotations` settling rotations (exactly `run.rotations` without settling),
/// and `settled` (a run's, or an ensemble's mean) is empty exactly where the case does not
/// settle. The file alone bounds them only by what any scene could run. For a row of a case
/// that ran.
fn check_run(
    path: &Path,
    (k, case): (usize, usize),
    header: &[String],
    row: &[String],
    run: &RunSettings,
) -> Result<()> {
    let most = run.rotations + run.settle.map_or(0, |s| s.max_rotations);
    let settles = run.settle.is_some();
    for (name, value) in header.iter().zip(row) {
        // (A run's cell, or an ensemble's mean.)
        let q = name.strip_suffix(".mean").unwrap_or(name);
        let window = match name.as_str() {
            n if n == RECORD_COLUMNS[0] => Some((run.record_rotations.to_string(), "rotations")),
            n if n == RECORD_COLUMNS[1] => Some((number(run.record_interval), "s")),
            _ => None,
        };
        let (fits, writes) = if let Some((setting, unit)) = window {
            let writes = format!("{setting} {unit} (run.{name})");
            (*value == setting, writes)
        } else if q.ends_with(".rotations_simulated") {
            let fits = value
                .parse::<f64>()
                .is_ok_and(|n| (f64::from(run.rotations)..=f64::from(most)).contains(&n));
            let writes = if settles {
                format!(
                    "{} to {most} rotations (run.rotations and at most \
                     steady_state.max_rotations settling)",
                    run.rotations
                )
            } else {
                format!(
                    "{} rotations (run.rotations; the case does not settle)",
                    run.rotations
                )
            };
            (fits, writes)
        } else if q.ends_with(".settled") {
            let fits = value.is_empty() != settles;
            let writes = if settles {
                "whether the case settled (it settles)".to_string()
            } else {
                "an empty cell (the case does not settle)".to_string()
            };
            (fits, writes)
        } else {
            continue;
        };
        if !fits {
            return Err(parse_error(
                path,
                format!(
                    "row {} (case {case}), column `{name}`: `{value}` where this case's scene \
                     writes {writes}; likely cause: the file was edited (remove the row and \
                     resume the sweep to run its case again)",
                    k + 1
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `row` is a failed case's: its error, in the last column, is not empty.
fn failed(row: &[String]) -> bool {
    row.last().is_some_and(|e| !e.is_empty())
}

/// The finished rows of the sweep `id` under `header` in the file at `path`, to resume it:
/// none if there is no file; an error if it holds another sweep, shard or header.
pub fn resume_rows(path: &Path, id: &SweepId, header: &[String]) -> Result<Vec<Vec<String>>> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let file = SweepFile::read(path)?;
    if let Some(theirs) = file.another(id, header) {
        return Err(Error::invalid(
            "--resume",
            path.display(),
            format!(
                "a file of this sweep and shard (fingerprint {}, shard {}/{}); it holds \
                 {theirs}: {ANOTHER_SWEEP} (use another --out, or remove the file to start over)",
                id.fingerprint, id.shard.index, id.shard.count,
            ),
        ));
    }
    Ok(file.rows)
}

/// The refusal of `--out`, the unfinished sweep file `file` at `out` of `what`, whose finished
/// cases this `command` (`sweep`, `merge`) would lose.
fn refuse_unfinished(out: &Path, file: &SweepFile, what: &str, command: &str) -> Error {
    Error::invalid(
        "--out",
        out.display(),
        format!(
            "a file no unfinished sweep needs: it holds {} of the {} cases of {what} \
             (fingerprint {}, shard {}/{}), which this {command} would lose; give another \
             --out, finish that sweep with its own command and --resume, or remove the file",
            file.rows.len(),
            file.id.cases,
            file.id.fingerprint,
            file.id.shard.index,
            file.id.shard.count
        ),
    )
}

/// The sweep file at `path`, an `--out` about to be replaced, if it is unfinished (some of its
/// cases finished, not all), of whichever sweep; None for a missing or empty file (`mktemp`'s)
/// or a complete sweep file, which a new sweep or merge may replace. Anything else is an
/// error, as replacing it would destroy what it holds: a sweep file that cannot be read back
/// (an edited row, an earlier version's), whose finished cases would be lost unseen, and a
/// file that is not a sweep's at all (the swept scene, another command's output: `--out
/// scene.toml` used to replace the scene by the sweep's CSV, exit 0).
fn unfinished(path: &Path) -> Result<Option<SweepFile>> {
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Ok(m) if m.is_file() && m.len() == 0 => return Ok(None),
        _ => {}
    }
    match SweepFile::read(path) {
        Ok(file) => Ok((!file.rows.is_empty() && file.rows.len() < file.id.cases).then_some(file)),
        Err(e) if names_a_sweep(path) => Err(Error::invalid(
            "--out",
            path.display(),
            format!(
                "a file a new sweep may replace: it is a sweep file that cannot be read back \
                 ({e}), whose finished cases a new sweep would lose unseen; remove it, or \
                 mend it and resume its sweep"
            ),
        )),
        Err(_) => {
            let Some(line) = first_line(path) else {
                return Err(Error::invalid(
                    "--out",
                    path.display(),
                    "a new file, an empty one or a sweep file, which --out may replace: it is \
                     not a regular file (a device, a FIFO or a folder), or cannot be read",
                ));
            };
            let mut start: String = line.chars().take(80).collect();
            if start.len() < line.len() {
                start.push('…');
            }
            Err(Error::invalid(
                "--out",
                path.display(),
                format!(
                    "a new file, an empty one or a sweep file (its header's last column names \
                     a sweep), which --out may replace: it is a file that is not a sweep's, \
                     beginning `{start}`, which the sweep's CSV would destroy; likely cause: \
                     an --out naming the scene or another file by mistake (give another --out, \
                     or remove the file)"
                ),
            ))
        }
    }
}

/// The first line of `path`, a regular file, without its line break; at most 64 KiB (the
/// header's bound) are read. None if it is not a regular file or cannot be read.
fn first_line(path: &Path) -> Option<String> {
    use std::io::{BufRead, BufReader, Read};
    // (Not opened unless regular: a FIFO would wait for a writer.)
    let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
    let file = regular.then(|| std::fs::File::open(path).ok()).flatten()?;
    let mut line = Vec::new();
    BufReader::new(file.take(65536))
        .read_until(b'\n', &mut line)
        .ok()?;
    Some(String::from_utf8_lossy(&line).trim_end().to_string())
}

/// Whether `path` is a regular file whose first line is a sweep file's header (its last
/// column names a sweep), whatever the rest holds.
fn names_a_sweep(path: &Path) -> bool {
    first_line(path).is_some_and(|l| {
        l.rsplit(',')
            .next()
            .is_some_and(|c| SweepId::parse(c).is_some())
    })
}

/// Joins the shard files of one sweep into `out`, sorted by case, as the file of the whole
/// sweep (resumable if partial). Refused: a file of another sweep (fingerprint, shard count
/// or header), a shard given twice, a case in two files, unless `allow_partial`, a missing
/// shard or one whose cases did not all finish, and an `out` that is not a sweep file or holds
/// finished cases of an unfinished sweep that the merge does not (`unfinished`, as `sweep`
/// checks its `--out`). Returns the number of rows.
pub fn merge(inputs: &[impl AsRef<Path>], out: &Path, allow_partial: bool) -> Result<usize> {
    let files = inputs
        .iter()
        .map(|p| SweepFile::read(p.as_ref()).map(|f| (p.as_ref(), f)))
        .collect::<Result<Vec<_>>>()?;
    let Some((first_path, first)) = files.first() else {
        return Err(Error::invalid("inputs", "none", "at least one shard file"));
    };
    let bad = |path: &Path, value: String, expected: String| {
        Error::invalid(
            format!("{} (sweep-merge input)", path.display()),
            value,
            expected,
        )
    };
    // Shard numbers come from the files: a map, never a vector as long as a number read.
    let mut shards = BTreeMap::new();
    let mut rows = Vec::new();
    for (path, f) in &files {
        if f.id.fingerprint != first.id.fingerprint || f.id.shard.count != first.id.shard.count {
            return Err(bad(
                path,
                format!(
                    "fingerprint {}, shard {}/{}",
                    f.id.fingerprint, f.id.shard.index, f.id.shard.count
                ),
                format!(
                    "a shard of the sweep of {} (fingerprint {}, {} shards): this is a shard of \
                     another sweep (another scene, other --set values, another shard count or another \
                     program version's arithmetic)",
                    first_path.display(),
                    first.id.fingerprint,
                    first.id.shard.count
                ),
            ));
        }
        if f.header != first.header {
            return Err(bad(
                path,
                format!("header {}", f.header.join(",")),
                format!(
                    "the header of {}: {}",
                    first_path.display(),
                    first.header.join(",")
                ),
            ));
        }
        if let Some(other) = shards.insert(f.id.shard.index, *path) {
            return Err(bad(
                path,
                format!("shard {}/{}", f.id.shard.index, f.id.shard.count),
                format!("each shard once (also given as {})", other.display()),
            ));
        }
        if !allow_partial && f.rows.len() != f.id.cases {
            return Err(bad(
                path,
                format!("{} of its {} cases", f.rows.len(), f.id.cases),
                "a finished shard (resume it with `jointwear sweep --resume`, or merge with \
                 --allow-partial)"
                    .into(),
            ));
        }
        for row in &f.rows {
            rows.push((case_of(path, row)?, row.clone()));
        }
    }
    // Fewer shards than the count: one of the first `shards.len() + 1` numbers is missing.
    let missing = (1..=first.id.shard.count).find(|i| !shards.contains_key(i));
    if let (false, Some(missing)) = (allow_partial, missing) {
        return Err(Error::invalid(
            "inputs",
            format!("no shard {missing}/{}", first.id.shard.count),
            "every shard of the sweep (or --allow-partial)",
        ));
    }
    rows.sort_by_key(|(case, _)| *case);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(Error::invalid(
            "case",
            w[0].0,
            "each case in only one shard file",
        ));
    }
    // An unfinished file at `out` is replaced only by a merge of its sweep that holds every
    // case it holds (a partial merge completed), as a sweep refuses it without --resume.
    if let Some(old) = unfinished(out)? {
        let merged: HashSet<usize> = rows.iter().map(|(case, _)| *case).collect();
        let kept = old.id.fingerprint == first.id.fingerprint
            && old.header == first.header
            && (old.rows.iter()).all(|r| case_of(out, r).is_ok_and(|c| merged.contains(&c)));
        if !kept {
            let what = "a sweep whose finished cases this merge does not all hold";
            return Err(refuse_unfinished(out, &old, what, "merge"));
        }
    }
    let rows: Vec<Vec<String>> = rows.into_iter().map(|(_, r)| r).collect();
    let count = rows.len();
    write_file(out, &first.id.whole(), &first.header, rows)?;
    Ok(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingerprints_tell_sweeps_apart() {
        let table = |text: &str| toml::Value::Table(text.parse().unwrap());
        let doc = table("a = 1\n[b]\nc = 2.5\n");
        let sets = |s: &str| vec![Assignment::parse(s).unwrap()];
        let f = fingerprint(&doc, &sets("b.c=1,2"));
        assert_eq!(f.len(), 16);
        assert_eq!(f, fingerprint(&doc, &sets("b.c=1,2")));
        assert_ne!(f, fingerprint(&doc, &sets("b.c=1,3")));
        assert_ne!(f, fingerprint(&doc, &sets("b.c=12")));
        let other = table("a = 2\n[b]\nc = 2.5\n");
        assert_ne!(f, fingerprint(&other, &sets("b.c=1,2")));
        // Another program version's arithmetic, another sweep: its runs differ by rounding.
        assert_ne!(f, fingerprint_of(&doc, &sets("b.c=1,2"), ARITHMETIC + 1));
    }

    #[test]
    fn the_id_column_name_round_trips_and_rejects_other_names() {
        let id = SweepId {
            fingerprint: "0123456789abcdef".into(),
            shard: Shard::parse("2/4").unwrap(),
            cases: 3,
            total: 12,
        };
        assert_eq!(
            id.column_name(),
            "jointwear sweep fingerprint=0123456789abcdef shard=2/4 cases=3 total=12"
        );
        assert_eq!(SweepId::parse(&id.column_name()), Some(id.clone()));
        assert_eq!(
            id.whole().column_name(),
            "jointwear sweep fingerprint=0123456789abcdef shard=1/1 cases=12 total=12"
        );
        for bad in [
            "case,x",
            "jointwear sweep shard=2/4 cases=3 total=12",
            "jointwear sweep fingerprint=f shard=5/4 cases=3 total=12",
        ] {
            assert_eq!(SweepId::parse(bad), None, "{bad}");
        }
    }
}
