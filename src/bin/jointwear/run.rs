//! `jointwear run SCENE`: one run of a scene (with its `--set` values and `--rotations`), with
//! checkpoints and resumption; its folder ([`write_run`]: time series, wear profiles and
//! snapshots, default plots, `summary.json` and `README.txt`) and the summary it prints.

use crate::ensemble::{checked, fits};
use crate::failure::{CliResult, Failure};
use crate::{claim_outputs, load_variant};
use jointwear::io::format::{number, quantity};
use jointwear::io::interrupt;
use jointwear::io::progress::{progress_bar, Progress};
use jointwear::simulation::checkpoint::{
    read_checkpoint, refuse_checkpoint, write_checkpoint, CHECKPOINT_FILE,
};
use jointwear::simulation::ensemble::{member_simulation, EnsembleSettings};
use jointwear::simulation::folder::run::write_run;
use jointwear::simulation::folder::{FolderCommand, SUMMARY_FILE};
use jointwear::simulation::summary::JointSummary;
use jointwear::simulation::Scene;
use jointwear::simulation::{RunOutput, Simulation};
use jointwear::Error;
use std::path::{Path, PathBuf};

/// What a run does with the checkpoint of an unfinished run in its output folder.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Saved {
    /// `--resume`: continues it.
    Resume,
    /// `--discard-checkpoint`: removes it and starts over.
    Discard,
    /// Neither: a folder holding one is refused, so that no checkpoint is lost unasked.
    Keep,
}

impl Saved {
    /// The choice the flags `--resume` and `--discard-checkpoint` (exclusive) make.
    pub fn from_flags(resume: bool, discard: bool) -> Saved {
        if resume {
            Saved::Resume
        } else if discard {
            Saved::Discard
        } else {
            Saved::Keep
        }
    }
}

/// `run` without `--ensemble` (or with `--member`): simulates the scene at `path` with `sets`
/// and `rotations` applied ([`load_variant`]), or resumes its checkpoint (`saved_run`), or runs
/// `member` (the ensemble and member number) of an ensemble, writes its outputs into `out` and
/// prints a summary.
pub fn run(
    path: &Path,
    sets: &[String],
    rotations: Option<u32>,
    out: Option<PathBuf>,
    checkpoint_every: Option<u32>,
    saved_run: Saved,
    member: Option<(EnsembleSettings, usize)>,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    if let Some((ensemble, k)) = &member {
        checked(path, ensemble)?;
        if *k >= ensemble.members {
            let expected = format!(
                "a member number in [0, {}] (0-based) of `--ensemble {}`",
                ensemble.members - 1,
                ensemble.members
            );
            return Err(Failure::input(
                path,
                Error::invalid("--member", k, expected),
            ));
        }
    }
    let kind = member
        .as_ref()
        .map_or("run".into(), |(_, k)| format!("member-{k}"));
    let loaded = load_variant(path, sets, rotations, (&kind, out))?;
    let (scene, dir) = (&loaded.scene, &loaded.dir);
    let fingerprint = &loaded.variant.fingerprint();
    // A member's protocol is checked before the folder is touched (a checkpoint discarded,
    // say); a resumed one is the run it saved.
    if let (Some((ensemble, _)), false) = (&member, saved_run == Saved::Resume) {
        fits(path, ensemble, scene)?;
    }
    let command = match member {
        Some(_) => FolderCommand::Member,
        None => FolderCommand::Run,
    };
    let _claim = claim_outputs(path, dir, command)?;
    if checkpoint_every == Some(0) {
        return Err(Failure::input(
            path,
            Error::invalid("--checkpoint-every", 0, "at least 1 rotation"),
        ));
    }
    let saved = dir.join(CHECKPOINT_FILE);
    let io = |source| {
        bad(Error::Io {
            path: saved.clone(),
            source,
        })
    };
    if saved.exists() && saved_run == Saved::Discard {
        std::fs::remove_file(&saved).map_err(io)?;
        eprintln!(
            "note: removed {}, the checkpoint of an unfinished run (--discard-checkpoint)",
            saved.display()
        );
    } else if saved_run == Saved::Keep {
        let how = "continue that run with --resume, start over with --discard-checkpoint";
        refuse_checkpoint("--out", dir, how).map_err(|e| Failure::input(path, e))?;
    }
    let mut sim = if saved_run == Saved::Resume {
        let checkpoint = read_checkpoint(&saved, fingerprint).map_err(|e| match e {
            Error::Io { .. } => Failure::input(
                path,
                Error::invalid(
                    "--resume",
                    saved.display(),
                    "a checkpoint written by `run --checkpoint-every K` into this --out folder",
                ),
            ),
            e => Failure::input(path, e),
        })?;
        let sim = Simulation::resume(scene, checkpoint)
            .map_err(|e| Failure::input(path, e.in_context(&format!("in {}", saved.display()))))?;
        eprintln!(
            "note: continuing the run saved in {} after rotation {} (--resume)",
            saved.display(),
            sim.rotations_done()
        );
        sim
    } else if let Some((ensemble, k)) = &member {
        member_simulation(scene, &scene.run, ensemble, *k).map_err(bad)?
    } else {
        Simulation::start(scene).map_err(bad)?
    };
    if checkpoint_every.is_some() {
        interrupt::keep(format!(
            "the last checkpoint stays in {} (continue with --resume)",
            saved.display()
        ));
    }
    let bar = progress_bar(scene.run.rotations as u64, "rotations");
    let result = (|| {
        while !sim.is_finished() {
            sim.advance_rotation()?;
            let done = sim.rotations_done();
            // While a run settles its length is unknown: the bar then counts settling rotations.
            let total = sim.total_rotations();
            let total = total.unwrap_or(done + scene.run.rotations);
            bar.observe(done.into(), Some(total.into()));
            if checkpoint_every.is_some_and(|k| done % k == 0) {
                write_checkpoint(&saved, fingerprint, sim.checkpoint())?;
            }
        }
        Ok(())
    })();
    bar.finish_and_clear();
    result.map_err(bad)?;
    let out = sim.finish();
    let member = member.as_ref().map(|(e, k)| (e, *k));
    let joints = write_run(dir, &loaded.variant.origin(), scene, &out, member).map_err(bad)?;
    // A completed run needs no checkpoint (any there is its own: another is refused or
    // discarded above); a failed one keeps its last.
    if saved.exists() {
        std::fs::remove_file(&saved).map_err(io)?;
    }
    print_summary(scene, &out, &joints);
    println!("outputs in {}", dir.display());
    Ok(())
}

/// Says on stderr which values `--rotations n` cut beyond `run.rotations` (`cuts`: key, value).
pub fn print_cuts(cuts: &[(String, toml::Value)], n: u32) {
    for (key, value) in cuts {
        eprintln!("note: --rotations {n} sets {key} = {value}");
    }
}

/// Wear regions printed per joint; `summary.json` lists them all.
const SHOWN_REGIONS: usize = 3;

/// The run's summary on stdout: counters, and per joint (`joints`, as its folder's) forces,
/// motion and wear regions. What was not recorded is said to be, never printed as NaN.
fn print_summary(scene: &Scene, out: &RunOutput, joints: &[JointSummary]) {
    let s = &out.stats;
    println!("{}", scene.title);
    // A settling run simulates its settling rotations too (the wear and the whole-run
    // maximum cover them).
    let rotations = match out.settling {
        Some(settled) => format!("{} settling + {}", settled.rotations, scene.run.rotations),
        None => scene.run.rotations.to_string(),
    };
    // A cap reached is not a steady state: the recorded rotations are not after settling.
    let unsettled = out.settling.and_then(|s| s.unsettled_note());
    println!(
        "  {rotations} rotations in {} of wall time: {} steps, {} rejected, {} evaluations, {} \
         contact onsets",
        quantity(out.wall_time, "s"),
        s.steps,
        s.rejected,
        s.evaluations,
        s.events
    );
    if let Some(note) = unsettled {
        println!("  {note}");
    }
    // Impacts make a run chaotic: one run's wear peak read as the scene's misleads (the
    // unperturbed standard run's, 0.503 µm, lies 4.3 standard deviations below its 32-member
    // ensemble's 0.669 ± 0.039 µm).
    println!(
        "  one trajectory of a chaotic system: its numbers are one draw; `--ensemble N` gives \
         their spread over perturbed starts, and the states its members fall into"
    );
    if let Some(e) = out.energy {
        println!(
            "  energy balance residual {} (relative)",
            number(e.residual())
        );
    }
    // The recorded window's numbers are read off its samples, which may miss a peak or a
    // contact onset between them: the printout names the grid.
    let grid = format!("samples every {} s", number(scene.run.record_interval));
    for j in joints {
        println!("  joint {}:", j.name);
        match (j.max_normal_force_recorded, j.max_penetration_recorded) {
            (Some(f), Some(p)) => println!(
                "    max normal force {}, max penetration {} (recorded rotations, largest of the {grid})",
                quantity(f, "N"),
                quantity(p * 1e6, "µm")
            ),
            _ => println!(
                "    max normal force and penetration not recorded (run.record_rotations = 0)"
            ),
        }
        println!(
            "    max penetration {} over the whole run (start-up transient included)",
            quantity(j.max_penetration_whole_run * 1e6, "µm")
        );
        if let Some(m) = j.motion {
            println!(
                "    motion: {} ({} in contact, {} contact onsets per rotation; recorded \
                 rotations, {grid})",
                m.mode(),
                quantity(100.0 * m.contact_fraction, "%"),
                number(m.impacts_per_rotation)
            );
        } else {
            println!("    motion: not classified (run.record_rotations = 0)");
        }
        let shown = j.regions.len().min(SHOWN_REGIONS);
        if shown < j.regions.len() {
            println!(
                "    wear regions: {} ({shown} most prominent shown, all in {SUMMARY_FILE})",
                j.regions.len()
            );
        }
        for p in &j.regions[..shown] {
            println!(
                "    wear region at {}: depth {}, prominence {}, width {}",
                quantity(p.angle_deg, "deg"),
                quantity(p.depth * 1e6, "µm"),
                quantity(p.prominence * 1e6, "µm"),
                quantity(p.width_deg, "deg")
            );
        }
    }
}
