//! `jointwear run SCENE --ensemble N`: members in parallel from seeded initial offsets, each
//! journaled as it finishes ([`Journal`]: `--resume` runs only the missing ones), their folder
//! ([`write_ensemble`]: statistics as CSVs, the band plot) and the summary it prints.

use crate::failure::{CliResult, Failure};
use crate::run::Saved;
use crate::{claim_outputs, load_variant};
use jointwear::io::format::{self as people, quantity, Reading};
use jointwear::io::interrupt;
use jointwear::io::progress::progress_bar;
use jointwear::simulation::ensemble::{self, EnsembleSettings};
use jointwear::simulation::folder::ensemble::{write_ensemble, Member};
use jointwear::simulation::folder::FolderCommand;
use jointwear::simulation::journal::{refuse_journal, Journal, MemberResult};
use jointwear::simulation::summary::{summarize, window};
use jointwear::simulation::Scene;
use jointwear::Error;
use std::path::{Path, PathBuf};

/// `settings` of `--ensemble N --seed S` checked; a bad member count is bad input naming
/// `--ensemble` (the library names the field `members`).
pub fn checked(path: &Path, settings: &EnsembleSettings) -> CliResult<()> {
    settings
        .validate()
        .map_err(|e| flagged(path, e, "--ensemble"))
}

/// `--perturbation` checked against the scene it perturbs
/// ([`ensemble::Perturbation::check`]), before any member runs; a bad one is bad input naming
/// the flag (the library names the field `perturbation`).
pub fn fits(path: &Path, settings: &EnsembleSettings, scene: &Scene) -> CliResult<()> {
    (settings.perturbation.check(scene)).map_err(|e| flagged(path, e, "--perturbation"))
}

/// `e` as bad input, a bad value's field named by `flag`, the flag that gave it.
fn flagged(path: &Path, e: Error, flag: &str) -> Failure {
    let e = match e {
        Error::Invalid {
            value, expected, ..
        } => Error::invalid(flag, value, expected),
        e => e,
    };
    Failure::input(path, e)
}

/// `run --ensemble`: members of the scene at `path` (with `sets` and `rotations` applied,
/// [`load_variant`]) in parallel, their statistics as CSVs, a band plot, `summary.json`,
/// `README.txt` and a printed summary. Each member's results go to the folder's journal as it
/// finishes ([`Journal`]); `saved` says what to do with the journal of an unfinished ensemble
/// in the folder: continue it (only its missing members run), discard it, or refuse the folder.
pub fn run_ensemble(
    path: &Path,
    sets: &[String],
    rotations: Option<u32>,
    out: Option<PathBuf>,
    settings: EnsembleSettings,
    saved: Saved,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    checked(path, &settings)?;
    let variant = load_variant(path, sets, rotations, ("ensemble", out))?;
    let (scene, dir) = (&variant.scene, &variant.dir);
    fits(path, &settings, scene)?;
    // (Refused there too: a folder holding a plain run's unfinished checkpoint.)
    let _claim = claim_outputs(path, dir, FolderCommand::Ensemble)?;
    let journal = Journal::new(dir, &variant.variant.fingerprint(), &settings);
    let mut kept = match saved {
        Saved::Resume if !journal.exists() => {
            return Err(Failure::input(
                path,
                Error::invalid(
                    "--resume",
                    journal.path().display(),
                    "the journal of an ensemble interrupted while running into this --out \
                     folder (an ensemble that completed has removed its own)",
                ),
            ))
        }
        Saved::Resume => {
            let kept = journal.read(scene).map_err(|e| Failure::input(path, e))?;
            eprintln!(
                "note: continuing the ensemble journaled in {}: {} of {} members finished \
                 (--resume)",
                journal.path().display(),
                kept.iter().flatten().count(),
                settings.members
            );
            kept
        }
        Saved::Discard => {
            if journal.exists() {
                journal.remove().map_err(bad)?;
                eprintln!(
                    "note: removed {}, the journal of an unfinished ensemble \
                     (--discard-checkpoint)",
                    journal.path().display()
                );
            }
            vec![None; settings.members]
        }
        Saved::Keep => {
            let how = "continue that ensemble with --resume, start over with \
                       --discard-checkpoint";
            refuse_journal("--out", dir, how).map_err(|e| Failure::input(path, e))?;
            vec![None; settings.members]
        }
    };
    interrupt::keep(format!(
        "the finished members stay in {} (continue with --resume)",
        journal.path().display()
    ));
    let missing: Vec<usize> = (0..settings.members)
        .filter(|&k| kept[k].is_none())
        .collect();
    let clock = std::time::Instant::now();
    let bar = progress_bar(missing.len() as u64, "members");
    let ran = ensemble::run_members(
        scene,
        &settings,
        &missing,
        |k, o| {
            let result = MemberResult {
                joints: summarize(scene, &o),
                final_wear: o.final_wear,
                wall_time_s: o.wall_time,
            };
            journal.record(k, &result).map(|()| result)
        },
        &bar,
    );
    bar.finish_and_clear();
    for (k, result) in missing.iter().zip(ran.map_err(bad)?) {
        kept[*k] = Some(result.map_err(bad)?);
    }
    let results: Vec<MemberResult> = kept.into_iter().flatten().collect();
    // A cap reached is not a steady state: those members' recorded rotations are not after
    // settling (every joint's summary says it of its member).
    let unsettled = (results.iter())
        .filter(|r| r.joints.first().is_some_and(|j| j.settled == Some(false)))
        .count();
    let walls: Vec<f64> = results.iter().map(|r| r.wall_time_s).collect();
    let members: Vec<Member> = (results.into_iter())
        .map(|r| (r.joints, r.final_wear))
        .collect();
    let wall = clock.elapsed().as_secs_f64();
    let origin = variant.variant.origin();
    let stats =
        write_ensemble(dir, &origin, scene, &settings, (&members, &walls), wall).map_err(bad)?;
    // The outputs hold every member: the journal has served.
    journal.remove().map_err(bad)?;
    println!("{}", scene.title);
    println!(
        "  {} members (seed {}) of {} rotations{} in {} of wall time{}",
        settings.members,
        settings.seed,
        scene.run.rotations,
        if scene.run.settle.is_some() {
            " after settling (the wear and whole-run maxima cover each member's rotations \
             simulated, below)"
        } else {
            ""
        },
        quantity(wall, "s"),
        match settings.members - missing.len() {
            0 => String::new(),
            k => format!(" (this process's, {k} members read from the journal)"),
        }
    );
    if let Some(note) = ensemble::unsettled_note(unsettled, settings.members) {
        println!("  {note}");
    }
    println!(
        "  perturbation {}: {}",
        settings.perturbation.key(),
        settings.perturbation.describe()
    );
    if scene.run.record_rotations > 0 {
        // As a single run's printout: the recorded quantities are read off the samples.
        println!(
            "  recorded rotations: the last {}, samples every {} s (the recorded maxima and \
             contact onsets are read off the samples)",
            scene.run.record_rotations,
            people::number(scene.run.record_interval)
        );
    }
    for j in &stats {
        // The sd and quantiles of a few members scatter widely: the header says how many.
        println!(
            "  joint {} (mean ± sd over {} members, [5 %, 95 %]):",
            j.name, settings.members
        );
        for (name, states) in &j.quantities {
            // Said once for the run above ("not settled: …"), not per joint.
            if name == &"settled" {
                continue;
            }
            let d = &states.pooled;
            let mut r = Reading::of(name);
            // The column keeps its name; what it counts is the contact onsets between samples,
            // as the single run's printout says.
            if name == &"impacts_per_rotation" {
                r.label = "contact onsets per rotation".into();
            }
            // A quantity of the recorded rotations says so where its name does not (the
            // motion's figures, as the forces' do).
            if window(name) == Some("recorded") && !name.contains("recorded") {
                r.label.push_str(" (recorded)");
            }
            if d.n == 0 {
                println!("    {:38} not recorded (run.record_rotations = 0)", r.label);
            } else if name == &"continuous_contact" {
                let k = (d.mean * d.n as f64).round();
                println!(
                    "    continuous contact in {k} of {} members (recorded rotations)",
                    d.n
                );
            } else {
                // Over fewer members than the header says where some have no value.
                let over = if d.n == settings.members {
                    String::new()
                } else {
                    format!("  (over the {} members with a value)", d.n)
                };
                println!(
                    "    {:38} {}  [{}, {}]{over}",
                    r.label,
                    r.mean_sd(d.mean, d.sd),
                    people::number(d.quantiles[0] * r.scale),
                    people::number(d.quantiles[4] * r.scale)
                );
                if let Some((low, high)) = states.low_high() {
                    let part = |s: &jointwear::analysis::states::State| {
                        let x = &s.distribution;
                        format!("{} of {}: {}", x.n, d.n, r.mean_sd(x.mean, x.sd))
                    };
                    println!("      two states: low {}, high {}", part(low), part(high));
                }
            }
        }
    }
    println!("outputs in {}", dir.display());
    Ok(())
}
