//! How the predicted wear depends on how finely the bearing is divided (eq. 9's sectors).
//!
//! ```text
//! h_i = h_(i−1) + k P_i Δs_i / H      (9), per sector of width 2π/N
//! ```
//! Each sector holds the mean depth over its width, so a wear scar narrower than a few
//! sectors is read shallower than it is, and its slope (which the gap's validity bound
//! watches) is smoothed away. The scenes divide the bearing into 360 sectors (a calibration
//! setting, `paper.md` section 4). This study reruns the wear cases' rotations (those of
//! the wear figures, 5 to 15) with [`SECTOR_COUNTS`] sectors, [`SECTOR_MEMBERS`] members each
//! (seed 1, the default perturbation), and records per count, over the members that stayed
//! within the gap's validity bound, each member's deepest sector depth (mean and sd), the
//! angle and width of each member's most prominent wear region, their evaluations and wall
//! time, and how many members left the bound (and the earliest rotation one did). The 30
//! r/min case's scar is a few degrees wide at half its prominence and narrows with the sector
//! width (a Hertz half-angle under one degree at its small load), the standard case's tens of
//! degrees: the first is what the sector width limits.
//! Writes `data/sector_resolution.csv`; the report's section 5 reads it.

use crate::analysis::statistics::Distribution;
use crate::io::output::{read_rows, write_rows};
use crate::io::progress::{Counter, Progress};
use crate::paper::cases::{wear_member, wear_scene, WearMember};
use crate::paper::figures::output_path;
use crate::paper::format::{csv_statistic, parse_statistic};
use crate::paper::provenance::{self, Inputs};
use crate::scene::{scene_path, SceneFile};
use crate::simulation::ensemble::{run_member, EnsembleSettings};
use crate::{Error, Result};
use rayon::prelude::*;

/// Sector counts compared (sector widths 4° to 0.125°); the scenes' own is 360.
pub const SECTOR_COUNTS: [usize; 7] = [90, 180, 360, 720, 1080, 1440, 2880];

/// The wear cases of the paper's wear figures (5-15).
pub const SECTOR_CASES: [&str; 5] = [
    "standard",
    "clearance_0.2mm",
    "clearance_0.5mm",
    "speed_30rpm",
    "speed_600rpm",
];

/// Members per case and count: the deepest depth of the standard and 2000 r/min clearance cases
/// spreads by 3-9 % between members, so the mean of 8 is known to 1-3 %; the 30 r/min members
/// agree to 1e-4. A count's dependence is judged against that standard error (the report's
/// section 5).
pub const SECTOR_MEMBERS: usize = 8;

/// File of the study under `data/`.
pub const SECTOR_RESOLUTION_FILE: &str = "sector_resolution.csv";

/// Columns of [`SECTOR_RESOLUTION_FILE`].
pub const SECTOR_RESOLUTION_HEADER: [&str; 14] = [
    "case",
    "sectors",
    "members",
    "within_validity",
    "earliest_validity_stop_rotation",
    "deepest_mean_m",
    "deepest_sd_m",
    "paired_members",
    "paired_change_m",
    "paired_change_se_m",
    "prominent_region_deg",
    "prominent_region_width_deg",
    "evaluations_mean",
    "wall_time_within_s",
];

/// One case at one sector count: a row of [`SECTOR_RESOLUTION_FILE`].
#[derive(Clone, Debug, PartialEq)]
pub struct SectorRow {
    /// Case scene.
    pub case: String,
    /// Sectors of the bearing profile.
    pub sectors: usize,
    /// Members run.
    pub members: usize,
    /// Members that ran all rotations within the gap's validity bound.
    pub within: usize,
    /// The earliest driver rotation at which a member left the bound (`None`: none did).
    pub earliest_stop: Option<u32>,
    /// Deepest sector depth at the end (m): mean over the members within the bound.
    pub deepest_mean: f64,
    /// Its standard deviation over those members (m).
    pub deepest_sd: f64,
    /// Members within the bound both at this count and at the scene's own.
    pub paired: usize,
    /// Mean over them of each member's deepest depth here less its own at the scene's count
    /// (m): the same seeds at both counts, so the members' spread cancels.
    pub paired_change: f64,
    /// Its standard error (m).
    pub paired_change_se: f64,
    /// Angle of each member's most prominent wear region (deg), circular mean over those
    /// members (between scars where members' most prominent scars differ).
    pub region_deg: f64,
    /// Width of that region at half its prominence (deg), mean over them.
    pub region_width_deg: f64,
    /// Mean right-hand-side evaluations of those members.
    pub evaluations: f64,
    /// Wall time of the members within the bound (s, summed; the rows share the cores).
    pub wall_time: f64,
}

impl SectorRow {
    /// The row as written, in the order of [`SECTOR_RESOLUTION_HEADER`].
    fn fields(&self) -> Vec<String> {
        vec![
            self.case.clone(),
            self.sectors.to_string(),
            self.members.to_string(),
            self.within.to_string(),
            self.earliest_stop.map_or(String::new(), |r| r.to_string()),
            csv_statistic(self.deepest_mean),
            csv_statistic(self.deepest_sd),
            self.paired.to_string(),
            csv_statistic(self.paired_change),
            csv_statistic(self.paired_change_se),
            csv_statistic(self.region_deg),
            csv_statistic(self.region_width_deg),
            // Whole evaluations: the mean of counts, read as a count.
            csv_statistic(self.evaluations.round()),
            format!("{:.2}", self.wall_time),
        ]
    }

    /// A row as [`SectorRow::fields`] wrote it; `None` if a field does not parse.
    fn parse(f: &[String]) -> Option<SectorRow> {
        // An empty statistic is one of no member (every member left the bound).
        let x = |i: usize| parse_statistic(f.get(i)?);
        let count = |i: usize| f.get(i)?.parse::<usize>().ok();
        let earliest_stop = match f.get(4)?.as_str() {
            "" => None,
            s => Some(s.parse::<u32>().ok()?),
        };
        Some(SectorRow {
            case: f.first()?.clone(),
            sectors: count(1)?,
            members: count(2)?,
            within: count(3)?,
            earliest_stop,
            deepest_mean: x(5)?,
            deepest_sd: x(6)?,
            paired: count(7)?,
            paired_change: x(8)?,
            paired_change_se: x(9)?,
            region_deg: x(10)?,
            region_width_deg: x(11)?,
            evaluations: x(12)?,
            wall_time: x(13)?,
        })
    }
}

/// The rows an earlier run of the study wrote; `None` if the file is missing or not of this
/// study's columns.
pub fn read_sector_resolution() -> Option<Vec<SectorRow>> {
    let (header, rows) = read_rows(&output_path("data", SECTOR_RESOLUTION_FILE)).ok()?;
    if header != SECTOR_RESOLUTION_HEADER {
        return None;
    }
    rows.iter().map(|r| SectorRow::parse(r)).collect()
}

/// What one member ended with: its wear, evaluations and wall time, or the rotation at which
/// it left the gap's validity bound.
type MemberEnd = std::result::Result<(WearMember, u64, f64), u32>;

/// What produced `data/sector_resolution.csv` ([`provenance`]): the wear cases' scenes, the
/// sector counts and the members.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[SECTOR_RESOLUTION_FILE],
    figures: &[],
    command: "cargo run --release --bin sector_resolution",
    rerun_by_all: false,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            SECTOR_CASES.to_vec(),
            false,
            (SECTOR_COUNTS, SECTOR_MEMBERS, EnsembleSettings::default()),
        )
    },
};

/// Runs the study, telling `progress` the members finished, and writes its CSV with its record
/// ([`PROVENANCE`]). A member that leaves the gap's validity bound is counted, not averaged;
/// any other failure stops the study.
pub fn sector_resolution(progress: &dyn Progress) -> Result<Vec<SectorRow>> {
    provenance::recorded(&PROVENANCE, &[], || study(progress))
}

/// The study itself ([`sector_resolution`]).
fn study(progress: &dyn Progress) -> Result<Vec<SectorRow>> {
    let ensemble = EnsembleSettings {
        members: SECTOR_MEMBERS,
        ..EnsembleSettings::default()
    };
    let scenes = SECTOR_CASES
        .iter()
        .flat_map(|&case| SECTOR_COUNTS.iter().map(move |&n| (case, n)))
        .map(|(case, n)| {
            let scene = wear_scene(case, 0, &|f| {
                for c in &mut f.clearance {
                    if let Some(w) = &mut c.wear {
                        w.sectors = n;
                    }
                }
            })?;
            Ok((case, n, scene))
        })
        .collect::<Result<Vec<_>>>()?;
    let jobs: Vec<(usize, usize)> = (0..scenes.len())
        .flat_map(|k| (0..SECTOR_MEMBERS).map(move |m| (k, m)))
        .collect();
    let done = Counter::new(progress, jobs.len());
    let ends = jobs
        .par_iter()
        .map(|&(k, m)| {
            let (case, n, scene) = &scenes[k];
            let end = match run_member(scene, &scene.run, &ensemble, m, progress) {
                Ok(out) => {
                    let (evaluations, wall) = (out.stats.evaluations, out.wall_time);
                    Ok((wear_member(out), evaluations, wall))
                }
                Err(Error::Validity { time, .. }) => Err((time / scene.period()).round() as u32),
                Err(e) => return Err(e.in_run(&format!("{case} at {n} sectors, member {m}"))),
            };
            done.finish_one();
            Ok(end)
        })
        .collect::<Result<Vec<MemberEnd>>>()?;
    let ends: Vec<&[MemberEnd]> = ends.chunks(SECTOR_MEMBERS).collect();
    // Each case's ends at its scene's own count, read once per case.
    let own: Vec<(&str, Option<&[MemberEnd]>)> = SECTOR_CASES
        .iter()
        .map(|&case| {
            let n = scene_sectors(case);
            let k = scenes
                .iter()
                .position(|(c, m, _)| *c == case && Some(*m) == n);
            (case, k.map(|k| ends[k]))
        })
        .collect();
    let own = |case: &str| own.iter().find(|(c, _)| *c == case).and_then(|(_, e)| *e);
    let rows: Vec<SectorRow> = scenes
        .iter()
        .zip(&ends)
        .map(|((case, n, _), ends)| row(case, *n, ends, own(case)))
        .collect();
    write_rows(
        &output_path("data", SECTOR_RESOLUTION_FILE),
        &SECTOR_RESOLUTION_HEADER,
        rows.iter().map(SectorRow::fields),
    )?;
    Ok(rows)
}

/// The sector count `case`'s scene runs with (`None` if it cannot be read or does not wear).
pub fn scene_sectors(case: &str) -> Option<usize> {
    let file = SceneFile::read(scene_path(case)).ok()?;
    Some(file.clearance.first()?.wear.as_ref()?.sectors)
}

/// The row of `case` at `sectors` from its members' ends, paired member by member with `own`,
/// the ends at the scene's own count.
fn row(case: &str, sectors: usize, ends: &[MemberEnd], own: Option<&[MemberEnd]>) -> SectorRow {
    let member_deepest = |e: &MemberEnd| e.as_ref().ok().map(|(w, ..)| w.max_depth());
    let change = Distribution::of(
        own.into_iter()
            .flat_map(|own| ends.iter().zip(own))
            .filter_map(|(e, o)| Some(member_deepest(e)? - member_deepest(o)?)),
    );
    let within: Vec<&(WearMember, u64, f64)> =
        ends.iter().filter_map(|e| e.as_ref().ok()).collect();
    let deepest = Distribution::of(within.iter().map(|(w, ..)| w.max_depth()));
    let first = |w: &WearMember| w.regions.first().cloned();
    let regions: Vec<_> = within.iter().filter_map(|(w, ..)| first(w)).collect();
    // Means over no member are NaN: written as empty fields.
    SectorRow {
        case: case.to_string(),
        sectors,
        members: ends.len(),
        within: within.len(),
        earliest_stop: ends.iter().filter_map(|e| e.as_ref().err()).min().copied(),
        deepest_mean: deepest.mean,
        deepest_sd: deepest.sd,
        paired: change.n,
        paired_change: change.mean,
        paired_change_se: change.standard_error(),
        region_deg: Distribution::of_angles_deg(regions.iter().map(|r| r.angle_deg)).mean,
        region_width_deg: Distribution::of(regions.iter().map(|r| r.width_deg)).mean,
        evaluations: Distribution::of(within.iter().map(|(_, e, _)| *e as f64)).mean,
        wall_time: within.iter().fold(0.0, |sum, (.., w)| sum + w),
    }
}
