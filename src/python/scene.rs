//! The scene document Python holds ([`Document`]): loaded from a file or built from a dict,
//! varied by dotted keys, and validated, run, run as an ensemble or swept; each result handed
//! back as plain Python objects that the package `jointwear` wraps as numpy arrays.

use super::convert::{f64_bytes, from_toml, to_toml};
use super::{to_py_err, SimulationError};
use crate::analysis::states::{States, STATE_COLUMNS, STATE_COUNTS};
use crate::analysis::statistics::{Distribution, VALUE_KEYS};
use crate::analysis::Motion;
use crate::io::lock::claim_folder;
use crate::io::output::{check_output_dir, read_bounded_text, write_text};
use crate::io::paper_claim::claim_output;
use crate::io::progress::Progress;
use crate::laws::wear::sector_angles_deg;
use crate::scene::variant::{Change, Variant};
use crate::scene::{reversal_note, SceneFile, MAX_SCENE_BYTES};
use crate::simulation::checkpoint::{refuse_checkpoint, ARITHMETIC};
use crate::simulation::ensemble::{self, EnsembleSettings, Perturbation, MAX_MEMBERS};
use crate::simulation::folder::ensemble::{write_ensemble, Member};
use crate::simulation::folder::run::{write_run, EnsembleMember};
use crate::simulation::folder::{check_manifest, FolderCommand, Origin, PROGRAM};
use crate::simulation::summary::{joint_statistics, summarize, window, JointSummary, SCALARS};
use crate::simulation::{simulate_with_progress, RunOutput, Scene};
use crate::sweep::{Assignment, CaseResult, Outcome, Shard, Sweep, RECORD_COLUMNS};
use crate::Error;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// A scene document (TOML values, `extends` resolved) and the changes made to it by `set`, as
/// the program's `--set` and `--rotations` make them ([`Variant`]).
#[pyclass(module = "jointwear._native")]
pub struct Document {
    variant: Variant,
}

/// The wear profiles of one member's snapshots: per snapshot, per joint, per sector.
type Snapshots = Vec<Vec<Vec<f64>>>;

/// One ensemble member as a worker of a Python executor hands it back ([`Document::member`]):
/// JSON with every `f64` written so that it reads back identical, with what it is the member
/// of ([`Sent`]).
#[derive(Serialize, Deserialize)]
struct MemberPayload {
    joints: Vec<JointSummary>,
    final_wear: Vec<Vec<f64>>,
    snapshots: Snapshots,
    wall_time_s: f64,
}

/// A member's [`MemberPayload`] with what it claims to be: which member of which ensemble of
/// which scene, run by which program. A worker of another build, or of another scene or
/// seed, is refused when its result is gathered ([`Document::ensemble_of`]) instead of being
/// pooled as a member of this ensemble.
#[derive(Serialize, Deserialize, PartialEq)]
struct Sent {
    program: String,
    arithmetic: u32,
    fingerprint: String,
    member: usize,
    members: usize,
    seed: u64,
    perturbation: String,
}

impl Document {
    /// What the payload of member `member` of the ensemble `settings` of this scene says it is.
    fn sent(&self, settings: &EnsembleSettings, member: usize) -> Sent {
        Sent {
            program: PROGRAM.to_string(),
            arithmetic: ARITHMETIC,
            fingerprint: self.variant.fingerprint(),
            member,
            members: settings.members,
            seed: settings.seed,
            perturbation: settings.perturbation.key(),
        }
    }

    /// The validated scene in SI units; errors as the program reports a scene's.
    fn scene(&self) -> PyResult<Scene> {
        self.variant.build().map_err(|e| self.error(e))
    }

    /// The Python exception of an error about this scene.
    fn error(&self, e: Error) -> PyErr {
        to_py_err(self.variant.path(), e, true)
    }

    /// A variant read as given, checked by building it (as the program does on loading).
    fn checked(variant: Variant) -> PyResult<Document> {
        let d = Document { variant };
        d.scene()?;
        Ok(d)
    }

    /// The ensemble settings of `members`, `seed` and the protocol named `perturbation` (the
    /// default for `None`), checked: a protocol the program's `--perturbation` refuses is a
    /// `ValueError` with its message, which names the forms allowed.
    fn ensemble_settings(
        &self,
        members: usize,
        seed: u64,
        perturbation: Option<&str>,
    ) -> PyResult<EnsembleSettings> {
        let perturbation = perturbation.map_or(Ok(Perturbation::default()), |key| {
            Perturbation::from_key(key)
                .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
        })?;
        let settings = EnsembleSettings {
            members,
            seed,
            perturbation,
        };
        settings.validate().map_err(|e| self.error(e))?;
        Ok(settings)
    }

    /// The sweep of `values[i]` at `keys[i]`, each case once or as an ensemble of `members`,
    /// every value validated.
    fn make_sweep(
        &self,
        keys: &[String],
        values: &[Vec<Bound<'_, PyAny>>],
        members: Option<usize>,
        seed: u64,
    ) -> PyResult<Sweep> {
        if keys.len() != values.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} keys but {} lists of values",
                keys.len(),
                values.len()
            )));
        }
        let mut sets = Vec::new();
        for (key, vs) in keys.iter().zip(values) {
            if vs.is_empty() {
                return Err(self.error(Error::invalid(
                    key.as_str(),
                    "[]",
                    "at least one value to sweep",
                )));
            }
            let texts = vs
                .iter()
                .map(|v| to_toml(v, key).map(|t| t.to_string()))
                .collect::<PyResult<Vec<_>>>()?;
            sets.push(Assignment {
                key: key.clone(),
                values: texts,
            });
        }
        let doc = self.variant.document();
        // The library names the program's option; from Python the values came in `grid`.
        let as_grid = |e| match e {
            Error::Invalid {
                field,
                value,
                expected,
            } if field == "--set" => Error::invalid("grid", value, expected),
            e => e,
        };
        let mut sweep = Sweep::from_document(doc, self.variant.path(), sets, Shard::ALL)
            .map_err(|e| self.error(as_grid(e)))?;
        if let Some(members) = members {
            sweep = sweep
                .with_ensemble(EnsembleSettings {
                    members,
                    seed,
                    ..EnsembleSettings::default()
                })
                .map_err(|e| self.error(e))?;
        }
        Ok(sweep)
    }
}

#[pymethods]
impl Document {
    /// Reads the scene file at `path` (resolving `extends` and `[overrides]`) and validates it.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Document> {
        let variant = Variant::read(&path).map_err(|e| to_py_err(&path, e, true))?;
        Document::checked(variant)
    }

    /// A scene from a dict of the keys of a scene file, named `<base_dir>/<dict>`
    /// ([`DICT_NAME`]) in messages; a relative `extends` is found in `base_dir` (default: the
    /// working directory).
    #[staticmethod]
    #[pyo3(signature = (table, base_dir=None))]
    fn from_dict(table: &Bound<'_, PyDict>, base_dir: Option<PathBuf>) -> PyResult<Document> {
        let path = base_dir.unwrap_or_default().join(DICT_NAME);
        let doc = to_toml(table.as_any(), "")?;
        let doc = SceneFile::resolve_document(doc, &path).map_err(|e| to_py_err(&path, e, true))?;
        Document::checked(Variant::new(doc, &path))
    }

    /// The document as text ([`Variant::state`]): `(path, document as loaded, changes)`, which
    /// [`Document::from_state`] makes an identical document of, in another process.
    fn state(&self) -> PyResult<(PathBuf, String, Vec<Change>)> {
        let (loaded, asked) = self.variant.state().map_err(|e| self.error(e))?;
        Ok((self.variant.path().to_path_buf(), loaded, asked))
    }

    /// The document of [`Document::state`].
    #[staticmethod]
    fn from_state(path: PathBuf, loaded: &str, asked: Vec<Change>) -> PyResult<Document> {
        let variant =
            Variant::restore(&path, loaded, &asked).map_err(|e| to_py_err(&path, e, true))?;
        Ok(Document { variant })
    }

    /// Sets the value at a dotted key, as the program's `--set` (`clearance.0.clearance_mm`),
    /// all or nothing: a key the scene file does not have, or a value of the wrong type, raises
    /// and leaves the document as it was; values out of range are refused when the scene is
    /// next checked or run. `run.rotations` cuts the wear snapshots and recorded rotations as
    /// the program's `--rotations` does (unless they were set), with a note on Python's
    /// `sys.stderr` ([`show_note`]).
    fn set(&mut self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let value = to_toml(value, key)?;
        let text = value.to_string();
        let note = reversal_note(self.variant.loaded(), key, &value);
        let cuts = (self.variant.set(key, value, &text, true)).map_err(|e| match e {
            // The scene reader's message names a field, not the call it came from.
            Error::Parse { .. } => self.error(e.in_context(&format!("with set({key:?}, …)"))),
            e => self.error(e),
        })?;
        for (cut, value) in cuts {
            show_note(
                py,
                &format!("set(\"run.rotations\", {text}) sets {cut} = {value}"),
            );
        }
        if let Some(note) = note {
            show_note(py, &note);
        }
        Ok(())
    }

    /// The document as nested dicts and lists.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_toml(py, self.variant.document())
    }

    /// The path that names the scene in messages.
    #[getter]
    fn path(&self) -> PathBuf {
        self.variant.path().to_path_buf()
    }

    /// An independent copy.
    fn copy(&self) -> Document {
        Document {
            variant: self.variant.clone(),
        }
    }

    /// Validates and assembles the scene and turns its driver through one rotation as
    /// `jointwear check` does; returns its title, bodies, clearance joints (name, radial
    /// clearance in m, sectors or None without wear), degrees of freedom and driver period (s).
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene()?;
        let m = &scene.mechanism;
        let y = m.assemble(&scene.guess).map_err(|e| self.error(e))?;
        if let Some(lock) = m.check_rotation(0.0, &y).map_err(|e| self.error(e))? {
            return Err(self.error(lock.error()));
        }
        let d = PyDict::new(py);
        d.set_item("title", &scene.title)?;
        let bodies: Vec<&str> = m.bodies().iter().map(|b| b.name.as_str()).collect();
        d.set_item("bodies", bodies)?;
        let joints = PyList::empty(py);
        for cj in &m.clearance_joints {
            let j = PyDict::new(py);
            j.set_item("name", &cj.name)?;
            j.set_item("clearance_m", cj.given_clearance)?;
            j.set_item("bearing_radius_m", cj.r_bearing)?;
            let sectors = cj.wear.is_some().then(|| cj.initial_profile.depths().len());
            j.set_item("sectors", sectors)?;
            j.set_item("stiffness", cj.contact.stiffness_law().name())?;
            j.set_item("dissipation", cj.contact.dissipation_law().name())?;
            joints.append(j)?;
        }
        d.set_item("joints", joints)?;
        d.set_item("dof", m.degrees_of_freedom())?;
        d.set_item("period_s", scene.period())?;
        d.set_item("rotations", scene.run.rotations)?;
        Ok(d)
    }

    /// Simulates the scene with the GIL released, or with `member`, member `member` of the
    /// ensemble of `seed` and `perturbation` (`jointwear run --member K --seed S
    /// --perturbation P`); returns the time series (the
    /// columns of `jointwear run`'s `timeseries.csv`, then every body's position), the final
    /// wear profile and summary of every clearance joint, the wear snapshots, the run's
    /// counters and, as `folder`, the [`Folder`] that saves it as the program does.
    #[pyo3(signature = (member=None, seed=1, perturbation=None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        member: Option<usize>,
        seed: u64,
        perturbation: Option<&str>,
    ) -> PyResult<Bound<'py, PyDict>> {
        if member.is_none() && perturbation.is_some() {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "perturbation applies to an ensemble member: give member=K with it (as the \
                 program's --perturbation needs --member or --ensemble)",
            ));
        }
        let of = self.ensemble_settings(MAX_MEMBERS, seed, perturbation)?;
        let scene = self.scene()?;
        let out = interruptible(py, |cancel| match member {
            Some(k) => ensemble::run_member(&scene, &scene.run, &of, k, cancel),
            None => simulate_with_progress(&scene, cancel),
        })?;
        let out = out.map_err(|e| self.error(e))?;
        let d = run_dict(py, &scene, &out)?;
        let which = member.map(|k| EnsembleMember::of(&of, k));
        d.set_item("ensemble_member", serde_dict(py, which)?)?;
        let folder = Folder(Kept::Run {
            variant: self.variant.clone(),
            member: member.map(|k| (of, k)),
            scene,
            out: Box::new(out),
        });
        d.set_item("folder", folder)?;
        Ok(d)
    }

    /// Runs `members` members of the scene, perturbed by `perturbation` (default: seeded
    /// initial offsets of at most 10 nm), in parallel with the GIL released; returns, per clearance joint, every member's scalar
    /// results, final profile and snapshots, and their statistics with the states the members
    /// fall into (see [`Document::ensemble_of`]).
    #[pyo3(signature = (members, seed, perturbation=None))]
    fn ensemble<'py>(
        &self,
        py: Python<'py>,
        members: usize,
        seed: u64,
        perturbation: Option<&str>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let settings = self.ensemble_settings(members, seed, perturbation)?;
        let scene = self.scene()?;
        let clock = std::time::Instant::now();
        let keep = |_, o: RunOutput| payload(&scene, o);
        let kept = interruptible(py, |cancel| ensemble::run(&scene, &settings, keep, cancel))?;
        let kept = kept.map_err(|e| self.error(e))?;
        let wall = clock.elapsed().as_secs_f64();
        self.ensemble_result(py, scene, settings, kept, wall)
    }

    /// Checks an ensemble of `members`, `seed` and `perturbation` of this scene as
    /// [`Document::ensemble`] does, without running it: before an executor's workers run its
    /// members.
    #[pyo3(signature = (members, seed, perturbation=None))]
    fn check_ensemble(
        &self,
        members: usize,
        seed: u64,
        perturbation: Option<&str>,
    ) -> PyResult<()> {
        self.ensemble_settings(members, seed, perturbation)?;
        self.scene().map(drop)
    }

    /// Runs member `member` of the ensemble of `members`, `seed` and `perturbation` with the
    /// GIL released (what [`Document::ensemble`] runs for it, bit for bit), for a worker of an
    /// executor: returns it as JSON for [`Document::ensemble_of`].
    #[pyo3(signature = (member, members, seed, perturbation=None))]
    fn member(
        &self,
        py: Python<'_>,
        member: usize,
        members: usize,
        seed: u64,
        perturbation: Option<&str>,
    ) -> PyResult<String> {
        let settings = self.ensemble_settings(members, seed, perturbation)?;
        let scene = self.scene()?;
        let out = interruptible(py, |cancel| {
            ensemble::run_member(&scene, &scene.run, &settings, member, cancel)
        })?;
        let out = out.map_err(|e| self.error(e))?;
        serde_json::to_string(&(self.sent(&settings, member), payload(&scene, out)))
            .map_err(|e| SimulationError::new_err(format!("member {member}: {e}")))
    }

    /// The ensemble of `members`, `seed` and `perturbation` of the members `payloads`
    /// ([`Document::member`], in member order) that took `wall` seconds: the dict of
    /// [`Document::ensemble`].
    #[pyo3(signature = (members, seed, payloads, wall, perturbation=None))]
    fn ensemble_of<'py>(
        &self,
        py: Python<'py>,
        members: usize,
        seed: u64,
        payloads: Vec<String>,
        wall: f64,
        perturbation: Option<&str>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let settings = self.ensemble_settings(members, seed, perturbation)?;
        if payloads.len() != members {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} members' results for an ensemble of {members}",
                payloads.len()
            )));
        }
        let kept = (payloads.iter().enumerate())
            .map(|(k, p)| {
                let bad = |why: String| {
                    pyo3::exceptions::PyValueError::new_err(format!("member {k}'s result: {why}"))
                };
                let (sent, kept): (Sent, MemberPayload) =
                    serde_json::from_str(p).map_err(|e| bad(e.to_string()))?;
                let expected = self.sent(&settings, k);
                if sent != expected {
                    return Err(bad(format!(
                        "it is member {} of {} (seed {}, {}) of the scene with fingerprint {} \
                         run by {} (arithmetic {}), not member {k} of {} (seed {}, {}) of this \
                         scene ({}) run by {} (arithmetic {}); likely cause: a worker of \
                         another build of jointwear, or tasks gathered out of order",
                        sent.member,
                        sent.members,
                        sent.seed,
                        sent.perturbation,
                        sent.fingerprint,
                        sent.program,
                        sent.arithmetic,
                        expected.members,
                        expected.seed,
                        expected.perturbation,
                        expected.fingerprint,
                        expected.program,
                        expected.arithmetic,
                    )));
                }
                Ok(kept)
            })
            .collect::<PyResult<Vec<MemberPayload>>>()?;
        self.ensemble_result(py, self.scene()?, settings, kept, wall)
    }

    /// Runs the cartesian product of `values[i]` at `keys[i]` (the last key varying fastest,
    /// as `jointwear sweep`), each case once or as an ensemble of `members`, in parallel with
    /// the GIL released; every case is validated before any runs. Returns the keys as the
    /// program's sweep header spells them (canonical: an array index as its number) and one
    /// dict per case: `case`, `error` (None, or the message of a case that failed while
    /// running, as in the program's sweep file), `wall_time_s` and the columns of the
    /// program's sweep file.
    #[pyo3(signature = (keys, values, members=None, seed=1))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        keys: Vec<String>,
        values: Vec<Vec<Bound<'py, PyAny>>>,
        members: Option<usize>,
        seed: u64,
    ) -> PyResult<(Vec<String>, Bound<'py, PyList>)> {
        let sweep = self.make_sweep(&keys, &values, members, seed)?;
        show_notes(py, &sweep);
        let results = interruptible(py, |cancel| {
            let results = Mutex::new(Vec::new());
            let collect = |r| results.lock().unwrap_or_else(|e| e.into_inner()).push(r);
            sweep.run(collect, cancel);
            let mut results = results.into_inner().unwrap_or_else(|e| e.into_inner());
            results.sort_unstable_by_key(|r: &CaseResult| r.case);
            results
        })?;
        let cases = PyList::empty(py);
        for r in &results {
            cases.append(case_dict(py, r)?)?;
        }
        Ok((canonical_keys(&sweep), cases))
    }

    /// Checks the sweep of [`Document::sweep`] without running it and returns its keys as the
    /// program's sweep header spells them (canonical: an array index as its number), its
    /// case count and its identity ([`sweep_identity`]), before any case runs.
    #[pyo3(signature = (keys, values, members=None, seed=1))]
    fn check_sweep<'py>(
        &self,
        py: Python<'py>,
        keys: Vec<String>,
        values: Vec<Vec<Bound<'py, PyAny>>>,
        members: Option<usize>,
        seed: u64,
    ) -> PyResult<(Vec<String>, usize, String)> {
        let sweep = self.make_sweep(&keys, &values, members, seed)?;
        show_notes(py, &sweep);
        Ok((canonical_keys(&sweep), sweep.total, sweep_identity(&sweep)))
    }

    /// Runs case `case` of the sweep of [`Document::sweep`] with the GIL released, for a
    /// worker of an executor: the dict [`Document::sweep`] returns for it, and as `sweep` the
    /// sweep's identity ([`sweep_identity`]), which the caller checks against its own.
    #[pyo3(signature = (keys, values, case, members=None, seed=1))]
    fn sweep_case<'py>(
        &self,
        py: Python<'py>,
        keys: Vec<String>,
        values: Vec<Vec<Bound<'py, PyAny>>>,
        case: usize,
        members: Option<usize>,
        seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let sweep = self.make_sweep(&keys, &values, members, seed)?;
        if case >= sweep.total {
            let expected = format!("a case in [0, {})", sweep.total);
            return Err(self.error(Error::invalid("case", case, expected)));
        }
        let result = interruptible(py, |cancel| sweep.run_case(case, cancel))?;
        let d = case_dict(py, &result)?;
        d.set_item("sweep", sweep_identity(&sweep))?;
        Ok(d)
    }
}

impl Document {
    /// The dict of an ensemble of `scene` with `settings` whose members `kept` took `wall`
    /// seconds, with the [`Folder`] that saves it.
    fn ensemble_result<'py>(
        &self,
        py: Python<'py>,
        scene: Scene,
        settings: EnsembleSettings,
        kept: Vec<MemberPayload>,
        wall: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut members = Vec::with_capacity(kept.len());
        let (mut walls, mut snapshots) = (Vec::new(), Vec::new());
        for p in kept {
            members.push((p.joints, p.final_wear));
            walls.push(p.wall_time_s);
            snapshots.push(p.snapshots);
        }
        let d = ensemble_dict(py, &scene, &settings, (&members, &snapshots), wall)?;
        let folder = Folder(Kept::Ensemble {
            variant: self.variant.clone(),
            scene,
            settings,
            members,
            walls,
            wall,
        });
        d.set_item("folder", folder)?;
        Ok(d)
    }
}

/// What a member keeps of its run for an ensemble: its summaries, final wear, snapshots and
/// wall time.
fn payload(scene: &Scene, out: RunOutput) -> MemberPayload {
    MemberPayload {
        joints: summarize(scene, &out),
        snapshots: out.wear_snapshots.into_iter().map(|s| s.depths).collect(),
        final_wear: out.final_wear,
        wall_time_s: out.wall_time,
    }
}

/// One case of a sweep as a dict: `case`, `error`, and with no error `wall_time_s`, the
/// recorded window ([`RECORD_COLUMNS`]) and the columns of the program's sweep file.
fn case_dict<'py>(py: Python<'py>, r: &CaseResult) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("case", r.case)?;
    match &r.outcome {
        Err(message) => d.set_item("error", message)?,
        Ok((outcome, recorded, wall)) => {
            d.set_item("error", py.None())?;
            d.set_item("wall_time_s", wall)?;
            d.set_item(RECORD_COLUMNS[0], recorded.rotations)?;
            d.set_item(RECORD_COLUMNS[1], recorded.interval_s)?;
            sweep_columns(&d, outcome)?;
        }
    }
    Ok(d)
}

/// A run or an ensemble that Python holds, to be saved as the `jointwear` program saves it
/// ([`crate::simulation::folder`]): `Run.save` and `Ensemble.save`.
#[pyclass(module = "jointwear._native")]
pub struct Folder(Kept);

/// What a [`Folder`] holds.
enum Kept {
    /// One run, with the ensemble member it is.
    Run {
        variant: Variant,
        scene: Scene,
        out: Box<RunOutput>,
        member: Option<(EnsembleSettings, usize)>,
    },
    /// An ensemble: its members in order, their wall times and the ensemble's (s).
    Ensemble {
        variant: Variant,
        scene: Scene,
        settings: EnsembleSettings,
        members: Vec<Member>,
        walls: Vec<f64>,
        wall: f64,
    },
}

/// The argument of `Run.save` and `Ensemble.save` that a refusal of their folder names.
const SAVE_ARGUMENT: &str = "directory";

/// What a Python user can do about a `directory` holding another command's outputs.
const SAVE_REMEDY: &str = "call save with another directory (Run.save writes the folder of \
                           `jointwear run`, or of `run --member` for a member, Ensemble.save \
                           that of `run --ensemble`) or move those files away first";

#[pymethods]
impl Folder {
    /// Writes the folder `dir` as `jointwear run … --out dir` does (with `--ensemble N --seed
    /// S` or `--member K --seed S` as the results are), claimed against other writers while
    /// it is written, with the paper's outputs if it lies among them, as the program's
    /// commands claim them ([`claim_output`]); the files of an earlier write of the
    /// same command into it are replaced, and a folder of another command's outputs, or
    /// holding the checkpoint of an unfinished run, is refused before anything is written, the
    /// refusal naming the Python argument (`directory`) and what a Python user can do. A scene
    /// built from a dict is written into the folder first ([`save_scene`]), for its command
    /// line to name.
    fn save(&self, py: Python<'_>, dir: PathBuf) -> PyResult<()> {
        let (variant, scene) = match &self.0 {
            Kept::Run { variant, scene, .. } | Kept::Ensemble { variant, scene, .. } => {
                (variant, scene)
            }
        };
        let command = match &self.0 {
            Kept::Run { member: None, .. } => FolderCommand::Run,
            Kept::Run {
                member: Some(_), ..
            } => FolderCommand::Member,
            Kept::Ensemble { .. } => FolderCommand::Ensemble,
        };
        // The claims' notes (a stale lock taken over), shown once the GIL is held again.
        let mut notes = Vec::new();
        let written = py.detach(|| {
            check_output_dir(SAVE_ARGUMENT, &dir)?;
            // (Both held until the folder is written.) The paper's outputs too if the folder
            // lies among them: a paper program writing there at once could replace the
            // folder's files, or they its own.
            let _claims = claim_output(SAVE_ARGUMENT, &dir, claim_folder, &mut |n| {
                notes.extend_from_slice(n)
            })?;
            check_manifest(SAVE_ARGUMENT, &dir, command, SAVE_REMEDY)?;
            // Another run's state: results saved beside it would be mixed with it, and
            // replaced by a later `--resume` of that run.
            let how = "continue that run with `jointwear run ... --resume --out` this \
                       directory, or remove the checkpoint if that run is not to go on";
            refuse_checkpoint(SAVE_ARGUMENT, &dir, how)?;
            let origin = if variant.path().file_name() == Some(DICT_NAME.as_ref()) {
                save_scene(&dir, variant)?
            } else {
                variant.origin()
            };
            match &self.0 {
                Kept::Run { out, member, .. } => {
                    let member = member.as_ref().map(|(e, k)| (e, *k));
                    write_run(&dir, &origin, scene, out, member).map(drop)
                }
                Kept::Ensemble {
                    settings,
                    members,
                    walls,
                    wall,
                    ..
                } => write_ensemble(&dir, &origin, scene, settings, (members, walls), *wall)
                    .map(drop),
            }
        });
        notes.iter().for_each(|n| show_note(py, n));
        written.map_err(|e| to_py_err(variant.path(), e, false))
    }
}

/// The name of a scene built from a dict (`Scene.from_dict`): no file holds it.
const DICT_NAME: &str = "<dict>";

/// The file into which `save` writes the scene of a dict ([`save_scene`]).
const SAVED_SCENE: &str = "scene.toml";

/// The first line of every scene file [`save_scene`] writes: it tells an earlier save's
/// `scene.toml`, which the next save replaces, from the user's own (a TOML comment, so the
/// scene and its fingerprint are as without it).
const SAVED_SCENE_MARK: &str = "# The scene built from a dict that Run.save or Ensemble.save \
                                of jointwear saved with this folder; the next save replaces it";

/// Writes the scene document of `variant`, built from a dict, as read (before its changes) to
/// `dir/scene.toml`, under [`SAVED_SCENE_MARK`], and returns the origin of the variant named
/// by that file: the folder's command line then reruns it (`jointwear run DIR/scene.toml --set
/// …`) with the same fingerprint, which a dict's name (`<dict>`) could not. A `scene.toml`
/// without that mark (on a line ending in LF or CRLF), unless it holds this very scene (as a
/// save of an earlier version wrote it), is refused: it is the user's own, even where the
/// folder's manifest names it (the program's run of that file into its folder, `jointwear run
/// D/scene.toml --out D`, names it as a save's does).
fn save_scene(dir: &Path, variant: &Variant) -> crate::Result<Origin> {
    let path = dir.join(SAVED_SCENE);
    let saved = variant.named(&path);
    let (text, _) = saved.state()?;
    // (An earlier save's, also with its line ends turned into CRLF, or one that holds this
    // very scene, as versions before the mark saved it: replacing it loses nothing.)
    let saves = |old: String| {
        let rest = old.strip_prefix(SAVED_SCENE_MARK).unwrap_or_default();
        rest.starts_with('\n') || rest.starts_with("\r\n") || old == text
    };
    let why = "1 MiB; the largest shipped scene is a few kB";
    if path.exists()
        && !read_bounded_text(&path, MAX_SCENE_BYTES, "a scene file", why).is_ok_and(saves)
    {
        return Err(Error::invalid(
            SAVE_ARGUMENT,
            dir.display(),
            format!(
                "a folder without another scene's {SAVED_SCENE}: it holds {}, which saving a \
                 scene built from a dict would replace with that scene (the folder's command \
                 line runs it); call save with another directory or move that file away first",
                path.display()
            ),
        ));
    }
    write_text(&path, &format!("{SAVED_SCENE_MARK}\n{text}"))?;
    Ok(saved.origin())
}

/// The scalar columns of one sweep case, named as in the program's sweep file.
fn sweep_columns(d: &Bound<'_, PyDict>, outcome: &Outcome) -> PyResult<()> {
    match outcome {
        Outcome::Run(summaries) => {
            for s in summaries {
                for (name, x) in s.scalars() {
                    d.set_item(format!("{}.{name}", s.name), x)?;
                }
                let mode = s.motion.as_ref().map(Motion::mode);
                d.set_item(format!("{}.motion_mode", s.name), mode)?;
            }
        }
        Outcome::Ensemble(members, stats) => {
            d.set_item("members", members)?;
            for j in stats {
                for (name, states) in &j.quantities {
                    let dist = &states.pooled;
                    let column = |c: &str| format!("{}.{name}.{c}", j.name);
                    d.set_item(column("n"), dist.n)?;
                    d.set_item(column("mean"), dist.mean)?;
                    d.set_item(column("sd"), dist.sd)?;
                    // NaN where the file's cell is empty, as in every column of a sweep.
                    for (c, value) in STATE_COLUMNS.iter().zip(states.values()) {
                        d.set_item(column(c), value.unwrap_or(f64::NAN))?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Writes `note: {text}` to Python's `sys.stderr`, where its user sees it: a notebook shows
/// that stream, not the process's stderr, to which the notes used to go unseen. A note never
/// fails the call that made it, which has done its work: without a `sys.stderr` (None, as
/// under pythonw) it is dropped, as `print` drops it, and a stream that fails to write
/// reports its error as unraisable.
fn show_note(py: Python<'_>, text: &str) {
    let shown = py
        .import("sys")
        .and_then(|sys| sys.getattr("stderr"))
        .and_then(|stderr| {
            if stderr.is_none() {
                return Ok(());
            }
            stderr.call_method1("write", (format!("note: {text}\n"),))?;
            stderr.call_method0("flush").map(drop)
        });
    if let Err(e) = shown {
        e.write_unraisable(py, None);
    }
}

/// [`show_note`] of each of a sweep's notes, once per sweep (not in each executor task).
fn show_notes(py: Python<'_>, sweep: &Sweep) {
    sweep.notes.iter().for_each(|n| show_note(py, n));
}

/// What a sweep is, for a worker's case to be checked against: the program that ran it and
/// the sweep's fingerprint (scene, keys, values, ensemble and arithmetic).
fn sweep_identity(sweep: &Sweep) -> String {
    format!("{PROGRAM} {}", sweep.fingerprint)
}

/// The keys of `sweep` as the program's sweep header spells them (canonical: an array index as
/// its number).
fn canonical_keys(sweep: &Sweep) -> Vec<String> {
    sweep.sets.iter().map(|a| a.key.clone()).collect()
}

/// A run's output as a dict (see [`Document::run`]).
fn run_dict<'py>(py: Python<'py>, scene: &Scene, out: &RunOutput) -> PyResult<Bound<'py, PyDict>> {
    let m = &scene.mechanism;
    let rec = &out.recording;
    let d = PyDict::new(py);
    d.set_item("title", &scene.title)?;
    d.set_item("rotations", out.rotations_simulated(&scene.run))?;
    d.set_item("period_s", out.period)?;
    d.set_item("wall_time_s", out.wall_time)?;
    // The columns of `jointwear run`'s timeseries.csv, in its order, then the positions.
    let columns = PyList::empty(py);
    let push = |name: String, data: &[f64]| -> PyResult<()> {
        columns.append((name, f64_bytes(py, data)))
    };
    for (name, data) in rec.columns(m) {
        push(name, &data)?;
    }
    for (body, pos) in m.bodies().iter().zip(&rec.positions) {
        for (name, data) in ["x_m", "y_m", "angle_rad"].iter().zip(pos) {
            push(format!("{}.{name}", body.name), data)?;
        }
    }
    d.set_item("columns", columns)?;

    let summaries = summarize(scene, out);
    let joints = PyList::empty(py);
    for (k, (cj, s)) in m.clearance_joints.iter().zip(&summaries).enumerate() {
        let j = PyDict::new(py);
        j.set_item("name", &cj.name)?;
        j.set_item("contact_onsets", out.impacts[k])?;
        j.set_item("motion_mode", s.motion.as_ref().map(Motion::mode))?;
        for (name, x) in s.scalars() {
            j.set_item(name, x)?;
        }
        let regions = PyList::empty(py);
        for p in &s.regions {
            let pd = PyDict::new(py);
            pd.set_item("angle_deg", p.angle_deg)?;
            pd.set_item("depth_m", p.depth)?;
            pd.set_item("prominence_m", p.prominence)?;
            pd.set_item("width_deg", p.width_deg)?;
            regions.append(pd)?;
        }
        j.set_item("wear_regions", regions)?;
        if cj.wear.is_some() {
            let depth = &out.final_wear[k];
            j.set_item("angle_deg", f64_bytes(py, &sector_angles_deg(depth.len())))?;
            j.set_item("final_wear_m", f64_bytes(py, depth))?;
            let snaps: Vec<f64> = (out.wear_snapshots.iter())
                .flat_map(|s| s.depths[k].iter().copied())
                .collect();
            j.set_item("snapshots_m", f64_bytes(py, &snaps))?;
        }
        joints.append(j)?;
    }
    d.set_item("joints", joints)?;
    let rotations: Vec<u32> = out.wear_snapshots.iter().map(|s| s.rotation).collect();
    d.set_item("snapshot_rotations", rotations)?;

    let s = &out.stats;
    let stats = PyDict::new(py);
    stats.set_item("steps", s.steps)?;
    stats.set_item("rejected", s.rejected)?;
    stats.set_item("evaluations", s.evaluations)?;
    stats.set_item("contact_onsets", s.events)?;
    d.set_item("stats", stats)?;
    match out.energy {
        Some(e) => {
            let ed = PyDict::new(py);
            ed.set_item("driver_work_j", e.driver_work)?;
            ed.set_item("normal_work_j", e.normal_work)?;
            ed.set_item("friction_work_j", e.friction_work)?;
            ed.set_item("mechanical_change_j", e.mechanical_change)?;
            ed.set_item("damping_loss_j", e.damping_loss())?;
            ed.set_item("residual", e.residual())?;
            d.set_item("energy", ed)?;
        }
        None => d.set_item("energy", py.None())?,
    }
    d.set_item("settling", serde_dict(py, out.settling)?)?;
    // The program's line for a run that stopped unsettled, for Python to warn with.
    d.set_item("unsettled", out.settling.and_then(|s| s.unsettled_note()))?;
    Ok(d)
}

/// `value` as summary.json has it (its JSON read back: a seed of 2^63 or more, which TOML
/// cannot hold, as the int it is); None as None.
fn serde_dict<'py>(py: Python<'py>, value: Option<impl Serialize>) -> PyResult<Bound<'py, PyAny>> {
    let text =
        serde_json::to_string(&value).map_err(|e| SimulationError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// [`States::values`] into a quantity's statistics dict (`None` as None), as `summary.json`
/// has them: the counts ([`STATE_COUNTS`]) as ints, the means and sds as floats.
fn set_states(d: &Bound<'_, PyDict>, states: &States) -> PyResult<()> {
    for (i, (key, value)) in STATE_COLUMNS.iter().zip(states.values()).enumerate() {
        if STATE_COUNTS.contains(&i) {
            d.set_item(key, value.map(|x| x as usize))?;
        } else {
            d.set_item(key, value)?;
        }
    }
    Ok(())
}

/// An ensemble's members and statistics as a dict (see [`Document::ensemble`]).
fn ensemble_dict<'py>(
    py: Python<'py>,
    scene: &Scene,
    settings: &EnsembleSettings,
    (kept, snapshots): (&[Member], &[Snapshots]),
    wall: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let stats = joint_statistics(scene, kept);
    let d = PyDict::new(py);
    d.set_item("title", &scene.title)?;
    d.set_item("members", settings.members)?;
    d.set_item("seed", settings.seed)?;
    d.set_item("perturbation", settings.perturbation.key())?;
    d.set_item("rotations", scene.run.rotations)?;
    d.set_item("wall_time_s", wall)?;
    d.set_item("snapshot_rotations", scene.run.wear_snapshots.clone())?;
    // Counted as the program counts them (every joint of a member has its settling).
    let unsettled = (kept.iter())
        .filter(|(joints, _)| joints.first().is_some_and(|j| j.settled == Some(false)))
        .count();
    let note = ensemble::unsettled_note(unsettled, settings.members);
    d.set_item("unsettled", note)?;
    let joints = PyList::empty(py);
    for (k, (cj, st)) in scene
        .mechanism
        .clearance_joints
        .iter()
        .zip(&stats)
        .enumerate()
    {
        let j = PyDict::new(py);
        j.set_item("name", &cj.name)?;
        let scalars = PyDict::new(py);
        let statistics = PyDict::new(py);
        for (i, (name, states)) in st.quantities.iter().enumerate() {
            let dist = &states.pooled;
            let values: Vec<f64> = kept.iter().map(|(s, _)| s[k].scalars()[i].1).collect();
            scalars.set_item(*name, f64_bytes(py, &values))?;
            let sd = PyDict::new(py);
            // Named as summary.json names it: not every quantity's name says its window.
            sd.set_item("window", window(name))?;
            sd.set_item("n", dist.n)?;
            for (key, x) in VALUE_KEYS.iter().zip(dist.values()) {
                sd.set_item(key, x)?;
            }
            set_states(&sd, states)?;
            statistics.set_item(*name, sd)?;
        }
        j.set_item("scalars", scalars)?;
        j.set_item("statistics", statistics)?;
        let modes: Vec<Option<&str>> = kept
            .iter()
            .map(|(s, _)| s[k].motion.as_ref().map(Motion::mode))
            .collect();
        j.set_item("motion_mode", modes)?;
        if let Some(band) = &st.wear {
            let sectors = band.sectors.len();
            j.set_item("angle_deg", f64_bytes(py, &sector_angles_deg(sectors)))?;
            let finals: Vec<f64> = kept
                .iter()
                .flat_map(|(_, w)| w[k].iter().copied())
                .collect();
            j.set_item("final_wear_m", f64_bytes(py, &finals))?;
            let snaps: Vec<f64> = (snapshots.iter())
                .flat_map(|s| s.iter().flat_map(|depths| depths[k].iter().copied()))
                .collect();
            j.set_item("snapshots_m", f64_bytes(py, &snaps))?;
            let bd = PyDict::new(py);
            let per_sector: Vec<[f64; 9]> = band.sectors.iter().map(Distribution::values).collect();
            for (i, key) in VALUE_KEYS.iter().enumerate() {
                let column: Vec<f64> = per_sector.iter().map(|v| v[i]).collect();
                bd.set_item(key, f64_bytes(py, &column))?;
            }
            j.set_item("band", bd)?;
        }
        joints.append(j)?;
    }
    d.set_item("joints", joints)?;
    d.set_item("scalar_names", SCALARS.to_vec())?;
    Ok(d)
}

/// Asks a computation to stop once Python has a pending signal.
struct Flag<'a>(&'a AtomicBool);

impl Progress for Flag<'_> {
    fn observe(&self, _: u64, _: Option<u64>) {}

    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// How often a waiting call looks for Ctrl-C: well under a person's patience, and a wake-up
/// that costs nothing next to a rotation.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a thread of its own with the GIL released, while this (the calling) thread
/// runs Python's signal handlers every [`SIGNAL_POLL`]: only the main thread can, and the
/// computation holds neither it nor the GIL. A handler's exception (KeyboardInterrupt on
/// Ctrl-C) asks `work` to stop between rotations and is raised once it has.
fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&dyn Progress) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let (result, raised) = py.detach(|| {
        std::thread::scope(|s| {
            let (caller, stop) = (std::thread::current(), &stop);
            let worker = s.spawn(move || {
                let result = work(&Flag(stop));
                caller.unpark();
                result
            });
            let mut raised = None;
            while !worker.is_finished() {
                std::thread::park_timeout(SIGNAL_POLL);
                if raised.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        raised = Some(e);
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            let result = worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (result, raised)
        })
    });
    match raised {
        Some(e) => Err(e),
        None => Ok(result),
    }
}
