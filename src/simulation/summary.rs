//! A run's summary: per clearance joint its largest force and penetration (each over a named
//! window), motion and wear regions ([`summarize`]), as every output of a run reports them (the
//! run folder, a sweep's row, an ensemble member's row, Python's `Run.summary`); and the
//! statistics of those summaries over the members of an ensemble ([`joint_statistics`]).

use crate::analysis::regions::{wear_regions, Region};
use crate::analysis::states::States;
use crate::analysis::statistics::Band;
use crate::analysis::Motion;
use crate::io::output::number;
use crate::simulation::{RunOutput, Scene};
use serde::{Deserialize, Serialize};

/// Summary of one clearance joint over a run (serialisable: a member run elsewhere, by a
/// Python executor, hands it back exactly).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSummary {
    /// The joint's name.
    pub name: String,
    /// Largest sampled normal force of the recorded rotations (N); `None` when none were
    /// recorded.
    pub max_normal_force_recorded: Option<f64>,
    /// Largest sampled penetration of the recorded rotations (m), the window of the force;
    /// `None` when none were recorded.
    pub max_penetration_recorded: Option<f64>,
    /// Largest penetration over the accepted steps of the whole run, at their ends and peaks
    /// inside them (m): the start-up transient
    /// (the impact after the centred start) and any settling included.
    pub max_penetration_whole_run: f64,
    /// Motion of the recorded rotations, if any were recorded.
    pub motion: Option<Motion>,
    /// Wear regions of the final profile, most prominent (and so deepest) first; empty
    /// without wear.
    pub regions: Vec<Region>,
    /// Rotations simulated from the start, the window of the whole-run maximum and of the
    /// final wear: `run.rotations`, plus the settling rotations of a run that settles (which
    /// differ between the members of an ensemble).
    pub rotations_simulated: u32,
    /// Whether the run met its steady-state criterion before `steady_state.max_rotations`
    /// (`Some(false)`: it stopped settling there, the orbit still changing); `None` for a scene
    /// that does not settle. An unsettled member's recorded rotations are no steady state.
    pub settled: Option<bool>,
}

/// Summarises every clearance joint of a run of `scene`.
pub fn summarize(scene: &Scene, out: &RunOutput) -> Vec<JointSummary> {
    let rec = &out.recording;
    let dt = scene.run.record_interval;
    scene
        .mechanism
        .clearance_joints
        .iter()
        .enumerate()
        .map(|(k, cj)| {
            let trace = rec.joints.get(k).filter(|t| !t.delta.is_empty());
            let max = |v: &[f64]| v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            JointSummary {
                name: cj.name.clone(),
                max_normal_force_recorded: trace.map(|t| max(&t.normal_force)),
                max_penetration_recorded: trace.map(|t| max(&t.delta)),
                max_penetration_whole_run: out.max_penetration_whole_run[k],
                motion: trace
                    .map(|t| Motion::classify(&t.delta, dt, scene.run.record_rotations as f64)),
                regions: wear_regions(&out.final_wear[k]),
                rotations_simulated: out.rotations_simulated(&scene.run),
                settled: out.settling.map(|s| s.steady),
            }
        })
        .collect()
}

impl JointSummary {
    /// The joint's scalar results by name: the numeric sweep columns, and
    /// `continuous_contact` and `settled` as 1 or 0, whose means over an ensemble are the shares
    /// of members in continuous contact and of members that settled. What was not recorded (or
    /// a scene that does not settle) is NaN here, and an empty field or "not
    /// recorded" wherever it is written or printed.
    pub fn scalars(&self) -> [(&'static str, f64); 10] {
        let deepest = self.regions.first();
        let motion = |f: fn(&Motion) -> f64| self.motion.as_ref().map_or(f64::NAN, f);
        let values = [
            self.max_normal_force_recorded.unwrap_or(f64::NAN),
            self.max_penetration_recorded.unwrap_or(f64::NAN),
            self.max_penetration_whole_run,
            deepest.map_or(f64::NAN, |p| p.angle_deg),
            deepest.map_or(f64::NAN, |p| p.depth),
            motion(|m| m.contact_fraction),
            motion(|m| m.impacts_per_rotation),
            motion(|m| f64::from(u8::from(m.continuous()))),
            f64::from(self.rotations_simulated),
            self.settled.map_or(f64::NAN, |s| f64::from(u8::from(s))),
        ];
        std::array::from_fn(|i| (SCALARS[i], values[i]))
    }
}

/// Statistics of one clearance joint over the members of an ensemble.
#[derive(Clone, Debug, PartialEq)]
pub struct JointStatistics {
    /// The joint's name.
    pub name: String,
    /// Each of [`JointSummary::scalars`] by name, in order, as the states its members fall
    /// into ([`States`]: largest-gap rule; an angle's cut at its largest gap on the circle
    /// first, [`States::of_angles_deg`]), with the distribution of all of them as
    /// [`States::pooled`] (an angle's unwrapped around its circular mean): members whose
    /// deepest wear lies in different regions are two states, not one mean angle between them.
    pub quantities: Vec<(&'static str, States)>,
    /// Per-sector band of the final wear profiles, for a joint with a wear model.
    pub wear: Option<Band>,
}

/// Statistics of every clearance joint over `members`: each member's joint summaries and
/// final wear profiles.
pub fn joint_statistics(
    scene: &Scene,
    members: &[(Vec<JointSummary>, Vec<Vec<f64>>)],
) -> Vec<JointStatistics> {
    scene
        .mechanism
        .clearance_joints
        .iter()
        .enumerate()
        .map(|(k, cj)| {
            let values = |i: usize| members.iter().map(move |(s, _)| s[k].scalars()[i].1);
            let quantities = SCALARS
                .iter()
                .enumerate()
                .map(|(i, &name)| {
                    let v = || values(i).collect::<Vec<f64>>();
                    let s = match scalar_quantum(name, scene) {
                        _ if name.ends_with("_deg") => States::of_angles_deg(values(i)),
                        Some(quantum) => States::of_quantised(&v(), quantum),
                        None => States::of(&v()),
                    };
                    (name, s)
                })
                .collect();
            JointStatistics {
                name: cj.name.clone(),
                quantities,
                wear: cj
                    .wear
                    .is_some()
                    .then(|| Band::of(members.iter().map(|(_, w)| w[k].as_slice()))),
            }
        })
        .collect()
}

impl JointSummary {
    /// The joint's [`JOINT_COLUMNS`] cells of a CSV row: numbers by [`number`], an empty field
    /// where nothing was recorded, there is no wear or the scene does not settle.
    pub fn cells(&self) -> [String; 10] {
        let deepest = self.regions.first();
        let recorded = |x: Option<f64>| x.map_or(String::new(), number);
        let motion = |f: fn(&Motion) -> String| self.motion.as_ref().map_or(String::new(), f);
        [
            recorded(self.max_normal_force_recorded),
            recorded(self.max_penetration_recorded),
            number(self.max_penetration_whole_run),
            deepest.map_or(String::new(), |p| number(p.angle_deg)),
            deepest.map_or(String::new(), |p| number(p.depth)),
            motion(|m| m.mode().to_string()),
            motion(|m| number(m.contact_fraction)),
            motion(|m| number(m.impacts_per_rotation)),
            self.rotations_simulated.to_string(),
            self.settled.map_or(String::new(), |s| s.to_string()),
        ]
    }
}

/// Per-joint columns of a run's summary row ([`JointSummary::cells`]: a sweep case's and an
/// ensemble member's), after the joint's name and a dot. Each maximum names its window:
/// `recorded` the recorded rotations (empty when none were recorded), `whole_run` every step
/// from the start, whose rotations `rotations_simulated` counts (with the final wear's);
/// `settled` says whether a settling run met its criterion (`true`, `false`, empty for a scene
/// that does not settle).
pub const JOINT_COLUMNS: [&str; 10] = [
    "max_normal_force_recorded_n",
    "max_penetration_recorded_m",
    "max_penetration_whole_run_m",
    "max_wear_angle_deg",
    "max_wear_depth_m",
    "motion_mode",
    "contact_fraction",
    "impacts_per_rotation",
    "rotations_simulated",
    "settled",
];

/// The names of [`JointSummary::scalars`], in order.
pub const SCALARS: [&str; 10] = [
    "max_normal_force_recorded_n",
    "max_penetration_recorded_m",
    "max_penetration_whole_run_m",
    "max_wear_angle_deg",
    "max_wear_depth_m",
    "contact_fraction",
    "impacts_per_rotation",
    "continuous_contact",
    "rotations_simulated",
    "settled",
];

/// The windows a scalar is taken over, each with the part of the run it covers (as the
/// folders' READMEs say it).
pub const WINDOWS: [(&str, &str); 3] = [
    (
        "recorded",
        "the recorded rotations, the last run.record_rotations, read off their samples every \
         run.record_interval_s (no value when none were recorded)",
    ),
    (
        "whole_run",
        "every rotation from the start, settling included, rotations_simulated of them (the \
         final wear is the whole run's)",
    ),
    (
        "settling",
        "the settling phase (no value where the scene does not settle)",
    ),
];

/// The window ([`WINDOWS`]) of each of [`SCALARS`], in order. Not every name says it:
/// `contact_fraction`, `impacts_per_rotation` and `continuous_contact` are of the recorded
/// rotations.
pub const SCALAR_WINDOWS: [&str; 10] = [
    "recorded",
    "recorded",
    "whole_run",
    "whole_run",
    "whole_run",
    "recorded",
    "recorded",
    "recorded",
    "whole_run",
    "settling",
];

/// The spacing of the values the scalar `name` ([`SCALARS`]) takes in runs of `scene`, for a
/// count divided by what it is counted over: contact onsets over the recorded rotations
/// (`1/run.record_rotations`), samples in contact over the recorded samples, 1 for a 0-or-1
/// flag and for whole rotations; `None` for a quantity that is not quantised. Its members
/// split only across an empty level ([`States::of_quantised`]).
pub fn scalar_quantum(name: &str, scene: &Scene) -> Option<f64> {
    match name {
        "contact_fraction" => Some(contact_quantum(scene)),
        "impacts_per_rotation" => Some(onset_quantum(scene)),
        "continuous_contact" | "rotations_simulated" | "settled" => Some(1.0),
        _ => None,
    }
}

/// The spacing of contact onsets per rotation ([`Motion::impacts_per_rotation`]) in runs of
/// `scene`: one onset over the recorded rotations.
pub fn onset_quantum(scene: &Scene) -> f64 {
    1.0 / f64::from(scene.run.record_rotations)
}

/// The spacing of the share of the recorded time in contact ([`Motion::contact_fraction`]) in
/// runs of `scene`: one sample of the recorded ones.
pub fn contact_quantum(scene: &Scene) -> f64 {
    1.0 / scene.recorded_samples()
}

/// The window of the scalar `name` ([`SCALAR_WINDOWS`]); `None` for a name not in [`SCALARS`].
pub fn window(name: &str) -> Option<&'static str> {
    SCALARS
        .iter()
        .position(|s| *s == name)
        .map(|i| SCALAR_WINDOWS[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A member of the four-bar with `onsets` contact onsets over its 2 recorded rotations,
    /// in continuous contact or not.
    fn member(onsets: f64, continuous: bool) -> (Vec<JointSummary>, Vec<Vec<f64>>) {
        let summary = JointSummary {
            name: "coupler-rocker".into(),
            max_normal_force_recorded: Some(400.0),
            max_penetration_recorded: Some(4e-6),
            max_penetration_whole_run: 7e-6,
            motion: Some(Motion {
                contact_fraction: if continuous { 0.97 } else { 0.5 },
                impacts_per_rotation: onsets / 2.0,
                mean_flight_time: f64::NAN,
            }),
            regions: Vec::new(),
            rotations_simulated: 10,
            settled: None,
        };
        (vec![summary], vec![Vec::new()])
    }

    /// The four-bar's onsets per rotation (`run data/scenes/fourbar.toml --ensemble 16
    /// --rotations 10 --seed 2`: 9 members at 3, 6 at 3.5, 1 at 4) and a flag of 12 and 4
    /// members are one state each; onsets 0 in 12 members and 3 in 4 are two. Failed before
    /// the quanta ("two states: low 9 of 16: 3 ± 0, high 7 of 16: 3.571 ± 0.189"; the flag
    /// split into its two values).
    #[test]
    fn counts_split_only_across_an_empty_level() {
        let scene = Scene::load(crate::scene::scene_path("fourbar")).unwrap();
        assert_relative_eq!(onset_quantum(&scene), 0.5);
        // 1000 r/min, 2 rotations sampled every 2e-5 s: 6000 intervals, both ends sampled
        assert_relative_eq!(1.0 / contact_quantum(&scene), 6001.0);
        let states = |members: &[(Vec<JointSummary>, Vec<Vec<f64>>)], name: &str| {
            let stats = joint_statistics(&scene, members);
            let (_, s) = (stats[0].quantities.iter())
                .find(|(q, _)| *q == name)
                .cloned()
                .unwrap();
            s
        };
        let levels: Vec<_> = (0..16)
            .map(|i| {
                member(
                    [6.0, 7.0, 8.0][usize::from(i >= 9) + usize::from(i == 15)],
                    i < 12,
                )
            })
            .collect();
        for name in ["impacts_per_rotation", "continuous_contact"] {
            let s = states(&levels, name);
            assert!(!s.split(), "{name}: {s:?}");
        }
        let apart: Vec<_> = (0..16)
            .map(|i| member(if i < 12 { 0.0 } else { 6.0 }, true))
            .collect();
        let s = states(&apart, "impacts_per_rotation");
        assert_eq!(s.states[1].members, [12, 13, 14, 15]);
        // exactly the counts among the scalars are quantised
        for name in SCALARS {
            let quantised = scalar_quantum(name, &scene).is_some();
            assert_eq!(
                quantised,
                [
                    "contact_fraction",
                    "impacts_per_rotation",
                    "continuous_contact",
                    "rotations_simulated",
                    "settled"
                ]
                .contains(&name),
                "{name}"
            );
        }
    }
}
