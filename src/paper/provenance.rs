//! What produced the results of a study that the report reads back from `data/` instead of
//! computing them (calibration, work-precision, the ensemble-size study, the contact-law studies
//! and the others of `report::READ_BACK`), and the check that they are this checkout's.
//!
//! A study's CSVs were checked for their column layout only: after a scene under
//! `data/scenes/` changed, or the program's arithmetic, or a CSV was edited or cut short,
//! `paper.md` still printed the old numbers as this checkout's, exit 0. So every such study
//! leaves a record beside its first CSV, `data/<stem>.provenance.json`, written atomically
//! after its CSVs ([`recorded`]):
//!
//! ```json
//! {
//!   "study": "contact_law_wear",
//!   "variant": [],
//!   "jointwear": "0.1.0",
//!   "arithmetic": 3,
//!   "inputs": {
//!     "data/golden/paper.toml": "<fingerprint>",
//!     "data/scenes/clearance_0.5mm.toml": "<fingerprint>",
//!     "data/scenes/standard.toml": "<fingerprint>",
//!     "settings": "<fingerprint>"
//!   },
//!   "outputs": { "contact_law_wear.csv": { "bytes": 54122, "fnv1a": "<fingerprint>" } }
//! }
//! ```
//!
//! * `jointwear` and `arithmetic`: the crate's version and the version of what a run computes
//!   from its steps ([`ARITHMETIC`], which checkpoints and sweep files carry for the same
//!   reason: a run under other arithmetic is another run);
//! * `inputs`: what else decides its numbers, each as a fingerprint ([`fnv1a`], the
//!   crate's hash of its files): every scene it reads, as [`scene_fingerprint`] takes it (the
//!   document with `extends` resolved, so an edit of `standard.toml` reaches the scenes that
//!   extend it and a comment reaches none), the paper's values where it scores against them
//!   (`data/golden/paper.toml`, parsed the same way), and its settings (the constants of its
//!   code that choose what it runs, [`Inputs::settings`]), taken before it runs, so a scene
//!   edited while it runs makes its results stale rather than current;
//! * `variant`: the flags of its program that change what it runs (`contact_law_wear
//!   --table3`), each a study of its own that the report reads as well;
//! * `outputs`: each CSV it wrote, by length and fingerprint, so an edited row or a file cut
//!   short is seen.
//!
//! [`check`] compares a record with what this checkout would use. A study none of whose CSVs
//! exists is absent (its section of `paper.md` says so and prints no number); any other
//! difference (no record, an unreadable one, another study's, another version or arithmetic,
//! an input or a CSV that differs) is refused, every such study named in one error
//! ([`Error::Stale`], exit 2) with its file, what differs and the command that remakes it.
//!
//! Why refuse rather than print the section under a warning: the numbers read back do not stay
//! in their sections. The default tolerance stated in sections 5 and 7 is picked from the rule's
//! CSV, section 8 sets the contact-law study's rows beside section 1's fresh ensembles, the
//! perturbation study's verdicts fill a column of section 1's claims and the calibration feeds
//! the Why paragraph, so a label on one section would leave sentences elsewhere stating foreign
//! numbers as current. A refusal is also what the crate does with every other state file that
//! does not match (a sweep file, a checkpoint, a Python worker's result), and it keeps a stale
//! `data/` from passing the tests: they check the committed records.
//!
//! What the record cannot see: a change of the code that moves a study's numbers but neither its
//! settings, the crate's version nor [`ARITHMETIC`] (which such a change must raise, as it must
//! for checkpoints).

use crate::io::output::{fnv1a, read_bounded_text, write_json};
use crate::paper::figures::output_root;
use crate::paper::golden::read_toml;
use crate::scene::variant::fingerprint as scene_fingerprint;
use crate::scene::SceneFile;
use crate::simulation::checkpoint::ARITHMETIC;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A study whose results the report reads back from `data/`.
pub struct Study {
    /// Its CSVs under `data/`; the record is named after the first
    /// (`calibration.csv`: `calibration.provenance.json`).
    pub files: &'static [&'static str],
    /// The figures its run draws under `figures/` that `paper.md` shows as that run left them.
    /// Its record does not cover them (a figure redrawn from the CSV differs from the run's
    /// own drawing in its antialiasing), so the report's header lists them as unchecked.
    pub figures: &'static [&'static str],
    /// The command that reruns it alone.
    pub command: &'static str,
    /// Whether `report --all` reruns it.
    pub rerun_by_all: bool,
    /// The flags of its program that change what it runs (a record names those it ran with).
    pub variants: &'static [&'static str],
    /// What it reads, run with the given flags of [`Study::variants`].
    pub inputs: fn(&[String]) -> Inputs,
}

/// What decides a study's numbers besides the program's version and arithmetic.
pub struct Inputs {
    /// The scenes it reads, by name (`data/scenes/<name>.toml`).
    pub scenes: Vec<&'static str>,
    /// Whether it scores against the paper's values, `data/golden/paper.toml`.
    pub golden: bool,
    /// Its settings: the constants of its code that choose what it runs (members, seeds,
    /// tolerances, laws, grids), as text (`Debug` of a tuple of them).
    pub settings: String,
}

impl Inputs {
    /// A study's inputs: the `scenes` it reads, whether it scores against the paper's values
    /// (`golden`), and its `settings`, recorded as their `Debug` text.
    pub fn new(scenes: Vec<&'static str>, golden: bool, settings: impl std::fmt::Debug) -> Inputs {
        Inputs {
            scenes,
            golden,
            settings: format!("{settings:?}"),
        }
    }
}

/// The record's key of the study's settings.
const SETTINGS: &str = "settings";

/// A study's record, `data/<stem>.provenance.json`.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Record {
    /// The stem of the study's first CSV.
    study: String,
    /// The flags of [`Study::variants`] it ran with.
    variant: Vec<String>,
    /// The crate's version.
    jointwear: String,
    /// [`ARITHMETIC`].
    arithmetic: u32,
    /// Each input's fingerprint, by what it is (`data/scenes/standard.toml`, `settings`).
    inputs: BTreeMap<String, String>,
    /// Each CSV written, by name under `data/`.
    outputs: BTreeMap<String, Output>,
}

/// One file a study wrote.
#[derive(Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Output {
    bytes: u64,
    fnv1a: String,
}

impl Study {
    /// The stem of its first CSV, which names its record.
    fn stem(&self) -> &'static str {
        let first = self.files[0];
        first.strip_suffix(".csv").unwrap_or(first)
    }

    /// Its record under the data folder `data`.
    fn record_path(&self, data: &Path) -> PathBuf {
        data.join(format!("{}.provenance.json", self.stem()))
    }

    /// How to remake its results.
    fn remedy(&self) -> String {
        if self.rerun_by_all {
            format!(
                "rerun `cargo run --release --bin report -- --all` (or `{}` alone)",
                self.command
            )
        } else {
            format!("rerun `{}`", self.command)
        }
    }
}

/// `data/` of the checkout this was built from, where the studies write and the report reads.
fn checkout_data() -> PathBuf {
    output_root().join("data")
}

/// 16 hex digits of [`fnv1a`] of `bytes`.
fn hex(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

/// The fingerprints of the inputs of `study` run with `variant`, its scenes and the paper's
/// values read from the data folder `data`.
fn fingerprints(
    study: &Study,
    variant: &[String],
    data: &Path,
) -> Result<BTreeMap<String, String>> {
    let inputs = (study.inputs)(variant);
    let mut map = BTreeMap::new();
    for scene in inputs.scenes {
        // as the studies read it: `extends` resolved
        let document = SceneFile::read_document(data.join(format!("scenes/{scene}.toml")))?;
        let fingerprint = scene_fingerprint(&document, std::iter::empty());
        map.insert(format!("data/scenes/{scene}.toml"), fingerprint);
    }
    if inputs.golden {
        // parsed as a scene is, so that its comments do not count either
        let document: toml::Value = read_toml(data.join("golden/paper.toml"))?;
        let fingerprint = scene_fingerprint(&document, std::iter::empty());
        map.insert("data/golden/paper.toml".into(), fingerprint);
    }
    map.insert(SETTINGS.into(), hex(inputs.settings.as_bytes()));
    Ok(map)
}

/// The most bytes a record may have: a study's record has under 2 kB, and a larger file is
/// refused unread ([`read_bounded_text`]).
const MAX_RECORD_BYTES: u64 = 1 << 16;

/// The length of the file at `path`, `None` if there is none.
fn length_of(path: &Path) -> Result<Option<u64>> {
    match std::fs::metadata(path) {
        Ok(metadata) => Ok(Some(metadata.len())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(Error::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// The length and fingerprint of the file at `path`, `None` if there is none.
fn output_of(path: &Path) -> Result<Option<Output>> {
    match std::fs::read(path) {
        Ok(bytes) => Ok(Some(Output {
            bytes: bytes.len() as u64,
            fnv1a: hex(&bytes),
        })),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(Error::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// Runs `study` (with the flags `variant`) by `run`, which writes its CSVs into `data/`, then
/// writes its record beside them: its inputs as they were before it ran, its CSVs as written.
/// A failed run writes no record (one left by an earlier run no longer matches a CSV it
/// replaced).
pub fn recorded<T>(study: &Study, variant: &[&str], run: impl FnOnce() -> Result<T>) -> Result<T> {
    let data = checkout_data();
    let variant: Vec<String> = variant.iter().map(|f| f.to_string()).collect();
    let inputs = fingerprints(study, &variant, &data)?;
    let value = run()?;
    write_record(study, variant, inputs, &data)?;
    Ok(value)
}

/// Writes the record of `study` run with `variant` on `inputs`, of its CSVs as they are in
/// the data folder `data`.
fn write_record(
    study: &Study,
    variant: Vec<String>,
    inputs: BTreeMap<String, String>,
    data: &Path,
) -> Result<()> {
    let mut outputs = BTreeMap::new();
    for file in study.files {
        let path = data.join(file);
        let written = output_of(&path)?.ok_or_else(|| Error::Io {
            path,
            source: std::io::ErrorKind::NotFound.into(),
        })?;
        outputs.insert(file.to_string(), written);
    }
    let record = Record {
        study: study.stem().into(),
        variant,
        jointwear: env!("CARGO_PKG_VERSION").into(),
        arithmetic: ARITHMETIC,
        inputs,
        outputs,
    };
    write_json(&study.record_path(data), &record)
}

/// Whether none of the CSVs of `study` is in the data folder `data`: an absent study, which
/// [`check_in`] passes and whose section of `paper.md` says is missing. A CSV that cannot be
/// looked up (a folder it may not search) is not absent.
pub fn absent_in(study: &Study, data: &Path) -> bool {
    (study.files.iter()).all(|file| matches!(data.join(file).try_exists(), Ok(false)))
}

/// What makes the results of `study` in the data folder `data` other than this checkout's:
/// each difference, empty when they are this checkout's or when none of its CSVs is there (an
/// absent study, whose section says so). An error only when this checkout's own inputs cannot
/// be read.
fn differences(study: &Study, data: &Path) -> Result<Vec<String>> {
    if absent_in(study, data) {
        return Ok(Vec::new());
    }
    let path = study.record_path(data);
    let name = format!(
        "data/{}",
        path.file_name().unwrap_or_default().to_string_lossy()
    );
    let why = "a study's record has under 2 kB: a file larger than any study's record is not read";
    let parsed = match read_bounded_text(&path, MAX_RECORD_BYTES, "a study's record", why) {
        Ok(text) => serde_json::from_str::<Record>(&text).map_err(|e| e.to_string()),
        Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
            return Ok(vec![format!(
                "no record of what produced it ({name} is missing), so nothing says its numbers \
                 are this checkout's"
            )])
        }
        // too large, not a regular file, not UTF-8
        Err(Error::Parse { message, .. }) => Err(message),
        Err(e) => return Ok(vec![format!("its record {name} cannot be read: {e}")]),
    };
    let record = match parsed {
        Ok(record) => record,
        Err(why) => {
            return Ok(vec![format!(
                "its record {name} is not a study's record: {why}"
            )])
        }
    };
    if record.study != study.stem() {
        return Ok(vec![format!(
            "its record {name} is that of `{}`, another study's",
            record.study
        )]);
    }
    if let Some(flag) = (record.variant.iter()).find(|f| !study.variants.contains(&f.as_str())) {
        return Ok(vec![format!(
            "its record {name} names the flag `{flag}`, which the study does not take"
        )]);
    }
    let mut differs = Vec::new();
    let version = env!("CARGO_PKG_VERSION");
    if record.jointwear != version {
        differs.push(format!(
            "it was made by jointwear {}, this is {version}",
            record.jointwear
        ));
    }
    if record.arithmetic != ARITHMETIC {
        differs.push(format!(
            "it was made under arithmetic {} (the version of what a run computes from its steps), \
             this build's is {ARITHMETIC}",
            record.arithmetic
        ));
    }
    let now = fingerprints(study, &record.variant, data)?;
    for (input, fingerprint) in &now {
        let what = if input == SETTINGS {
            "the study's settings (the constants of its code that choose what it runs)".to_string()
        } else {
            input.clone()
        };
        match record.inputs.get(input) {
            Some(r) if r == fingerprint => {}
            Some(r) => differs.push(format!(
                "{what} differ{} from what it ran with (fingerprint {r} in {name}, {fingerprint} \
                 now)",
                if input == SETTINGS { "" } else { "s" }
            )),
            None => differs.push(format!("{what}, which it reads now, is not in {name}")),
        }
    }
    for input in record.inputs.keys().filter(|i| !now.contains_key(*i)) {
        differs.push(format!("{name} names {input}, which it does not read now"));
    }
    for file in study.files {
        let path = data.join(file);
        let Some(recorded) = record.outputs.get(*file) else {
            differs.push(format!("{name} does not describe data/{file}"));
            continue;
        };
        // its length first: a file of another length is not read (it may be huge)
        let found = match length_of(&path)? {
            Some(bytes) if bytes != recorded.bytes => Some(format!("{bytes} bytes")),
            Some(_) => output_of(&path)?
                .filter(|d| d != recorded)
                .map(|d| format!("{} bytes, fingerprint {}", d.bytes, d.fnv1a)),
            None => {
                differs.push(format!("data/{file} is missing"));
                continue;
            }
        };
        if let Some(found) = found {
            differs.push(format!(
                "data/{file} is not the file it wrote ({found}; {name} says {} bytes, {}): \
                 edited, cut short or replaced since, or a run of the study stopped before \
                 it wrote its record",
                recorded.bytes, recorded.fnv1a
            ));
        }
    }
    for file in record
        .outputs
        .keys()
        .filter(|f| !study.files.contains(&f.as_str()))
    {
        differs.push(format!(
            "{name} describes data/{file}, which the study does not write"
        ));
    }
    Ok(differs)
}

/// Checks that the results of every study of `studies` in the data folder `data` are this
/// checkout's (module documentation): an [`Error::Stale`] naming each that is not, with its
/// CSVs, what differs and the command that remakes it. A study none of whose CSVs is there
/// passes (its section says it is missing); an error of its own only when this checkout's
/// inputs cannot be read.
pub fn check_in(studies: &[&Study], data: &Path) -> Result<()> {
    let mut stale = Vec::new();
    for study in studies {
        let differs = differences(study, data)?;
        if !differs.is_empty() {
            let files: Vec<String> = study.files.iter().map(|f| format!("data/{f}")).collect();
            stale.push(format!(
                "{}: {}; {}",
                files.join(" and "),
                differs.join("; "),
                study.remedy()
            ));
        }
    }
    if stale.is_empty() {
        Ok(())
    } else {
        Err(Error::Stale { results: stale })
    }
}

/// [`check_in`] the checkout's `data/`.
pub fn check(studies: &[&Study]) -> Result<()> {
    check_in(studies, &checkout_data())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A study of one CSV that reads the standard scene and the paper's values, with
    /// `--wide` as a variant that also reads the 0.5 mm scene.
    const STUDY: Study = Study {
        files: &["tiny.csv"],
        figures: &[],
        command: "cargo run --release --bin tiny",
        rerun_by_all: false,
        variants: &["--wide"],
        inputs: |variant| {
            Inputs::new(
                if variant.is_empty() {
                    vec!["standard"]
                } else {
                    vec!["standard", "clearance_0.5mm"]
                },
                true,
                (16, 1e-7),
            )
        },
    };

    /// A data folder with the checkout's scenes and paper values, the study's CSV and, for
    /// `variant`, its record; removed when dropped.
    struct Copy(PathBuf);

    impl Copy {
        fn new(name: &str, variant: &[&str]) -> Copy {
            let dir = std::env::temp_dir().join(format!(
                "jointwear-provenance-{}-{name}",
                std::process::id()
            ));
            let _ = std::fs::remove_dir_all(&dir);
            let real = checkout_data();
            for sub in ["scenes", "golden"] {
                std::fs::create_dir_all(dir.join(sub)).unwrap();
                for entry in std::fs::read_dir(real.join(sub)).unwrap() {
                    let path = entry.unwrap().path();
                    if path.is_file() {
                        std::fs::copy(&path, dir.join(sub).join(path.file_name().unwrap()))
                            .unwrap();
                    }
                }
            }
            std::fs::write(dir.join("tiny.csv"), "a,b\n1,2\n3,4\n").unwrap();
            let variant: Vec<String> = variant.iter().map(|f| f.to_string()).collect();
            let inputs = fingerprints(&STUDY, &variant, &dir).unwrap();
            write_record(&STUDY, variant, inputs, &dir).unwrap();
            Copy(dir)
        }

        fn edit(&self, file: &str, from: &str, to: &str) {
            crate::test_support::edit_file(&self.0.join(file), from, to);
        }

        /// The one stale result [`check_in`] reports, which must name every one of `needles`.
        fn refused(&self, needles: &[&str]) -> String {
            let e = check_in(&[&STUDY], &self.0).expect_err("refused");
            assert_eq!(crate::error::exit_code(&e), 2);
            let Error::Stale { results } = &e else {
                panic!("{e}")
            };
            assert_eq!(results.len(), 1, "{results:?}");
            for needle in needles
                .iter()
                .chain(&["data/tiny.csv", "cargo run --release --bin tiny"])
            {
                assert!(results[0].contains(needle), "`{needle}` in {}", results[0]);
            }
            results[0].clone()
        }
    }

    impl Drop for Copy {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    const RECORD: &str = "tiny.provenance.json";

    #[test]
    fn a_study_as_it_was_written_is_accepted() {
        let copy = Copy::new("accepted", &[]);
        check_in(&[&STUDY], &copy.0).unwrap();
        let copy = Copy::new("variant", &["--wide"]);
        check_in(&[&STUDY], &copy.0).unwrap();
        // a comment of a scene decides nothing
        copy.edit("scenes/standard.toml", "\n", "\n# a note\n");
        check_in(&[&STUDY], &copy.0).unwrap();
    }

    // Each of the following fails with the check disabled (`check_in` returning Ok(()) at once).

    #[test]
    fn a_changed_scene_is_refused_naming_it() {
        let copy = Copy::new("scene", &[]);
        copy.edit("scenes/standard.toml", "rotations = 40", "rotations = 39");
        copy.refused(&["data/scenes/standard.toml differs from what it ran with"]);
        // through `extends`: the 0.5 mm scene of the variant is the standard one changed
        let copy = Copy::new("extends", &["--wide"]);
        copy.edit("scenes/standard.toml", "rotations = 40", "rotations = 39");
        let why = copy.refused(&["data/scenes/clearance_0.5mm.toml differs"]);
        assert!(why.contains("data/scenes/standard.toml differs"), "{why}");
        // the paper's values too
        let copy = Copy::new("golden", &[]);
        copy.edit("golden/paper.toml", "0.8684", "0.8685");
        copy.refused(&["data/golden/paper.toml differs"]);
    }

    #[test]
    fn an_edited_or_cut_csv_is_refused() {
        let copy = Copy::new("edited", &[]);
        copy.edit("tiny.csv", "3,4", "3,5");
        copy.refused(&[
            "data/tiny.csv is not the file it wrote (12 bytes",
            "says 12 bytes",
        ]);
        let copy = Copy::new("cut", &[]);
        copy.edit("tiny.csv", "3,4\n", "");
        copy.refused(&["(8 bytes", "says 12 bytes", "cut short"]);
    }

    /// A CSV or a record far larger than a study writes (output redirected into `data/` by
    /// mistake) is refused by its length, without being read: it was read whole before it
    /// was compared, and one larger than the memory stopped the report with an error of
    /// reading (exit 1) instead of naming the study. Sparse files: they take no disk.
    #[test]
    fn a_huge_csv_or_record_is_refused_unread() {
        const HUGE: u64 = 1 << 40;
        let copy = Copy::new("huge-csv", &[]);
        let csv = std::fs::OpenOptions::new()
            .write(true)
            .open(copy.0.join("tiny.csv"))
            .unwrap();
        csv.set_len(HUGE).unwrap();
        copy.refused(&[&format!("({HUGE} bytes; "), "says 12 bytes"]);
        let copy = Copy::new("huge-record", &[]);
        let record = std::fs::OpenOptions::new()
            .append(true)
            .open(copy.0.join(RECORD))
            .unwrap();
        record.set_len(HUGE).unwrap();
        copy.refused(&["larger than any study's record"]);
    }

    #[test]
    fn a_missing_unreadable_or_foreign_record_is_refused() {
        let copy = Copy::new("missing", &[]);
        std::fs::remove_file(copy.0.join(RECORD)).unwrap();
        copy.refused(&["no record", "data/tiny.provenance.json is missing"]);
        let copy = Copy::new("garbled", &[]);
        copy.edit(RECORD, "{", "[");
        copy.refused(&["is not a study's record"]);
        let copy = Copy::new("foreign", &[]);
        copy.edit(RECORD, "\"study\": \"tiny\"", "\"study\": \"other\"");
        copy.refused(&["that of `other`"]);
        let copy = Copy::new("flag", &["--wide"]);
        copy.edit(RECORD, "--wide", "--narrow");
        copy.refused(&["the flag `--narrow`"]);
    }

    #[test]
    fn a_record_of_another_version_arithmetic_or_setting_is_refused() {
        let copy = Copy::new("version", &[]);
        let version = format!("\"jointwear\": \"{}\"", env!("CARGO_PKG_VERSION"));
        copy.edit(RECORD, &version, "\"jointwear\": \"0.0.9\"");
        copy.refused(&[&format!(
            "made by jointwear 0.0.9, this is {}",
            env!("CARGO_PKG_VERSION")
        )]);
        let copy = Copy::new("arithmetic", &[]);
        let arithmetic = format!("\"arithmetic\": {ARITHMETIC}");
        copy.edit(RECORD, &arithmetic, "\"arithmetic\": 1");
        copy.refused(&["under arithmetic 1"]);
        let copy = Copy::new("settings", &[]);
        let settings = hex(format!("{:?}", (16, 1e-7)).as_bytes());
        copy.edit(RECORD, &settings, &hex(b"(32, 1e-7)"));
        copy.refused(&["the study's settings (the constants of its code"]);
    }

    #[test]
    fn an_absent_study_is_left_to_its_section() {
        let copy = Copy::new("absent", &[]);
        std::fs::remove_file(copy.0.join("tiny.csv")).unwrap();
        check_in(&[&STUDY], &copy.0).unwrap();
    }
}
