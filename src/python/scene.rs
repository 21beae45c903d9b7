//! The scene document Python holds ([`Document`]): loaded from a file or built from a dict,
//! varied by dotted keys, and validated, run, run as an ensemble or swept; each result handed
//! back as plain Python objects that the package `jointwear` wraps as numpy arrays.

use super::convert::{f64_bytes, from_toml, to_toml};
use super::{to_py_err, SimulationError};
use crate::analysis::states::{States, STATE_COLUMNS};
use crate::analysis::statistics::{Distribution, VALUE_KEYS};
use crate::analysis::Motion;
use crate::io::progress::Progress;
use crate::laws::wear::sector_angles_deg;
use crate::scene::{reversal_note, set_dotted, SceneFile};
use crate::simulation::ensemble::{self, EnsembleSettings, MAX_MEMBERS};
use crate::simulation::{simulate_with_progress, RunOutput, Scene};
use crate::sweep::{
    joint_statistics, summarize, Assignment, CaseResult, JointSummary, Outcome, Shard, Sweep,
    SCALARS,
};
use crate::Error;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// A scene document (TOML values, `extends` resolved) and the path that names it in messages.
#[pyclass(module = "jointwear._native")]
pub struct Document {
    doc: toml::Value,
    path: PathBuf,
    /// The keys given to `set`, which `set("run.rotations", n)` leaves as they are.
    set_keys: BTreeSet<String>,
    /// The document as loaded or built, before any `set`: the sense of rotation that a `set`
    /// reversing the driver is noted against.
    loaded: toml::Value,
}

/// One ensemble member as the statistics take it: joint summaries and final wear.
type Member = (Vec<JointSummary>, Vec<Vec<f64>>);

/// The wear profiles of one member's snapshots: per snapshot, per joint, per sector.
type Snapshots = Vec<Vec<Vec<f64>>>;

impl Document {
    /// The validated scene in SI units; errors as the program reports a scene's.
    fn scene(&self) -> PyResult<Scene> {
        SceneFile::from_document(self.doc.clone(), &self.path)
            .and_then(|f| f.build())
            .map_err(|e| self.error(e))
    }

    /// The Python exception of an error about this scene.
    fn error(&self, e: Error) -> PyErr {
        to_py_err(&self.path, e, true)
    }

    /// A document read as given, checked by building it (as the program does on loading).
    fn checked(doc: toml::Value, path: PathBuf) -> PyResult<Document> {
        let d = Document {
            loaded: doc.clone(),
            doc,
            path,
            set_keys: BTreeSet::new(),
        };
        d.scene()?;
        Ok(d)
    }
}

#[pymethods]
impl Document {
    /// Reads the scene file at `path` (resolving `extends` and `[overrides]`) and validates it.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Document> {
        let doc = SceneFile::read_document(&path).map_err(|e| to_py_err(&path, e, true))?;
        Document::checked(doc, path)
    }

    /// A scene from a dict of the keys of a scene file; `path` names it in messages and a
    /// relative `extends` is found beside it.
    #[staticmethod]
    fn from_dict(table: &Bound<'_, PyDict>, path: PathBuf) -> PyResult<Document> {
        let doc = to_toml(table.as_any(), "")?;
        let doc = SceneFile::resolve_document(doc, &path).map_err(|e| to_py_err(&path, e, true))?;
        Document::checked(doc, path)
    }

    /// Sets the value at a dotted key, as the program's `--set` (`clearance.0.clearance_mm`),
    /// all or nothing: a key the scene file does not have, or a value of the wrong type, raises
    /// and leaves the document as it was; values out of range are refused when the scene is
    /// next checked or run. `run.rotations` cuts the wear snapshots and recorded rotations as
    /// the program's `--rotations` does (unless they were set), with a note on stderr.
    fn set(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let value = to_toml(value, key)?;
        let note = reversal_note(&self.loaded, key, &value);
        let mut doc = self.doc.clone();
        set_dotted(&mut doc, key, value).map_err(|e| self.error(e))?;
        let mut file = SceneFile::from_document(doc.clone(), &self.path)
            .map_err(|e| self.error(e.in_context(&format!("with set({key:?}, …)"))))?;
        if key == "run.rotations" {
            let n = file.run.rotations;
            for (cut, value) in file.run.cut_to(n, |k| self.set_keys.contains(k)) {
                eprintln!("note: set(\"run.rotations\", {n}) sets {cut} = {value}");
                set_dotted(&mut doc, &cut, value).map_err(|e| self.error(e))?;
            }
        }
        if let Some(note) = note {
            eprintln!("note: {note}");
        }
        self.doc = doc;
        self.set_keys.insert(key.to_string());
        Ok(())
    }

    /// The document as nested dicts and lists.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_toml(py, &self.doc)
    }

    /// The path that names the scene in messages.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// An independent copy.
    fn copy(&self) -> Document {
        Document {
            doc: self.doc.clone(),
            path: self.path.clone(),
            set_keys: self.set_keys.clone(),
            loaded: self.loaded.clone(),
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
            joints.append(j)?;
        }
        d.set_item("joints", joints)?;
        d.set_item("dof", m.degrees_of_freedom())?;
        d.set_item("period_s", scene.period())?;
        d.set_item("rotations", scene.run.rotations)?;
        Ok(d)
    }

    /// Simulates the scene with the GIL released, or with `member`, member `member` of the
    /// ensemble of `seed` (`jointwear run --member K --seed S`); returns the time series (the
    /// columns of `jointwear run`'s `timeseries.csv`, then every body's position), the final
    /// wear profile and summary of every clearance joint, the wear snapshots and the run's
    /// counters.
    #[pyo3(signature = (member=None, seed=1))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        member: Option<usize>,
        seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let scene = self.scene()?;
        let of = EnsembleSettings {
            members: MAX_MEMBERS,
            seed,
            ..EnsembleSettings::default()
        };
        let out = interruptible(py, |cancel| match member {
            Some(k) => ensemble::run_member(&scene, &scene.run, &of, k, cancel),
            None => simulate_with_progress(&scene, cancel),
        })?;
        let out = out.map_err(|e| self.error(e))?;
        run_dict(py, &scene, &out)
    }

    /// Runs `members` members of the scene (seeded initial offsets of at most 10 nm) in
    /// parallel with the GIL released; returns, per clearance joint, every member's scalar
    /// results, final profile and snapshots, and their statistics with the states the members
    /// fall into.
    fn ensemble<'py>(
        &self,
        py: Python<'py>,
        members: usize,
        seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let settings = EnsembleSettings {
            members,
            seed,
            ..EnsembleSettings::default()
        };
        settings.validate().map_err(|e| self.error(e))?;
        let scene = self.scene()?;
        let clock = std::time::Instant::now();
        let keep = |_, o: RunOutput| {
            let summary = summarize(&scene, &o);
            let snaps = o.wear_snapshots.into_iter().map(|s| s.depths).collect();
            ((summary, o.final_wear), snaps)
        };
        let kept = interruptible(py, |cancel| ensemble::run(&scene, &settings, keep, cancel))?;
        let (kept, snaps): (Vec<Member>, Vec<Snapshots>) =
            kept.map_err(|e| self.error(e))?.into_iter().unzip();
        let wall = clock.elapsed().as_secs_f64();
        ensemble_dict(py, &scene, &settings, (&kept, &snaps), wall)
    }

    /// Runs the cartesian product of `values[i]` at `keys[i]` (the last key varying fastest,
    /// as `jointwear sweep`), each case once or as an ensemble of `members`, in parallel with
    /// the GIL released; every case is validated before any runs. Returns one dict per case:
    /// `case`, `error` (None, or the message of a case that failed while running, as in the
    /// program's sweep file),
    /// `wall_time_s` and the columns of the program's sweep file.
    #[pyo3(signature = (keys, values, members=None, seed=1))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        keys: Vec<String>,
        values: Vec<Vec<Bound<'py, PyAny>>>,
        members: Option<usize>,
        seed: u64,
    ) -> PyResult<Bound<'py, PyList>> {
        if keys.len() != values.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} keys but {} lists of values",
                keys.len(),
                values.len()
            )));
        }
        let mut sets = Vec::new();
        for (key, vs) in keys.iter().zip(&values) {
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
        let mut sweep = Sweep::from_document(&self.doc, &self.path, sets, Shard::ALL)
            .map_err(|e| self.error(e))?;
        if let Some(members) = members {
            sweep = sweep
                .with_ensemble(EnsembleSettings {
                    members,
                    seed,
                    ..EnsembleSettings::default()
                })
                .map_err(|e| self.error(e))?;
        }
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
            let d = PyDict::new(py);
            d.set_item("case", r.case)?;
            match &r.outcome {
                Err(message) => d.set_item("error", message)?,
                Ok((outcome, wall)) => {
                    d.set_item("error", py.None())?;
                    d.set_item("wall_time_s", wall)?;
                    sweep_columns(&d, outcome)?;
                }
            }
            cases.append(d)?;
        }
        Ok(cases)
    }
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
                for (name, dist) in &j.scalars {
                    d.set_item(format!("{}.{name}.mean", j.name), dist.mean)?;
                    d.set_item(format!("{}.{name}.sd", j.name), dist.sd)?;
                }
            }
        }
    }
    Ok(())
}

/// A run's output as a dict (see [`Document::run`]).
fn run_dict<'py>(py: Python<'py>, scene: &Scene, out: &RunOutput) -> PyResult<Bound<'py, PyDict>> {
    let m = &scene.mechanism;
    let rec = &out.recording;
    let d = PyDict::new(py);
    d.set_item("title", &scene.title)?;
    d.set_item("rotations", scene.run.rotations)?;
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
        j.set_item("impacts", out.impacts[k])?;
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
    match out.settling {
        // The fields as serde names them, like summary.json's.
        Some(s) => {
            let value =
                toml::Value::try_from(s).map_err(|e| SimulationError::new_err(e.to_string()))?;
            d.set_item("settling", from_toml(py, &value)?)?
        }
        None => d.set_item("settling", py.None())?,
    }
    Ok(d)
}

/// The [`STATE_COLUMNS`] of a quantity into its statistics dict, as `ensemble_summary.csv`:
/// the state count, then the low and the high state's members, mean and sd; `None` where the
/// members fall into one state, and all `None` for an angle (no states).
fn set_states(d: &Bound<'_, PyDict>, states: Option<&States>) -> PyResult<()> {
    d.set_item(STATE_COLUMNS[0], states.map(|s| s.states.len()))?;
    let split = states.and_then(States::low_high);
    let (low, high) = (split.map(|(l, _)| l), split.map(|(_, h)| h));
    for (keys, state) in STATE_COLUMNS[1..].chunks(3).zip([low, high]) {
        let dist = state.map(|s| &s.distribution);
        d.set_item(keys[0], dist.map(|d| d.n))?;
        d.set_item(keys[1], dist.map(|d| d.mean))?;
        d.set_item(keys[2], dist.map(|d| d.sd))?;
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
    d.set_item("rotations", scene.run.rotations)?;
    d.set_item("wall_time_s", wall)?;
    d.set_item("snapshot_rotations", scene.run.wear_snapshots.clone())?;
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
        for (i, (name, dist)) in st.scalars.iter().enumerate() {
            let values: Vec<f64> = kept.iter().map(|(s, _)| s[k].scalars()[i].1).collect();
            scalars.set_item(*name, f64_bytes(py, &values))?;
            let sd = PyDict::new(py);
            sd.set_item("n", dist.n)?;
            for (key, x) in VALUE_KEYS.iter().zip(dist.values()) {
                sd.set_item(key, x)?;
            }
            let states = st.states.iter().find(|(n, _)| n == name).map(|(_, s)| s);
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
