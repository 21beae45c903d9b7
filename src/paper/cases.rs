//! The paper's cases and their runs as ensembles ([`crate::simulation::ensemble`]): what each
//! member measured, kept as typed results that the figures draw and the report's claims read.
//!
//! Owns the one list of the cases ([`CASES`]: scene, clearance, speed of each, as the named
//! fields of a [`PerCase`], so code that reads a case names it by a field, never by position or
//! by a string that could be misspelt).
//!
//! Two kinds of run per case scene: a *steady* run (settle to the steady state, then two
//! recorded rotations: Table 3 and the time-series figures) and a *wear* run (the scene's 40
//! rotations of coupled wear without time series: the wear figures). [`Runs::compute`] runs
//! every member of every ensemble a caller needs in one parallel loop and keeps only what the
//! figures and claims read, so the paper's whole reproduction holds a few megabytes per member.

use crate::analysis::concordance::{centred_cmf, Concordance};
use crate::analysis::regions::{wear_regions, Region};
use crate::analysis::states::States;
use crate::analysis::statistics::{Band, Distribution};
use crate::analysis::Motion;
use crate::io::progress::{Counter, Progress};
use crate::scene::{scene_path, SceneFile};
use crate::simulation::ensemble::{run_member, EnsembleSettings};
use crate::simulation::summary::{contact_quantum, onset_quantum};
use crate::simulation::Scene;
use crate::simulation::{simulate, RunOutput, Settling};
use crate::{Error, Result};
use rayon::prelude::*;

/// A case of the paper: its scene and the clearance and crank speed it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Scene name (`data/scenes/<scene>.toml`).
    pub scene: &'static str,
    /// Radial clearance (mm).
    pub clearance_mm: f64,
    /// Crank speed (r/min).
    pub speed_rpm: f64,
}

impl Case {
    /// The case as a person names it: `0.2 mm, 2000 r/min`.
    pub fn label(&self) -> String {
        format!("{} mm, {} r/min", self.clearance_mm, self.speed_rpm)
    }
}

/// One value per case of the paper, as named fields: a case the code reads that does not
/// exist is a compile error, not a lookup that fails (or gives NaN) at run time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerCase<T> {
    /// 0.02 mm, 30 r/min (figures 12-15).
    pub speed_30rpm: T,
    /// 0.02 mm, 600 r/min (figures 12-15).
    pub speed_600rpm: T,
    /// 0.02 mm, 2000 r/min: the standard case (figures 3-7).
    pub standard: T,
    /// 0.2 mm, 2000 r/min (figures 8-11).
    pub clearance_0_2mm: T,
    /// 0.5 mm, 2000 r/min (figures 8-11).
    pub clearance_0_5mm: T,
}

/// The paper's cases: the one list of their scenes, clearances and speeds.
pub const CASES: PerCase<Case> = PerCase {
    speed_30rpm: Case {
        scene: "speed_30rpm",
        clearance_mm: 0.02,
        speed_rpm: 30.0,
    },
    speed_600rpm: Case {
        scene: "speed_600rpm",
        clearance_mm: 0.02,
        speed_rpm: 600.0,
    },
    standard: Case {
        scene: "standard",
        clearance_mm: 0.02,
        speed_rpm: 2000.0,
    },
    clearance_0_2mm: Case {
        scene: "clearance_0.2mm",
        clearance_mm: 0.2,
        speed_rpm: 2000.0,
    },
    clearance_0_5mm: Case {
        scene: "clearance_0.5mm",
        clearance_mm: 0.5,
        speed_rpm: 2000.0,
    },
};

impl<T> PerCase<T> {
    /// The values in Table 3's order: 30, 600, 2000 r/min at 0.02 mm, then 0.2 and 0.5 mm.
    pub fn list(&self) -> [&T; 5] {
        [
            &self.speed_30rpm,
            &self.speed_600rpm,
            &self.standard,
            &self.clearance_0_2mm,
            &self.clearance_0_5mm,
        ]
    }

    /// The cases at 2000 r/min by growing clearance: 0.02, 0.2, 0.5 mm (figures 8-11).
    pub fn by_clearance(&self) -> [&T; 3] {
        [&self.standard, &self.clearance_0_2mm, &self.clearance_0_5mm]
    }

    /// The cases at 0.02 mm by growing speed: 30, 600, 2000 r/min (figures 12-15).
    pub fn by_speed(&self) -> [&T; 3] {
        [&self.speed_30rpm, &self.speed_600rpm, &self.standard]
    }

    /// `f` of every value, called in Table 3's order.
    pub fn map<U>(&self, mut f: impl FnMut(&T) -> U) -> PerCase<U> {
        PerCase {
            speed_30rpm: f(&self.speed_30rpm),
            speed_600rpm: f(&self.speed_600rpm),
            standard: f(&self.standard),
            clearance_0_2mm: f(&self.clearance_0_2mm),
            clearance_0_5mm: f(&self.clearance_0_5mm),
        }
    }

    /// `f` of every value, called in Table 3's order; the first error.
    pub fn try_map<U>(&self, mut f: impl FnMut(&T) -> Result<U>) -> Result<PerCase<U>> {
        Ok(PerCase {
            speed_30rpm: f(&self.speed_30rpm)?,
            speed_600rpm: f(&self.speed_600rpm)?,
            standard: f(&self.standard)?,
            clearance_0_2mm: f(&self.clearance_0_2mm)?,
            clearance_0_5mm: f(&self.clearance_0_5mm)?,
        })
    }

    /// The values of `self` and `other` of each case, paired.
    pub fn zip<'s, 'o, U>(&'s self, other: &'o PerCase<U>) -> PerCase<(&'s T, &'o U)> {
        PerCase {
            speed_30rpm: (&self.speed_30rpm, &other.speed_30rpm),
            speed_600rpm: (&self.speed_600rpm, &other.speed_600rpm),
            standard: (&self.standard, &other.standard),
            clearance_0_2mm: (&self.clearance_0_2mm, &other.clearance_0_2mm),
            clearance_0_5mm: (&self.clearance_0_5mm, &other.clearance_0_5mm),
        }
    }
}

/// The case whose scene is `scene`; an error naming it if there is none.
pub fn case_of_scene(scene: &str) -> Result<Case> {
    CASES
        .list()
        .into_iter()
        .find(|c| c.scene == scene)
        .copied()
        .ok_or_else(|| {
            let scenes: Vec<&str> = CASES.list().map(|c| c.scene).to_vec();
            Error::invalid(
                "case scene",
                format!("`{scene}`"),
                format!("one of the paper's cases {scenes:?}"),
            )
        })
}

/// Wear profiles saved per rotation by [`Need::WearHistory`] runs (figure 7).
pub const HISTORY_PER_ROTATION: u32 = 36;

/// An ensemble a figure or claim needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Need {
    /// Steady run of a case scene.
    Steady(&'static str),
    /// Wear run of a case scene.
    Wear(&'static str),
    /// Wear run that also saves [`HISTORY_PER_ROTATION`] profiles per rotation; serves
    /// [`Need::Wear`] of the same scene too.
    WearHistory(&'static str),
}

impl Need {
    /// The case scene it runs.
    pub fn scene(&self) -> &'static str {
        match *self {
            Need::Steady(s) | Need::Wear(s) | Need::WearHistory(s) => s,
        }
    }
}

/// Recorded series of a steady run used by the time-series figures (SI unless named).
#[derive(Clone, Debug)]
pub struct Traces {
    /// Crank angle from the start of the recording (deg).
    pub crank_deg: Vec<f64>,
    /// Slider acceleration along x (m/s²).
    pub slider_acc: Vec<f64>,
    /// Wear rate at the contact centre (µm/s).
    pub wear_rate_um_s: Vec<f64>,
    /// Journal centre relative to the bearing centre (µm).
    pub ex_um: Vec<f64>,
    /// Journal centre relative to the bearing centre (µm).
    pub ey_um: Vec<f64>,
}

/// What one member of a steady run measured over its two recorded rotations.
#[derive(Clone, Debug)]
pub struct SteadyMember {
    /// How it reached the steady state.
    pub settling: Settling,
    /// Motion mode of Table 3.
    pub motion: Motion,
    /// Concordances of Table 3.
    pub concordance: Concordance,
    /// Largest |slider acceleration| of the recorded rotations (m/s²).
    pub max_slider_acc: f64,
    /// Largest normal force of the recorded rotations (N).
    pub max_normal_force: f64,
    /// Largest sampled penetration of the recorded rotations (m): the window of the force,
    /// without the start-up impact.
    pub max_penetration: f64,
    /// Share of the circumference ([`COVERAGE_BINS`] bins of 1°) touched while in contact.
    pub contact_coverage: f64,
    /// Largest wear rate of the recorded rotations (m/s).
    pub max_wear_rate: f64,
    /// Centred correlation of the wear rate with |slider acceleration|.
    pub acc_wear_correlation: f64,
    /// Centred correlation of the wear rate with the normal force.
    pub force_wear_correlation: f64,
    /// Right-hand-side evaluations of the run, settling included.
    pub evaluations: u64,
    /// The time series, kept for the first member only (the one the figures draw).
    pub traces: Option<Traces>,
}

impl SteadyMember {
    /// The steady state it settled in, as section 2 of `paper.md` lists them: its motion mode,
    /// continuous contact split by whether the journal still leaves the wall at times (contact
    /// onsets in the recorded rotations).
    pub fn steady_state(&self) -> &'static str {
        match (self.motion.mode(), self.motion.impacts_per_rotation > 0.0) {
            ("continuous contact", false) => "continuous contact, no onsets",
            ("continuous contact", true) => "continuous contact with onsets",
            _ => "free flight and impact",
        }
    }
}

/// What one member of a wear run measured.
#[derive(Clone, Debug)]
pub struct WearMember {
    /// Final wear depth per sector (m).
    pub final_wear: Vec<f64>,
    /// `(rotation, depth per sector)` at the scene's wear snapshots.
    pub snapshots: Vec<(u32, Vec<f64>)>,
    /// Wear regions of the final profile, most prominent first.
    pub regions: Vec<Region>,
    /// `(time, depth per sector)` history, for [`Need::WearHistory`] runs.
    pub history: Vec<(f64, Vec<f64>)>,
}

impl WearMember {
    /// Deepest wear (m).
    pub fn max_depth(&self) -> f64 {
        self.final_wear.iter().cloned().fold(0.0, f64::max)
    }

    /// Mean wear over the circumference (m).
    pub fn mean_depth(&self) -> f64 {
        self.final_wear.iter().sum::<f64>() / self.final_wear.len().max(1) as f64
    }

    /// (first − third region's depth) / first's, of the three most prominent regions: 0 when
    /// they are equally deep; `None` with fewer than three regions.
    pub fn region_spread(&self) -> Option<f64> {
        match &self.regions[..] {
            [a, _, c, ..] => Some((a.depth - c.depth) / a.depth),
            _ => None,
        }
    }

    /// Angle of the deepest region (deg), the most prominent; `None` without regions.
    pub fn deepest_angle(&self) -> Option<f64> {
        self.regions.first().map(|p| p.angle_deg)
    }

    /// Angles of the three most prominent regions (deg).
    pub fn region_angles(&self) -> Vec<f64> {
        self.regions.iter().take(3).map(|p| p.angle_deg).collect()
    }
}

/// The bins of the circumference [`SteadyMember::contact_coverage`] counts: 1° each.
pub const COVERAGE_BINS: usize = 360;

/// The members of a steady ensemble of a scene.
#[derive(Clone, Debug)]
pub struct SteadyEnsemble {
    /// The scene as run.
    pub scene: Scene,
    /// In member order.
    pub members: Vec<SteadyMember>,
}

impl SteadyEnsemble {
    /// Distribution of `f` over the members.
    pub fn stat(&self, f: impl Fn(&SteadyMember) -> f64) -> Distribution {
        Distribution::of(self.members.iter().map(f))
    }

    /// States of `f` over the members ([`States`]).
    pub fn states(&self, f: impl Fn(&SteadyMember) -> f64) -> States {
        States::of(&self.members.iter().map(f).collect::<Vec<f64>>())
    }

    /// States of the members' contact onsets per rotation, a count over the recorded rotations:
    /// split only across an empty level ([`States::of_quantised`], [`onset_quantum`]).
    pub fn onset_states(&self) -> States {
        let quantum = onset_quantum(&self.scene);
        self.quantised_states(|m| m.motion.impacts_per_rotation, quantum)
    }

    /// States of the members' share of the recorded time in contact, a count of samples:
    /// split only across an empty level ([`States::of_quantised`], [`contact_quantum`]).
    pub fn contact_states(&self) -> States {
        let quantum = contact_quantum(&self.scene);
        self.quantised_states(|m| m.motion.contact_fraction, quantum)
    }

    /// States of the members' share of the circumference touched, a count of 1° bins: split
    /// only across an empty level ([`States::of_quantised`], quantum `1/COVERAGE_BINS`).
    pub fn coverage_states(&self) -> States {
        self.quantised_states(|m| m.contact_coverage, 1.0 / COVERAGE_BINS as f64)
    }

    /// States of `f`, on a lattice of spacing `quantum`, over the members.
    fn quantised_states(&self, f: impl Fn(&SteadyMember) -> f64, quantum: f64) -> States {
        States::of_quantised(&self.members.iter().map(f).collect::<Vec<f64>>(), quantum)
    }

    /// The members grouped by `label` (a motion mode, a steady state), the groups in the order
    /// their first members come.
    pub fn groups(
        &self,
        label: impl Fn(&SteadyMember) -> &'static str,
    ) -> Vec<(&'static str, Vec<&SteadyMember>)> {
        let mut groups: Vec<(&'static str, Vec<&SteadyMember>)> = Vec::new();
        for m in &self.members {
            let l = label(m);
            match groups.iter_mut().find(|(g, _)| *g == l) {
                Some((_, of)) => of.push(m),
                None => groups.push((l, vec![m])),
            }
        }
        groups
    }

    /// Members in continuous contact.
    pub fn continuous(&self) -> usize {
        let mode = |m: &&SteadyMember| m.motion.continuous();
        self.members.iter().filter(mode).count()
    }

    /// Members whose P-w concordance exceeds their s-w one.
    pub fn pressure_dominated(&self) -> usize {
        let pw = |m: &&SteadyMember| m.concordance.dominant() == "P-w";
        self.members.iter().filter(pw).count()
    }

    /// Samples per crank rotation of its recorded rotations (`run.record_interval_s`), rounded.
    pub fn samples_per_rotation(&self) -> f64 {
        let period = std::f64::consts::TAU / self.scene.mechanism.driver.omega.abs();
        (period / self.scene.run.record_interval).round()
    }
}

/// The window the recorded quantities of `ensembles` (maxima, time in contact, contact onsets)
/// are read off, as the printouts and `paper.md` name it: `the recorded rotations, 3000 samples
/// per rotation`, one count when every ensemble has it, else each's in order. The maxima are
/// the largest samples, not the largest values between them.
pub fn recorded_window(ensembles: &[&SteadyEnsemble]) -> String {
    let mut counts: Vec<String> = (ensembles.iter())
        .map(|e| format!("{:.0}", e.samples_per_rotation()))
        .collect();
    if counts.windows(2).all(|w| w[0] == w[1]) {
        counts.truncate(1);
    }
    format!(
        "the recorded rotations, {} samples per rotation",
        counts.join(" / ")
    )
}

/// The members of a wear ensemble of a scene.
#[derive(Clone, Debug)]
pub struct WearEnsemble {
    /// The scene as run.
    pub scene: Scene,
    /// In member order.
    pub members: Vec<WearMember>,
    /// Driver rotation period (s).
    pub period: f64,
}

impl WearEnsemble {
    /// States of `f` over the members ([`States`]).
    pub fn states(&self, f: impl Fn(&WearMember) -> f64) -> States {
        States::of(&self.members.iter().map(f).collect::<Vec<f64>>())
    }

    /// Per-sector band of the final profiles.
    pub fn band(&self) -> Band {
        Band::of(self.members.iter().map(|m| m.final_wear.as_slice()))
    }

    /// Per-sector band of the profiles at snapshot `i`, with its rotation count.
    pub fn snapshot_band(&self, i: usize) -> (u32, Band) {
        let rotation = self.members[0].snapshots[i].0;
        let band = Band::of(self.members.iter().map(|m| m.snapshots[i].1.as_slice()));
        (rotation, band)
    }

    /// Distribution of `f` over the members.
    pub fn stat(&self, f: impl Fn(&WearMember) -> f64) -> Distribution {
        Distribution::of(self.members.iter().map(f))
    }

    /// States of the angle `f` (deg) over the members ([`States::of_angles_deg`]).
    pub fn angle_states(&self, f: impl Fn(&WearMember) -> f64) -> States {
        States::of_angles_deg(self.members.iter().map(f))
    }
}

/// Radial clearance (m) of the scene's first clearance joint.
pub fn clearance(scene: &Scene) -> f64 {
    let cj = &scene.mechanism.clearance_joints[0];
    cj.r_bearing - cj.r_journal
}

/// A case scene set up for a steady run: settle, then two recorded rotations.
fn steady_scene(name: &str, modify: &dyn Fn(&mut SceneFile)) -> Result<Scene> {
    let mut file = SceneFile::read(scene_path(name))?;
    modify(&mut file);
    file.run.settle = true;
    file.run.rotations = 2;
    file.run.record_rotations = 2;
    file.run.wear_snapshots.clear();
    file.build()
}

/// A case scene set up for a wear run: its rotations without time series, `history` profiles
/// saved per rotation.
pub(crate) fn wear_scene(
    name: &str,
    history: u32,
    modify: &dyn Fn(&mut SceneFile),
) -> Result<Scene> {
    let mut file = SceneFile::read(scene_path(name))?;
    modify(&mut file);
    file.run.record_rotations = 0;
    file.run.profile_history_per_rotation = history;
    file.build()
}

/// One steady run (no ensemble) of a scene varied by `modify`, for the calibration and
/// accuracy studies.
pub fn steady_run_with(name: &str, modify: impl Fn(&mut SceneFile)) -> Result<(Scene, RunOutput)> {
    let scene = steady_scene(name, &modify)?;
    let out = simulate(&scene)?;
    Ok((scene, out))
}

/// One wear run (no ensemble) of a scene varied by `modify`, with `history` wear profiles
/// saved per rotation.
pub fn wear_run_with(
    name: &str,
    history: u32,
    modify: impl Fn(&mut SceneFile),
) -> Result<(Scene, RunOutput)> {
    let scene = wear_scene(name, history, &modify)?;
    let out = simulate(&scene)?;
    Ok((scene, out))
}

/// Index of the body called `name`.
fn body(scene: &Scene, name: &str) -> Result<usize> {
    scene
        .mechanism
        .bodies()
        .iter()
        .position(|b| b.name == name)
        .ok_or_else(|| {
            Error::invalid(
                "bodies",
                format!("no body `{name}`"),
                "the paper's slider-crank",
            )
        })
}

/// What a steady run measured; `keep_traces` keeps its time series.
pub fn steady_member(scene: &Scene, out: &RunOutput, keep_traces: bool) -> Result<SteadyMember> {
    let rec = &out.recording;
    let j = &rec.joints[0];
    let slider = body(scene, "slider")?;
    let start = rec.driver_angle[0];
    let dt = rec.time[1] - rec.time[0];
    let slider_acc = &rec.accelerations[slider][0];
    let abs_acc: Vec<f64> = slider_acc.iter().map(|a| a.abs()).collect();
    let mut touched = [false; COVERAGE_BINS];
    for (th, d) in j.theta.iter().zip(&j.delta) {
        if *d >= 0.0 {
            touched[(th.to_degrees() as usize).min(COVERAGE_BINS - 1)] = true;
        }
    }
    let max = |v: &[f64]| v.iter().cloned().fold(f64::MIN, f64::max);
    let um = |v: &[f64], s: f64| v.iter().map(|x| x * s).collect::<Vec<f64>>();
    Ok(SteadyMember {
        settling: out.settling.ok_or_else(|| Error::Integration {
            time: 0.0,
            cause: "a steady run ended without settling".into(),
        })?,
        motion: Motion::classify(&j.delta, dt, scene.run.record_rotations as f64),
        concordance: Concordance::of(&j.pressure, &j.sliding_velocity, &j.wear_rate, dt),
        max_slider_acc: max(&abs_acc),
        max_normal_force: max(&j.normal_force),
        max_penetration: max(&j.delta),
        contact_coverage: touched.iter().filter(|&&b| b).count() as f64 / COVERAGE_BINS as f64,
        max_wear_rate: max(&j.wear_rate),
        acc_wear_correlation: centred_cmf(&abs_acc, &j.wear_rate),
        force_wear_correlation: centred_cmf(&j.normal_force, &j.wear_rate),
        evaluations: out.stats.evaluations,
        traces: keep_traces.then(|| Traces {
            crank_deg: rec
                .driver_angle
                .iter()
                .map(|a| (a - start).abs().to_degrees())
                .collect(),
            slider_acc: slider_acc.clone(),
            wear_rate_um_s: um(&j.wear_rate, 1e6),
            ex_um: um(&j.ex, 1e6),
            ey_um: um(&j.ey, 1e6),
        }),
    })
}

/// What a wear run measured.
pub fn wear_member(out: RunOutput) -> WearMember {
    let mut final_wear = out.final_wear;
    let final_wear = final_wear.swap_remove(0);
    WearMember {
        regions: wear_regions(&final_wear),
        final_wear,
        snapshots: out
            .wear_snapshots
            .into_iter()
            .map(|s| (s.rotation, s.depths.into_iter().next().unwrap_or_default()))
            .collect(),
        history: out
            .profile_history
            .into_iter()
            .map(|(t, d)| (t, d.into_iter().next().unwrap_or_default()))
            .collect(),
    }
}

/// Every ensemble the paper's figures and claims need, computed once.
pub struct Runs {
    /// Size and seed of every ensemble.
    pub ensemble: EnsembleSettings,
    steady: Vec<(&'static str, SteadyEnsemble)>,
    wear: Vec<(&'static str, WearEnsemble)>,
    /// Wall time of the whole computation (s).
    pub seconds: f64,
}

/// The output of one member of one ensemble.
enum MemberResult {
    Steady(SteadyMember),
    Wear(WearMember),
}

impl Runs {
    /// Runs the ensembles of `needs` (each once) with the case scenes varied by `modify`, all
    /// members of all of them in one parallel loop; `progress` counts members.
    pub fn compute(
        needs: &[Need],
        ensemble: EnsembleSettings,
        modify: &(dyn Fn(&mut SceneFile) + Sync),
        progress: &dyn Progress,
    ) -> Result<Runs> {
        ensemble.validate()?;
        let clock = std::time::Instant::now();
        let mut needs = needs.to_vec();
        needs.sort();
        needs.dedup();
        let with_history: Vec<&str> = needs
            .iter()
            .filter_map(|n| match n {
                Need::WearHistory(s) => Some(*s),
                _ => None,
            })
            .collect();
        needs.retain(|n| !matches!(n, Need::Wear(s) if with_history.contains(s)));
        let scenes = needs
            .iter()
            .map(|n| match *n {
                Need::Steady(s) => steady_scene(s, modify),
                Need::Wear(s) => wear_scene(s, 0, modify),
                Need::WearHistory(s) => wear_scene(s, HISTORY_PER_ROTATION, modify),
            })
            .collect::<Result<Vec<Scene>>>()?;
        let jobs: Vec<(usize, usize)> = (0..needs.len())
            .flat_map(|k| (0..ensemble.members).map(move |m| (k, m)))
            .collect();
        let done = Counter::new(progress, jobs.len());
        let results = jobs
            .par_iter()
            .map(|&(k, m)| {
                let scene = &scenes[k];
                let out = run_member(scene, &scene.run, &ensemble, m, progress);
                let out =
                    out.map_err(|e| e.in_run(&format!("{:?}, ensemble member {m}", needs[k])))?;
                let r = match needs[k] {
                    Need::Steady(_) => MemberResult::Steady(steady_member(scene, &out, m == 0)?),
                    _ => MemberResult::Wear(wear_member(out)),
                };
                done.finish_one();
                Ok(r)
            })
            .collect::<Result<Vec<MemberResult>>>()?;
        let mut runs = Runs {
            ensemble,
            steady: Vec::new(),
            wear: Vec::new(),
            seconds: 0.0,
        };
        let mut results = results.into_iter();
        for (need, scene) in needs.iter().zip(scenes) {
            let members = results.by_ref().take(ensemble.members);
            match *need {
                Need::Steady(name) => {
                    let members = members
                        .filter_map(|r| match r {
                            MemberResult::Steady(s) => Some(s),
                            MemberResult::Wear(_) => None,
                        })
                        .collect();
                    runs.steady.push((name, SteadyEnsemble { scene, members }));
                }
                Need::Wear(name) | Need::WearHistory(name) => {
                    let members = members
                        .filter_map(|r| match r {
                            MemberResult::Wear(w) => Some(w),
                            MemberResult::Steady(_) => None,
                        })
                        .collect();
                    let period = std::f64::consts::TAU / scene.mechanism.driver.omega.abs();
                    runs.wear.push((
                        name,
                        WearEnsemble {
                            scene,
                            members,
                            period,
                        },
                    ));
                }
            }
        }
        runs.seconds = clock.elapsed().as_secs_f64();
        Ok(runs)
    }

    /// The same ensembles cut to their first `n` members (an ensemble of `n`, for studies of
    /// how statistics settle with the ensemble size); at least one member is kept.
    pub fn first_members(&self, n: usize) -> Runs {
        let n = n.max(1);
        Runs {
            ensemble: EnsembleSettings {
                members: n.min(self.ensemble.members),
                ..self.ensemble
            },
            steady: first_of(&self.steady, |e| e.members.truncate(n)),
            wear: first_of(&self.wear, |e| e.members.truncate(n)),
            seconds: self.seconds,
        }
    }

    /// The steady ensemble of a case scene.
    pub fn steady(&self, name: &str) -> Result<&SteadyEnsemble> {
        self.steady
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, e)| e)
            .ok_or_else(|| missing("steady", name))
    }

    /// The wear ensemble of a case scene.
    pub fn wear(&self, name: &str) -> Result<&WearEnsemble> {
        self.wear
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, e)| e)
            .ok_or_else(|| missing("wear", name))
    }

    /// The steady ensembles of every case.
    pub fn steady_cases(&self) -> Result<PerCase<&SteadyEnsemble>> {
        CASES.try_map(|c| self.steady(c.scene))
    }

    /// The wear ensembles of every case.
    pub fn wear_cases(&self) -> Result<PerCase<&WearEnsemble>> {
        CASES.try_map(|c| self.wear(c.scene))
    }
}

/// Copies of named ensembles, each cut by `cut`.
fn first_of<E: Clone>(list: &[(&'static str, E)], cut: impl Fn(&mut E)) -> Vec<(&'static str, E)> {
    list.iter()
        .map(|(name, e)| {
            let mut e = e.clone();
            cut(&mut e);
            (*name, e)
        })
        .collect()
}

fn missing(kind: &str, name: &str) -> Error {
    Error::invalid(
        "figure needs",
        format!("no {kind} ensemble of `{name}` was computed"),
        "every ensemble a figure reads listed in its needs",
    )
}
