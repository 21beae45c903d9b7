//! `jointwear`: simulate, check, sweep and predict long-life wear of any scene file.
//!
//! Exit codes: 0 success, 2 bad input (scene value, TOML, command-line syntax), 1 a failure
//! while running (integration, writing outputs), 130 interrupted.
//!
//! This file owns the command line (arguments, help, dispatch) and the output naming shared by
//! the subcommands; each subcommand lives in its own module: [`run`] (one run), [`ensemble`]
//! (`run --ensemble`), [`check`], [`animate`], [`sweep`] (`sweep` and `sweep-merge`) and [`longlife`];
//! their output folders are written by [`jointwear::simulation::folder`]; [`failure`] turns
//! errors into messages and exit codes.

mod animate;
mod check;
mod ensemble;
mod failure;
mod longlife;
mod run;
mod sweep;

use clap::{Parser, Subcommand};
use failure::{CliResult, Failure};
use jointwear::io::interrupt;
use jointwear::io::lock::{self, print_notes, Lock};
use jointwear::io::paper_claim::claim_output;
use jointwear::scene::reversal_note;
use jointwear::scene::variant::{parse_value, Variant};
use jointwear::simulation::checkpoint::refuse_checkpoint;
use jointwear::simulation::ensemble::{EnsembleSettings, Perturbation, DEFAULT_SEED, MAX_MEMBERS};
use jointwear::simulation::folder::{self, FolderCommand};
use jointwear::simulation::Scene;
use jointwear::sweep::{canonical_sets, Assignment};
use jointwear::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const RUN_HELP: &str = "\
KEY is a dotted path into the scene file, array elements by 0-based number \
(clearance.0.clearance_mm, run.method); VALUE is TOML (0.02, [0.0, -9.81], \"rk4\" or rk4). \
A bad key or value exits with code 2 naming the key, the value and the valid range.

Writes into the output folder: timeseries.csv (the recorded rotations: time, unwrapped \
driver angle and, per clearance joint, journal eccentricity, contact angle, penetration, \
forces, sliding velocity, pressure and wear rate; per body the accelerations), \
wear_<joint>.csv (final profile), wear_snapshots_<joint>.csv (the profile at each of \
run.wear_snapshots) and wear_evolution.png, trajectory.png, normal_force.png, wear.png, \
summary.json (settings, counters, wall time and per-joint results, machine-readable) and \
README.txt (every column's unit, frame and sign convention). Numbers are written in the \
shortest decimal form that reads back to the identical double.

With --ensemble N: ensemble_members.csv (one row per member), ensemble_summary.csv (mean, \
sd, min, quantiles and max of every scalar result), ensemble_wear_<joint>.csv (the \
per-sector band of the final wear profiles), wear.png (mean profile, 5-95 % band shaded), \
summary.json and README.txt.

With --member K (and the --seed S and --perturbation P of the ensemble, default 1 and \
disc_10nm): member K (0-based) of `--ensemble N --seed S --perturbation P` as one run, bit for \
bit the member the ensemble ran (or the perturbation study ran under protocol P), with all of \
a run's outputs; with --ensemble N too, K must be below N.";

const EXAMPLES: &str = "\
Examples:
  jointwear check data/scenes/fourbar.toml
  jointwear animate data/scenes/standard.toml --out /tmp/standard
  jointwear run data/scenes/standard.toml --out out/standard
  jointwear run data/scenes/standard.toml --rotations 10 --set clearance.0.clearance_mm=0.2
  jointwear run data/scenes/standard.toml --ensemble 16 --seed 1
  jointwear run data/scenes/standard.toml --member 3 --seed 1 --perturbation axis_10nm
  jointwear sweep data/scenes/standard.toml \\
      --set clearance.0.clearance_mm=0.02,0.1,0.5 --set driver.speed_rpm=-600,-2000 --out sweep.csv
  jointwear sweep data/scenes/standard.toml --set driver.speed_rpm=-500,-1000,-1500,-2000 \\
      --shard 2/4 --out shard2.csv
  jointwear sweep-merge shard1.csv shard2.csv shard3.csv shard4.csv --out all.csv
  jointwear longlife data/scenes/standard.toml --rotations 1e6 --k-over-h 1e-15";

/// Wear prediction in planar mechanisms with clearance revolute joints.
#[derive(Parser)]
#[command(version, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene: time series and wear CSVs, plots and a summary.
    #[command(after_help = RUN_HELP)]
    #[command(group(clap::ArgGroup::new("perturbed").args(["ensemble", "member"]).multiple(true)))]
    Run {
        scene: PathBuf,
        /// Output directory [default: out/<scene stem>/run; with --ensemble
        /// out/<scene stem>/ensemble; with --member K out/<scene stem>/member-K]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Change one value of the scene: KEY is a dotted path into the scene file (as for
        /// `sweep`), VALUE one TOML value (repeatable)
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Simulate N rotations instead of the scene's run.rotations (wear snapshots past N
        /// are dropped and run.record_rotations is cut to N, unless set with --set)
        #[arg(long, value_name = "N")]
        rotations: Option<u32>,
        /// Run N members, each from an initial journal offset of at most 10 nm in a seeded
        /// random direction (or perturbed as --perturbation says), and report statistics over
        /// them instead of one trajectory
        #[arg(long, value_name = "N")]
        ensemble: Option<usize>,
        /// Seed of the ensemble's initial offsets
        #[arg(long, default_value_t = DEFAULT_SEED, requires = "perturbed")]
        seed: u64,
        /// Run only member K (0-based) of the ensemble of this --seed, as one run with every
        /// output of a run (K below --ensemble N when that is given too)
        #[arg(long, value_name = "K")]
        member: Option<usize>,
        /// How the members differ: disc_<R>nm (initial journal offsets uniform over a disc,
        /// the default), axis_<R>nm (along the journal body's x axis), velocity_<V>um_s (the
        /// journal centred, its initial velocity perturbed) or tolerance_<S> (the journal
        /// centred, the tolerances jittered by a factor in [1 − S, 1 + S]): the protocols of
        /// the perturbation study by their names there
        #[arg(long, value_name = "PROTOCOL", default_value_t = Perturbation::default(),
              value_parser = parse_perturbation, requires = "perturbed")]
        perturbation: Perturbation,
        /// Save the run's whole state to <out>/checkpoint.json every K rotations (removed when
        /// the run completes)
        #[arg(long, value_name = "K", conflicts_with = "perturbed")]
        checkpoint_every: Option<u32>,
        /// Continue the run saved in <out>/checkpoint.json, bit for bit as if it had never
        /// stopped; with --ensemble, the ensemble journaled in <out>/ensemble_journal, running
        /// only the members it does not hold
        #[arg(long, conflicts_with = "member")]
        resume: bool,
        /// Remove <out>/checkpoint.json, the saved state of an unfinished run (with
        /// --ensemble, <out>/ensemble_journal, an unfinished ensemble's finished members), and
        /// start over (without it or --resume, a run into a folder holding one is refused)
        #[arg(long, conflicts_with = "resume")]
        discard_checkpoint: bool,
    },
    /// Validate a scene, print what it describes and draw its assembled pose.
    ///
    /// The picture is <out>/mechanism_<scene stem>.png; it names the branch the loop closed on.
    Check {
        scene: PathBuf,
        /// Output directory [default: out/<scene stem>/check]
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Draw rotations from the assembled start as a looping GIF, the journal's orbit magnified.
    ///
    /// The GIF is <out>/mechanism_<scene stem>.gif: no settling, no wear snapshots; an inset
    /// magnifies the first clearance joint's journal centre in its clearance circle.
    Animate {
        scene: PathBuf,
        /// Output directory [default: out/<scene stem>/animate]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Rotations to simulate and draw
        #[arg(long, value_name = "N", default_value_t = 1)]
        rotations: u32,
        /// Frames of the GIF, evenly spaced over the rotations (20 per second)
        #[arg(long, value_name = "N", default_value_t = 72)]
        frames: usize,
    },
    /// Run the cartesian product of --set values in parallel, one summary CSV row per case.
    #[command(
        after_help = "KEY is a dotted path into the scene file, array elements by 0-based \
        number (clearance.0.clearance_mm, run.method); values are TOML (0.02, [0.0, -9.81], \
        \"rk4\" or rk4). Case k (last --set varying fastest) belongs to shard (k mod N) + 1."
    )]
    Sweep {
        scene: PathBuf,
        /// KEY=V1,V2,.. (repeatable)
        #[arg(long = "set", value_name = "KEY=VALUES")]
        sets: Vec<String>,
        /// Run only shard I of N (1-based), for job arrays
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Summary CSV [default: out/<scene stem>/sweep.csv, or sweep-I-of-N.csv]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Keep the finished cases of an interrupted sweep in --out and run only the others
        #[arg(long)]
        resume: bool,
        /// Run every case as an ensemble of N members (see `run --ensemble`): per quantity its
        /// members, mean, sd and states instead of one run's values
        #[arg(long, value_name = "N")]
        ensemble: Option<usize>,
        /// Seed of the ensembles' initial offsets
        #[arg(long, default_value_t = DEFAULT_SEED, requires = "ensemble")]
        seed: u64,
    },
    /// Join the shard files of one sweep, sorted by case.
    #[command(
        after_help = "Refuses a shard of another sweep (fingerprint), a shard given twice and, \
        unless --allow-partial, a missing or unfinished shard."
    )]
    SweepMerge {
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        #[arg(long)]
        out: PathBuf,
        /// Merge even if shards are missing or unfinished (the result can be --resume'd)
        #[arg(long)]
        allow_partial: bool,
    },
    /// Predict the wear after many rotations by cycle-jump extrapolation.
    Longlife {
        scene: PathBuf,
        /// Rotations to predict (1e6 is accepted)
        #[arg(long, default_value = "1e6")]
        rotations: f64,
        /// Override k/H (1/Pa) of every worn joint
        #[arg(long)]
        k_over_h: Option<f64>,
        /// Largest depth change per extrapolated block, as a fraction of the clearance
        #[arg(long, default_value_t = 0.02)]
        max_change: f64,
        /// Rotations simulated before the first block, at most 10000
        #[arg(long, default_value_t = 3)]
        settle: u32,
        /// Stop when the deepest wear of a joint reaches this depth (mm), and report the
        /// rotations it took [default: each joint's radial clearance: the clearance doubled].
        /// A prediction also stops, short of its target, where a worn bearing grows too steep
        /// for the paper's gap (|dh/dθ| / (c + h) > 0.3; the standard scene at 2-3 µm)
        #[arg(long, value_name = "DEPTH_MM")]
        until: Option<f64>,
        /// Predict member K (0-based) of the ensemble of this --seed: the scene's mechanism
        /// with the journal pin shifted by the member's offset of at most 10 nm (the default
        /// protocol), from the assembled start; predictions of several members give the
        /// spread of one prediction
        #[arg(long, value_name = "K")]
        member: Option<usize>,
        /// Seed of the members' offsets
        #[arg(long, default_value_t = DEFAULT_SEED, requires = "member")]
        seed: u64,
        /// Output directory [default: out/<scene stem>/longlife]
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = interrupt::install() {
        eprintln!("warning: {e}; an interrupted run may leave temporary files");
    }
    let result = match cli.command {
        Command::Run {
            scene,
            out,
            sets,
            rotations,
            ensemble,
            seed,
            member: Some(member),
            perturbation,
            discard_checkpoint,
            ..
        } => {
            let of = EnsembleSettings {
                members: ensemble.unwrap_or(MAX_MEMBERS),
                seed,
                perturbation,
            };
            run::run(
                &scene,
                &sets,
                rotations,
                out,
                None,
                run::Saved::from_flags(false, discard_checkpoint),
                Some((of, member)),
            )
        }
        Command::Run {
            scene,
            out,
            sets,
            rotations,
            ensemble: None,
            checkpoint_every,
            resume,
            discard_checkpoint,
            ..
        } => run::run(
            &scene,
            &sets,
            rotations,
            out,
            checkpoint_every,
            run::Saved::from_flags(resume, discard_checkpoint),
            None,
        ),
        Command::Run {
            scene,
            out,
            sets,
            rotations,
            ensemble: Some(members),
            seed,
            perturbation,
            resume,
            discard_checkpoint,
            ..
        } => ensemble::run_ensemble(
            &scene,
            &sets,
            rotations,
            out,
            EnsembleSettings {
                members,
                seed,
                perturbation,
            },
            run::Saved::from_flags(resume, discard_checkpoint),
        ),
        Command::Check { scene, out } => check::check(&scene, out),
        Command::Animate {
            scene,
            out,
            rotations,
            frames,
        } => animate::animate(&scene, out, rotations, frames),
        Command::Sweep {
            scene,
            sets,
            shard,
            out,
            resume,
            ensemble,
            seed,
        } => {
            let ensemble = ensemble.map(|members| EnsembleSettings {
                members,
                seed,
                ..EnsembleSettings::default()
            });
            sweep::sweep(&scene, &sets, shard.as_deref(), out, resume, ensemble)
        }
        Command::SweepMerge {
            inputs,
            out,
            allow_partial,
        } => sweep::sweep_merge(&inputs, &out, allow_partial),
        Command::Longlife {
            scene,
            rotations,
            k_over_h,
            max_change,
            settle,
            out,
            until,
            member,
            seed,
        } => {
            let options = longlife::Options {
                rotations,
                k_over_h,
                max_change,
                settle,
                until_mm: until,
                member: member.map(|m| (m, seed)),
            };
            longlife::longlife(&scene, &options, out)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => f.report(),
    }
}

/// `--perturbation`'s value ([`Perturbation::from_key`]); clap reports a bad one with exit
/// code 2, naming the flag.
fn parse_perturbation(key: &str) -> Result<Perturbation, String> {
    Perturbation::from_key(key).map_err(|e| e.to_string())
}

/// `out/<scene stem>/<kind>` unless given: one default folder per kind of output (`run`,
/// `ensemble`, `member-<K>`, `longlife`, `animate`, `check`), so that no command replaces
/// another's results ([`jointwear::simulation::folder::write_folder`] removes the files of the
/// previous write into a folder, and refuses one holding another command's outputs).
fn out_dir(scene: &Path, kind: &str, out: Option<PathBuf>) -> PathBuf {
    out.unwrap_or_else(|| scene_out(scene).join(kind))
}

/// `out/<scene stem>`: the default folders of a scene's outputs, and its sweep files, are in it.
fn scene_out(scene: &Path) -> PathBuf {
    Path::new("out").join(scene_stem(scene))
}

/// The scene file's name without its extension (`standard` for `data/scenes/standard.toml`).
fn scene_stem(scene: &Path) -> String {
    scene
        .file_stem()
        .unwrap_or(scene.as_os_str())
        .to_string_lossy()
        .into_owned()
}

/// [`out_dir`], refused (exit 2, as `--out`) if it cannot hold a run's outputs.
fn checked_out_dir(scene: &Path, kind: &str, out: Option<PathBuf>) -> CliResult<PathBuf> {
    let dir = out_dir(scene, kind, out);
    jointwear::io::output::check_output_dir("--out", &dir).map_err(|e| Failure::from(scene, e))?;
    Ok(dir)
}

/// A command's claims of its outputs, released when it drops: of the paper's outputs, if it
/// writes among them, and of its own folder or file ([`claim_output`]).
pub type Claims = (Option<Lock>, Lock);

/// Claims the output folder `dir` of the scene at `scene` for this process until the claims
/// drop: refused (exit 2, naming the holder) while another process writes into it, or into
/// the paper's outputs if `dir` is among them.
fn claim_out(scene: &Path, dir: &Path) -> CliResult<Claims> {
    claim_with(scene, dir, lock::claim_folder)
}

/// Claims the output file `out` (a sweep's) for this process until the claims drop, as
/// [`claim_out`] claims a folder; a refusal is said of `input` (the scene, or `out` itself).
fn claim_out_file(input: &Path, out: &Path) -> CliResult<Claims> {
    claim_with(input, out, lock::claim_file)
}

/// [`claim_output`] of `out` by `claim` ([`lock::claim_folder`] or [`lock::claim_file`]),
/// each claim's notes printed; a refusal is said of `input`.
fn claim_with(
    input: &Path,
    out: &Path,
    claim: fn(&str, &Path) -> jointwear::Result<Lock>,
) -> CliResult<Claims> {
    claim_output("--out", out, claim, &mut print_notes).map_err(|e| Failure::from(input, e))
}

/// [`claim_out`] for `command`, which writes an output folder with a manifest (`run`, `run
/// --member`, `run --ensemble`, `longlife`): its manifest is checked too, before any work, so
/// that one this program cannot trust, or one of another command's outputs, is refused at
/// once (exit 2), not after the run ([`folder::check_manifest`]). So is a folder holding the
/// checkpoint of an unfinished run, for every command but `run` (which continues or discards
/// it as told, [`run::Saved`]): its outputs beside the checkpoint would make the folder
/// another command's, into which `run --resume` is then refused.
fn claim_outputs(scene: &Path, dir: &Path, command: FolderCommand) -> CliResult<Claims> {
    let claim = claim_out(scene, dir)?;
    folder::check_manifest("--out", dir, command, folder::OUT_REMEDY)
        .map_err(|e| Failure::from(scene, e))?;
    if !matches!(command, FolderCommand::Run | FolderCommand::Member) {
        let how = "continue that run with `jointwear run ... --resume`, or start it over with \
                   `jointwear run ... --discard-checkpoint`";
        refuse_checkpoint("--out", dir, how).map_err(|e| Failure::input(scene, e))?;
    }
    Ok(claim)
}

/// A scene as `run` simulates it: the file with its `--set` values and `--rotations`.
pub struct Loaded {
    /// The built scene.
    pub scene: Scene,
    /// The scene file and its changes: the `--set` values, then `--rotations` (and the
    /// snapshots and recorded rotations it cut); its fingerprint is a checkpoint's.
    pub variant: Variant,
    /// The output folder, checked ([`checked_out_dir`]).
    pub dir: PathBuf,
}

/// The scene file at `path` with `sets` (`KEY=VALUE`, one value each, each key once) assigned
/// by dotted key, then `rotations` as `run.rotations`, which cuts the wear snapshots past it
/// and the recorded rotations to it unless they were set ([`Variant::set`]). Validated as a
/// scene file is, and every error is bad input (exit code 2): a bad key or value names the
/// key, the value, the valid range and the `--set` it came from. The changes made on the
/// user's behalf are printed ([`run::print_cuts`]). `out` (default: the folder of `kind`,
/// [`out_dir`]) is checked as the output folder.
fn load_variant(
    path: &Path,
    sets: &[String],
    rotations: Option<u32>,
    (kind, out): (&str, Option<PathBuf>),
) -> CliResult<Loaded> {
    let input = |e| Failure::input(path, e);
    let mut assignments = Vec::new();
    for arg in sets {
        let a = Assignment::parse(arg).map_err(input)?;
        if a.values.len() != 1 {
            return Err(input(Error::invalid(
                "--set",
                arg,
                "KEY=VALUE with one value (`sweep` takes a list)",
            )));
        }
        assignments.push(a);
    }
    let mut variant = Variant::read(path).map_err(input)?;
    // A key given twice is refused as `sweep` refuses it: the one given last would silently
    // win. Only checked: each key is asked as written, which the fingerprint (a checkpoint's)
    // and the recorded command line hold as a run before this check and Python's `set` do.
    canonical_sets(variant.loaded(), assignments.clone()).map_err(input)?;
    // The arguments that changed the file, for messages.
    let from: Vec<String> = (sets.iter().map(|s| format!("--set {s}")))
        .chain(rotations.map(|n| format!("--rotations {n}")))
        .collect();
    let from_set = |e: Error| {
        if from.is_empty() {
            e
        } else {
            e.in_context(&format!("with {}", from.join(", ")))
        }
    };
    for a in &assignments {
        let value = parse_value(&a.values[0]);
        if let Some(note) = reversal_note(variant.loaded(), &a.key, &value) {
            eprintln!("note: {note} (--set {}={})", a.key, a.values[0]);
        }
        (variant.set(&a.key, value, &a.values[0], false)).map_err(|e| input(from_set(e)))?;
    }
    let mut cuts = Vec::new();
    if let Some(n) = rotations {
        cuts = (variant.set("run.rotations", n.into(), &n.to_string(), true))
            .map_err(|e| input(from_set(e)))?;
    }
    let scene = variant.build().map_err(|e| input(from_set(e)))?;
    if let Some(n) = rotations {
        run::print_cuts(&cuts, n);
    }
    Ok(Loaded {
        scene,
        variant,
        dir: checked_out_dir(path, kind, out)?,
    })
}
