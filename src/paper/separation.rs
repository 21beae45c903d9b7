//! Could the members of an ensemble share a settling phase? The scheme would settle one run,
//! then continue it once per member with that member's perturbation. This study runs exactly
//! that: for every Table 3 case, member 0 settles as a steady run does; from its settled state
//! (a checkpoint) the run continues [`SEPARATION_ROTATIONS`] rotations once per member
//! `1 … 2·PAIRS`, each with its own journal offset ([`member_mechanism`]: the journal point
//! moved by at most 10 nm in its body, which shifts the gap at once). Per rotation it takes the
//! RMS distance between the journal centres (relative to the bearing) of members `2k+1` and
//! `2k+2`, on the same time grid, over the radial clearance, averaged over the pairs:
//!
//! ```text
//! s_r = mean over pairs of sqrt(mean over rotation r of |e_a(t) − e_b(t)|²) / c
//! ```
//!
//! The same pairs are also run independently from their own assembled starts (the ensembles'
//! way), whose last rotations give the separation of independent members.
//! If `s_r` grows to the level of independently started members, a shared settling phase
//! followed by that many rotations per member samples the same ensemble; if it stays small,
//! the settled state attracts its perturbations and every member would stay in the state
//! member 0 settled into. Writes `data/member_separation.csv` (two columns per case); the
//! report's section 2 reads it.

use crate::io::output::{read_csv, write_csv};
use crate::io::progress::Silent;
use crate::paper::cases::CASES;
use crate::paper::figures::output_path;
use crate::paper::provenance::{self, Inputs};
use crate::scene::{scene_path, SceneFile};
use crate::simulation::ensemble::{
    member_mechanism, member_offsets, member_state, run_member, EnsembleSettings, Perturbation,
    DEFAULT_SEED,
};
use crate::simulation::{Recording, Scene, Simulation};
use crate::{Error, Result};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Rotations each member runs after the shared settling.
pub const SEPARATION_ROTATIONS: u32 = 12;

/// Pairs of members compared per case.
pub const PAIRS: usize = 4;

/// Recorded samples per rotation.
const SAMPLES_PER_ROTATION: usize = 360;

/// File of the study under `data/`.
pub const SEPARATION_FILE: &str = "member_separation.csv";

/// First column of [`SEPARATION_FILE`].
const ROTATION_COLUMN: &str = "rotation_after_settling";

/// The separation of the pairs of one case, per rotation.
#[derive(Clone, Debug, PartialEq)]
pub struct Separation {
    /// Case scene.
    pub case: String,
    /// `s_r` of rotations 1, 2, … after the shared settling (see the module documentation).
    pub shared: Vec<f64>,
    /// `s_r` of the same pairs started independently, each from its own assembly: rotations
    /// 1, 2, … from the start; its last rotations are the spread of independent members.
    pub independent: Vec<f64>,
}

/// The mean of the last four values of a separation series, the level it reaches.
pub fn level(series: &[f64]) -> f64 {
    let tail = &series[series.len().saturating_sub(4)..];
    tail.iter().sum::<f64>() / tail.len().max(1) as f64
}

/// The first rotation (1-based) of `series` that reaches `value`.
pub fn first_reaching(series: &[f64], value: f64) -> Option<usize> {
    series.iter().position(|s| *s >= value).map(|i| i + 1)
}

/// The mean initial distance between the journal offsets of the compared pairs (m).
pub fn pair_offset_distance() -> f64 {
    let d = |m: usize| member_offsets(DEFAULT_SEED, m, 1)[0];
    (0..PAIRS)
        .map(|k| (d(2 * k + 1) - d(2 * k + 2)).norm())
        .sum::<f64>()
        / PAIRS as f64
}

/// The first clearance joint's journal centre (x, y) of a recording.
fn journal_centre(rec: &Recording) -> Result<(&[f64], &[f64])> {
    let j = rec.joints.first().ok_or_else(|| {
        Error::invalid(
            "separation study",
            "a run without a recorded clearance joint",
            "a case scene with a clearance joint",
        )
    })?;
    Ok((&j.ex, &j.ey))
}

/// One case: settle member 0, continue it per member, compare the pairs.
fn separation(case: &'static str) -> Result<Separation> {
    let mut file = SceneFile::read(scene_path(case))?;
    file.run.rotations = SEPARATION_ROTATIONS;
    file.run.record_rotations = SEPARATION_ROTATIONS;
    file.run.wear_snapshots.clear();
    file.run.settle = true;
    let mut scene = file.build()?;
    scene.run.record_interval =
        TAU / scene.mechanism.driver.omega.abs() / SAMPLES_PER_ROTATION as f64;
    let clearance = (scene.mechanism.clearance_joints.first())
        .map(|cj| cj.clearance())
        .filter(|c| *c > 0.0)
        .ok_or_else(|| {
            Error::invalid(
                "separation study",
                format!("scene `{case}`"),
                "a first clearance joint with a positive clearance",
            )
        })?;
    let y0 = member_state(&scene, DEFAULT_SEED, 0)?;
    let mut settled = Simulation::new(
        member_mechanism(&scene, DEFAULT_SEED, 0),
        scene.run.clone(),
        &y0,
    )?;
    while settled.total_rotations().is_none() {
        settled.advance_rotation()?;
    }
    let checkpoint = settled.checkpoint();
    let mut from_start = scene.run.clone();
    from_start.settle = None;
    let shared = pair_series(case, clearance, |m| {
        let varied = Scene {
            mechanism: member_mechanism(&scene, DEFAULT_SEED, m),
            ..scene.clone()
        };
        let mut sim = Simulation::resume(&varied, checkpoint.clone())?;
        sim.run_to_end(&Silent)?;
        Ok(sim.finish().recording)
    })?;
    let independent = pair_series(case, clearance, |m| {
        Ok(run_member(
            &scene,
            &from_start,
            &EnsembleSettings::default(),
            m,
            &Silent,
        )?
        .recording)
    })?;
    Ok(Separation {
        case: case.to_string(),
        shared,
        independent,
    })
}

/// `s_r` per rotation, averaged over the [`PAIRS`] pairs of members `run(m)` records.
fn pair_series(
    case: &str,
    clearance: f64,
    run: impl Fn(usize) -> Result<Recording>,
) -> Result<Vec<f64>> {
    let needed = SAMPLES_PER_ROTATION * SEPARATION_ROTATIONS as usize;
    let mut sums = vec![0.0; SEPARATION_ROTATIONS as usize];
    for k in 0..PAIRS {
        let (a, b) = (run(2 * k + 1)?, run(2 * k + 2)?);
        let ((ax, ay), (bx, by)) = (journal_centre(&a)?, journal_centre(&b)?);
        if ax.len().min(bx.len()) < needed {
            return Err(Error::Integration {
                time: 0.0,
                cause: format!("scene `{case}`: a member recorded fewer than {needed} samples"),
            });
        }
        for (r, sum) in sums.iter_mut().enumerate() {
            let samples = r * SAMPLES_PER_ROTATION..(r + 1) * SAMPLES_PER_ROTATION;
            let square: f64 = samples
                .map(|i| (ax[i] - bx[i]).powi(2) + (ay[i] - by[i]).powi(2))
                .sum();
            *sum += (square / SAMPLES_PER_ROTATION as f64).sqrt() / clearance;
        }
    }
    Ok(sums.iter().map(|s| s / PAIRS as f64).collect())
}

/// What produced `data/member_separation.csv` ([`provenance`]): every case scene, the pairs,
/// the rotations, the sampling, and the seed and protocol that perturb the members.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[SEPARATION_FILE],
    figures: &[],
    command: "cargo run --release --bin separation",
    rerun_by_all: false,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            CASES.list().map(|c| c.scene).to_vec(),
            false,
            (
                SEPARATION_ROTATIONS,
                PAIRS,
                SAMPLES_PER_ROTATION,
                DEFAULT_SEED,
                Perturbation::default(),
            ),
        )
    },
};

/// Runs the study for every Table 3 case (in parallel) and writes its CSV (one column per
/// case, one row per rotation after the shared settling) with its record ([`PROVENANCE`]).
pub fn separation_study() -> Result<Vec<Separation>> {
    provenance::recorded(&PROVENANCE, &[], study)
}

/// The study itself ([`separation_study`]).
fn study() -> Result<Vec<Separation>> {
    let cases: Vec<&'static str> = CASES.list().iter().map(|c| c.scene).collect();
    let study = cases
        .par_iter()
        .map(|c| separation(c))
        .collect::<Result<Vec<_>>>()?;
    let rotations: Vec<f64> = (1..=SEPARATION_ROTATIONS).map(f64::from).collect();
    let names: Vec<String> = (study.iter())
        .flat_map(|s| {
            [
                format!("{}{SHARED}", s.case),
                format!("{}{INDEPENDENT}", s.case),
            ]
        })
        .collect();
    let mut header = vec![ROTATION_COLUMN];
    header.extend(names.iter().map(String::as_str));
    let mut columns: Vec<&[f64]> = vec![&rotations];
    columns.extend((study.iter()).flat_map(|s| [s.shared.as_slice(), s.independent.as_slice()]));
    write_csv(&output_path("data", SEPARATION_FILE), &header, &columns)?;
    Ok(study)
}

/// Column suffixes of [`SEPARATION_FILE`]: a case's shared-settling and independent series.
const SHARED: &str = "_shared";
const INDEPENDENT: &str = "_independent";

/// The separations an earlier run of the study wrote; `None` if the file is missing or not
/// this study's.
pub fn read_separation() -> Option<Vec<Separation>> {
    let (header, columns) = read_csv(&output_path("data", SEPARATION_FILE)).ok()?;
    // One row per rotation of the study, every value a number: a file cut short changed the
    // levels the report quotes "over their last four of 12 rotations".
    let whole = (columns.iter())
        .all(|c| c.len() == SEPARATION_ROTATIONS as usize && c.iter().all(|v| v.is_finite()));
    if header.first().map(String::as_str) != Some(ROTATION_COLUMN) || !whole {
        return None;
    }
    let column = |name: String| {
        let i = header.iter().position(|h| *h == name)?;
        Some(columns[i].clone())
    };
    (header.iter().skip(1))
        .filter_map(|h| h.strip_suffix(SHARED))
        .map(|case| {
            Some(Separation {
                case: case.to_string(),
                shared: column(format!("{case}{SHARED}"))?,
                independent: column(format!("{case}{INDEPENDENT}"))?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Its members are perturbed by the default protocol ([`member_mechanism`], and
    /// [`run_member`] with the default ensemble): another default moves every series, so its
    /// record must see the protocol as it sees the seed.
    #[test]
    fn its_record_sees_the_members_perturbation() {
        let settings = (PROVENANCE.inputs)(&[]).settings;
        let protocol = format!("{:?}", Perturbation::default());
        assert!(settings.contains(&protocol), "{protocol} in {settings}");
    }

    #[test]
    fn level_is_the_last_four_and_reaching_is_one_based() {
        let series = [0.01, 0.2, 0.5, 0.4, 0.6, 0.5];
        assert!((level(&series) - 0.5).abs() < 1e-12);
        assert_eq!(first_reaching(&series, 0.45), Some(3));
        assert_eq!(first_reaching(&series, 0.7), None);
        assert!((level(&[0.3]) - 0.3).abs() < 1e-12);
    }
}
