//! The folder of an ensemble: its members' results, their statistics (with the states the
//! members fall into) and per-sector wear bands as CSVs, the band plot, `summary.json` and
//! `README.txt` ([`write_ensemble`]).

use super::{
    conventions, joint_file, perturbation_arg, wear_panel, write_folder, write_summary, Origin,
    BAND_STEM, MEMBERS_FILE, PROGRAM, STATISTICS_FILE, SUMMARY_FILE, WEAR_FIGURE,
};
use crate::analysis::states::{States, STATE_COLUMNS, STATE_COUNTS};
use crate::analysis::statistics::{Distribution, VALUE_KEYS};
use crate::io::output::{number, number_or_empty, write_rows};
use crate::io::plot::{render, Axes, Series, Shade, Style};
use crate::laws::wear::sector_angles_deg;
use crate::simulation::ensemble::EnsembleSettings;
use crate::simulation::summary::{
    joint_statistics, window, JointStatistics, JointSummary, JOINT_COLUMNS, SCALARS,
    SCALAR_WINDOWS, WINDOWS,
};
use crate::simulation::Scene;
use crate::sweep::{Recorded, RECORD_COLUMNS};
use crate::Result;
use serde::Serialize;
use std::path::Path;

/// One member of an ensemble as its folder takes it: its joint summaries and final wear
/// profiles (per joint, per sector, m).
pub type Member = (Vec<JointSummary>, Vec<Vec<f64>>);

/// Writes the folder `dir` of the ensemble `settings` of `scene` (from `origin`): `members`
/// in member order, each member's wall time in `walls` (s), `wall` the ensemble's (s).
/// Returns the statistics it wrote. Its `README.txt` and manifest name the command that runs
/// it (`… --ensemble N --seed S`).
pub fn write_ensemble(
    dir: &Path,
    origin: &Origin,
    scene: &Scene,
    settings: &EnsembleSettings,
    (members, walls): (&[Member], &[f64]),
    wall: f64,
) -> Result<Vec<JointStatistics>> {
    let title = format!(
        "{} --ensemble {} --seed {}{}",
        origin.command,
        settings.members,
        settings.seed,
        perturbation_arg(&settings.perturbation)
    );
    write_folder(dir, &title, || {
        let stats = write_files(scene, settings, members, walls, dir)?;
        let summary = EnsembleSummary {
            program: PROGRAM.into(),
            scene: origin.path.clone(),
            title: scene.title.clone(),
            fingerprint: origin.fingerprint.clone(),
            changes: origin.changes.clone(),
            members: settings.members,
            seed: settings.seed,
            perturbation: settings.perturbation.key(),
            rotations: scene.run.rotations,
            record_rotations: scene.run.record_rotations,
            record_interval_s: scene.run.record_interval,
            wall_time_s: wall,
            joints: stats
                .iter()
                .map(|j| JointDistributions {
                    name: j.name.clone(),
                    quantities: j
                        .quantities
                        .iter()
                        .map(|(name, s)| (name.to_string(), QuantitySummary { name, states: s }))
                        .collect(),
                })
                .collect(),
        };
        write_summary(dir, &summary, &readme(&title, scene, settings, &stats))?;
        Ok(stats)
    })
}

/// The ensemble's CSVs and band plot; returns the statistics it wrote.
fn write_files(
    scene: &Scene,
    settings: &EnsembleSettings,
    members: &[Member],
    walls: &[f64],
    dir: &Path,
) -> Result<Vec<JointStatistics>> {
    let m = &scene.mechanism;
    let joints: Vec<String> = m.clearance_joints.iter().map(|c| c.name.clone()).collect();
    // One row per member: its offsets d (journal body frame), its tolerances, the window of its
    // recorded quantities as a sweep row names it, then a sweep row's joint columns.
    let recorded = Recorded::of(scene).cells();
    let mut head = vec!["member".to_string()];
    for j in &joints {
        head.extend([
            format!("{j}.offset_body_x_m"),
            format!("{j}.offset_body_y_m"),
        ]);
    }
    head.extend(
        ["rtol", "atol"]
            .iter()
            .chain(&RECORD_COLUMNS)
            .map(|c| c.to_string()),
    );
    for j in &joints {
        head.extend(JOINT_COLUMNS.iter().map(|c| format!("{j}.{c}")));
    }
    head.extend(["wall_time_s".to_string(), "error".to_string()]);
    let rows = members
        .iter()
        .zip(walls)
        .enumerate()
        .map(|(i, ((summary, _), secs))| {
            let p = &settings.perturbation;
            let mut row = vec![i.to_string()];
            for d in p.offsets(settings.seed, i, joints.len()) {
                row.extend([number(d.x), number(d.y)]);
            }
            let tolerances = p.run_settings(&scene.run, settings.seed, i).tolerances;
            row.extend([number(tolerances.rtol), number(tolerances.atol)]);
            row.extend(recorded.iter().cloned());
            row.extend(summary.iter().flat_map(JointSummary::cells));
            row.extend([number(*secs), String::new()]);
            row
        });
    write_rows(&dir.join(MEMBERS_FILE), &head, rows)?;
    let stats = joint_statistics(scene, members);
    let mut head = vec!["joint", "quantity", "n"];
    head.extend(VALUE_KEYS);
    head.extend(STATE_COLUMNS);
    let numbers = |d: &Distribution| d.values().map(number_or_empty);
    let mut rows = Vec::new();
    for j in &stats {
        for (name, states) in &j.quantities {
            let d = &states.pooled;
            let mut row = vec![j.name.clone(), name.to_string(), d.n.to_string()];
            row.extend(numbers(d));
            row.extend(states.cells(number));
            rows.push(row);
        }
    }
    write_rows(&dir.join(STATISTICS_FILE), &head, rows)?;
    let mut series = Vec::new();
    // one per clearance joint, in the mechanism's order
    for (k, j) in stats.iter().enumerate() {
        let Some(band) = &j.wear else { continue };
        let angles = sector_angles_deg(band.sectors.len());
        let mut head = vec!["angle_deg".to_string()];
        head.extend(VALUE_KEYS.map(|k| format!("{k}_m")));
        let rows = band.sectors.iter().zip(&angles).map(|(d, a)| {
            let mut row = vec![number(*a)];
            row.extend(numbers(d));
            row
        });
        let file = joint_file(BAND_STEM, &j.name);
        write_rows(&dir.join(file), &head, rows)?;
        let um = |v: Vec<f64>| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
        let (mean, lo, hi) = (um(band.mean()), um(band.quantile(0)), um(band.quantile(4)));
        series.push((k, angles, mean, lo, hi));
    }
    if !series.is_empty() {
        // A settling member wears through its own settling rotations too.
        let after = if scene.run.settle.is_some() {
            "each member's settling + "
        } else {
            ""
        };
        let title = format!(
            "wear after {after}{} rotations, mean of {} members, 5-95 % shaded",
            scene.run.rotations, settings.members
        );
        // one panel per joint: their angles are in different bearings' frames
        let m = &scene.mechanism;
        let panels: Vec<Axes> = series
            .iter()
            .map(|(k, a, mean, lo, hi)| Axes {
                shades: vec![Shade { series: 0, lo, hi }],
                ..wear_panel(
                    m,
                    *k,
                    &title,
                    vec![Series::new("mean wear depth", a, mean, Style::Line)],
                )
            })
            .collect();
        render(&dir.join(WEAR_FIGURE), &panels)?;
    }
    Ok(stats)
}

/// `summary.json` of `run --ensemble`: the ensemble and the distribution of every quantity.
#[derive(Serialize)]
struct EnsembleSummary<'a> {
    program: String,
    scene: String,
    title: String,
    fingerprint: String,
    /// `[key, value]` of `--set` and `--rotations`, in the order applied.
    changes: Vec<(String, String)>,
    members: usize,
    seed: u64,
    /// The protocol's key (`disc_10nm`, `--perturbation`).
    perturbation: String,
    rotations: u32,
    record_rotations: u32,
    /// The grid the recorded rotations are sampled on (s): the recorded maxima are its largest
    /// samples.
    record_interval_s: f64,
    /// Wall-clock time of all members, in parallel (s): of the process that completed the
    /// ensemble (one resumed from its journal ran only the members the journal lacked).
    wall_time_s: f64,
    joints: Vec<JointDistributions<'a>>,
}

#[derive(Serialize)]
struct JointDistributions<'a> {
    name: String,
    /// By quantity name (the `quantity` column of `ensemble_summary.csv`).
    quantities: Vec<(String, QuantitySummary<'a>)>,
}

/// A quantity in summary.json, as a row of `ensemble_summary.csv` has it and its window named:
/// `window` ([`SCALAR_WINDOWS`]), `n`, [`VALUE_KEYS`] of the pooled distribution, then
/// [`STATE_COLUMNS`] (counts as integers, `null` where a value does not exist), so that a mean
/// pooled over two states is never read alone.
struct QuantitySummary<'a> {
    name: &'static str,
    states: &'a States,
}

impl Serialize for QuantitySummary<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let pooled = &self.states.pooled;
        let mut map = s.serialize_map(Some(2 + VALUE_KEYS.len() + STATE_COLUMNS.len()))?;
        map.serialize_entry("window", &window(self.name))?;
        map.serialize_entry("n", &pooled.n)?;
        for (key, value) in VALUE_KEYS.iter().zip(pooled.values()) {
            map.serialize_entry(key, &value)?;
        }
        for (i, (key, value)) in STATE_COLUMNS.iter().zip(self.states.values()).enumerate() {
            if STATE_COUNTS.contains(&i) {
                map.serialize_entry(key, &value.map(|x| x as usize))?;
            } else {
                map.serialize_entry(key, &value)?;
            }
        }
        map.end()
    }
}

/// `README.txt` of an ensemble's folder: the conventions, then every file it wrote.
fn readme(
    title: &str,
    scene: &Scene,
    settings: &EnsembleSettings,
    stats: &[JointStatistics],
) -> String {
    let m = &scene.mechanism;
    let mut text = conventions(title, m, &scene.title);
    let worn: Vec<String> = stats
        .iter()
        .filter(|j| j.wear.is_some())
        .map(|j| joint_file(BAND_STEM, &j.name))
        .collect();
    text.push_str(&format!(
        "\nFILES\n\
         Every member is the scene run with the perturbation {} ({}) drawn from the seed and \
         the member number; statistics are over the members. Quantiles \
         qNN are type-7 sample quantiles; sd is the sample standard deviation. Angles \
         (_deg) are unwrapped around their circular mean before the statistics. {}\n\
         ensemble_members.csv: one row per member.\n\
         \x20 member                               0-based member number\n\
         \x20 J.offset_body_x_m, J.offset_body_y_m  initial journal offset, in the frame of the \
         journal's body (m); zero where the protocol starts the journal centred\n\
         \x20 rtol, atol                           the member's integration tolerances: the \
         scene's run.rtol and run.atol, multiplied under tolerance_S by the member's factor, uniform \
         in [1 - S, 1 + S]\n\
         \x20 record_rotations, record_interval_s  the window of every recorded quantity \
         below (the maxima _recorded, motion_mode, contact_fraction, impacts_per_rotation): the \
         last run.record_rotations rotations of the member's run, sampled every \
         run.record_interval_s (s)\n\
         \x20 J.max_normal_force_recorded_n        largest sampled normal force of the \
         recorded rotations (N; samples every run.record_interval_s); empty when none were \
         recorded\n\
         \x20 J.max_penetration_recorded_m         largest sampled penetration of the recorded \
         rotations (m), positive = overlap; empty when none were recorded\n\
         \x20 J.max_penetration_whole_run_m        largest penetration of the whole run (m), \
         the start-up transient (impact after the centred start) included\n\
         \x20 J.max_wear_angle_deg                 deepest sector of the final wear profile \
         (the most prominent wear region), bearing frame (deg)\n\
         \x20 J.max_wear_depth_m                   its depth (m)\n\
         \x20 J.motion_mode                        `continuous contact` or `free flight and \
         impact` (recorded rotations)\n\
         \x20 J.contact_fraction                   share of recorded samples in contact\n\
         \x20 J.impacts_per_rotation               contact onsets per rotation (recorded)\n\
         \x20 J.rotations_simulated                rotations from the start, the window of the \
         whole-run maximum and of the final wear: run.rotations plus the member's own settling \
         rotations where the scene settles\n\
         \x20 J.settled                            true if the member met the steady-state \
         criterion, false if it stopped settling at steady_state.max_rotations with its orbit \
         still changing (its recorded rotations are then no steady state); empty where the \
         scene does not settle\n\
         \x20 wall_time_s, error                   the member's wall time (s); empty error\n\
         ensemble_summary.csv: per joint and quantity (the joints' numeric columns above, \
         continuous_contact, 1 or 0 per member, whose mean is the share in continuous \
         contact, and settled as 1 or 0, whose mean is the share that settled): n (finite values), mean, sd, min, q05, q25, q50, q75, q95, max (empty \
         fields where n is 0: nothing recorded); then the \
         states the members fall into (largest-gap rule: split at the largest gap of the sorted \
         values that leaves max(2, ceil(n/10)) members on each side, when it exceeds 2 pooled \
         within-state sds, 2 * 32/n of them below 32 members, or 5.5 sds of the narrower side \
         of at least 4 members whose values do not all agree, 5.5 * sqrt(32/n) of them below \
         32 members, and one sd of the other side (a narrow state beside a wide one); a count \
         (contact_fraction, samples in contact over the recorded samples; impacts_per_rotation, \
         onsets over run.record_rotations; continuous_contact, settled and rotations_simulated, \
         whole numbers) split only at a gap of at least 2 of its steps, across a value no \
         member takes; angles cut at their largest gap on the circle first, so that low \
         and high are the two sides of the cut, and split only at a gap over 10 deg): states \
         (1 or 2; empty where n is 0), and with two low_n, low_mean, \
         low_sd, high_n, high_mean, high_sd. Where a quantity has two states, its pooled mean \
         depends on the share in each, and that share on how members are perturbed.\n\
         \x20 Each quantity is taken over a window of each member's run (`window` in {SUMMARY_FILE}):\n",
        settings.perturbation.key(),
        settings.perturbation.describe(),
        match scene.run.record_rotations {
            0 => "No rotation is recorded (run.record_rotations = 0).".to_string(),
            r => format!(
                "The recorded rotations are the last {r} of each member's run, samples every {} \
                 s (run.record_interval_s): the recorded maxima are the largest samples.",
                number(scene.run.record_interval)
            ),
        }
    ));
    for (w, covers) in WINDOWS {
        let names: Vec<&str> = (SCALARS.iter().zip(SCALAR_WINDOWS))
            .filter(|&(_, sw)| sw == w)
            .map(|(name, _)| *name)
            .collect();
        text.push_str(&format!("  {w:10} {covers}: {}\n", names.join(", ")));
    }
    if !worn.is_empty() {
        text.push_str(&format!(
            "{}: per sector of the final wear profiles (each member's after its \
             rotations_simulated{}): angle_deg (sector centre, bearing frame), then mean_m, \
             sd_m, min_m, q05_m ... q95_m, max_m of the depth worn into the bearing (m).\n\
             wear.png: the mean profile (µm), 5-95 % band shaded.\n",
            worn.join(", "),
            if scene.run.settle.is_some() {
                ", which differ between members as each settles in its own number of rotations"
            } else {
                ""
            }
        ));
    }
    text.push_str(&format!(
        "{SUMMARY_FILE}: the ensemble as JSON: program, scene, title, fingerprint, changes \
         (--set and --rotations as [key, value]), members, seed, perturbation, rotations, \
         record_rotations, record_interval_s, \
         wall_time_s, and per joint every quantity as [name, statistics]: its window (above), \
         then its row of ensemble_summary.csv: n, mean, sd, min, q05 ... q95, max, states, \
         low_n, low_mean, low_sd, high_n, high_mean, high_sd (null where no value exists).\n"
    ));
    text
}
