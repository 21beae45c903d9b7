//! `jointwear`: simulate, check, sweep and predict long-life wear of any scene file.
//!
//! Exit codes: 0 success, 2 bad input (scene value, TOML, command-line syntax), 1 a failure
//! while running (integration, writing outputs).

use clap::{Parser, Subcommand};
use jointwear::checkpoint::{read_checkpoint, write_checkpoint, CHECKPOINT_FILE};
use jointwear::ensemble::{self, member_offsets, EnsembleSettings, DEFAULT_SEED};
use jointwear::figures::sector_angles_deg;
use jointwear::interrupt;
use jointwear::longlife::{predict, LongLife, LongLifeSettings};
use jointwear::output::{
    check_output_dir, check_output_file, progress_bar, write_csv, write_outputs, write_rows,
};
use jointwear::plot::{render, Axes, Series, Shade, Style};
use jointwear::scene::{Scene, SceneFile};
use jointwear::simulation::{RunOutput, Simulation};
use jointwear::statistics::{Distribution, QUANTILES};
use jointwear::sweep::{
    header, joint_statistics, summarize, Assignment, CaseResult, JointStatistics, JointSummary,
    Outcome, Shard, Sweep,
};
use jointwear::sweep_file::{fingerprint, merge, JournaledSweep};
use jointwear::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const EXAMPLES: &str = "\
Examples:
  jointwear check data/scenes/fourbar.toml
  jointwear run data/scenes/standard.toml --out out/standard
  jointwear run data/scenes/standard.toml --ensemble 16 --seed 1
  jointwear sweep data/scenes/standard.toml \\
      --set clearance.0.clearance_mm=0.02,0.1,0.5 --set driver.speed_rpm=600,2000 --out sweep.csv
  jointwear sweep data/scenes/standard.toml --set driver.speed_rpm=500,1000,1500,2000 \\
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
    #[command(
        after_help = "Writes timeseries.csv (recorded rotations), wear_<joint>.csv (final \
        profile), trajectory.png, normal_force.png and wear.png. With --ensemble N: \
        ensemble_members.csv (one row per member), ensemble_summary.csv (mean, sd, min, \
        quantiles and max of every scalar result), ensemble_wear_<joint>.csv (the per-sector \
        band of the final wear profiles) and wear.png (mean profile, 5-95 % band shaded)."
    )]
    Run {
        scene: PathBuf,
        /// Output directory [default: out/<scene stem>]
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run N members, each from an initial journal offset of at most 10 nm in a seeded
        /// random direction, and report statistics over them instead of one trajectory
        #[arg(long, value_name = "N")]
        ensemble: Option<usize>,
        /// Seed of the ensemble's initial offsets
        #[arg(long, default_value_t = DEFAULT_SEED, requires = "ensemble")]
        seed: u64,
        /// Save the run's whole state to <out>/checkpoint.json every K rotations (removed when
        /// the run completes)
        #[arg(long, value_name = "K", conflicts_with = "ensemble")]
        checkpoint_every: Option<u32>,
        /// Continue the run saved in <out>/checkpoint.json, bit for bit as if it had never
        /// stopped
        #[arg(long, conflicts_with = "ensemble")]
        resume: bool,
    },
    /// Validate a scene and print what it describes.
    Check { scene: PathBuf },
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
        /// Run every case as an ensemble of N members (see `run --ensemble`): mean and sd
        /// columns of every quantity instead of one run's values
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
        /// Rotations simulated before the first block
        #[arg(long, default_value_t = 3)]
        settle: u32,
        /// Stop when the deepest wear of a joint reaches this depth (mm), and report the
        /// rotations it took [default: each joint's radial clearance: the clearance doubled]
        #[arg(long, value_name = "DEPTH_MM")]
        until: Option<f64>,
        /// Output directory [default: out/<scene stem>]
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// A failure to report: the message and the exit code.
struct Failure {
    code: u8,
    message: String,
}

impl Failure {
    /// A library error, prefixed with the file it concerns unless the message names it.
    fn from(path: &Path, e: Error) -> Failure {
        let code = match e {
            Error::Invalid { .. } | Error::Parse { .. } => 2,
            _ => 1,
        };
        let message = match e {
            Error::Invalid { .. } | Error::Integration { .. } => {
                format!("{}: {e}", path.display())
            }
            _ => e.to_string(),
        };
        Failure { code, message }
    }
}

impl Failure {
    /// Like [`Failure::from`] for an error while reading the command's input (a scene): a
    /// file that cannot be read is bad input too (exit code 2).
    fn input(path: &Path, e: Error) -> Failure {
        let unreadable = matches!(e, Error::Io { .. });
        let mut f = Failure::from(path, e);
        if unreadable {
            f.code = 2;
        }
        f
    }
}

type CliResult<T> = std::result::Result<T, Failure>;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = interrupt::install() {
        eprintln!("warning: {e}; an interrupted run may leave temporary files");
    }
    let result = match cli.command {
        Command::Run {
            scene,
            out,
            ensemble: None,
            checkpoint_every,
            resume,
            ..
        } => run(&scene, out, checkpoint_every, resume),
        Command::Run {
            scene,
            out,
            ensemble: Some(members),
            seed,
            ..
        } => run_ensemble(&scene, out, EnsembleSettings { members, seed }),
        Command::Check { scene } => check(&scene),
        Command::Sweep {
            scene,
            sets,
            shard,
            out,
            resume,
            ensemble,
            seed,
        } => {
            let ensemble = ensemble.map(|members| EnsembleSettings { members, seed });
            sweep(&scene, &sets, shard.as_deref(), out, resume, ensemble)
        }
        Command::SweepMerge {
            inputs,
            out,
            allow_partial,
        } => sweep_merge(&inputs, &out, allow_partial),
        Command::Longlife {
            scene,
            rotations,
            k_over_h,
            max_change,
            settle,
            out,
            until,
        } => longlife(&scene, rotations, k_over_h, max_change, settle, until, out),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

fn sweep_merge(inputs: &[PathBuf], out: &Path, allow_partial: bool) -> CliResult<()> {
    check_output_file("--out", out).map_err(|e| Failure::from(out, e))?;
    // Reading the inputs is reading input: an unreadable one is bad input.
    let rows = merge(inputs, out, allow_partial).map_err(|e| {
        if matches!(&e, Error::Io { path, .. } if inputs.contains(path)) {
            Failure::input(out, e)
        } else {
            Failure::from(out, e)
        }
    })?;
    println!("wrote {} ({rows} cases)", out.display());
    Ok(())
}

/// `out/<scene stem>` unless given.
fn out_dir(scene: &Path, out: Option<PathBuf>) -> PathBuf {
    out.unwrap_or_else(|| Path::new("out").join(scene.file_stem().unwrap_or(scene.as_os_str())))
}

/// A joint name usable in a file name.
fn file_part(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn load(path: &Path) -> CliResult<Scene> {
    Scene::load(path).map_err(|e| Failure::input(path, e))
}

fn run(
    path: &Path,
    out: Option<PathBuf>,
    checkpoint_every: Option<u32>,
    resume: bool,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    let scene = load(path)?;
    let dir = out_dir(path, out);
    check_output_dir("--out", &dir).map_err(bad)?;
    if checkpoint_every == Some(0) {
        return Err(Failure::input(
            path,
            Error::invalid("--checkpoint-every", 0, "at least 1 rotation"),
        ));
    }
    let saved = dir.join(CHECKPOINT_FILE);
    let fingerprint = scene_fingerprint(path)?;
    let mut sim = if resume {
        let checkpoint = read_checkpoint(&saved, &fingerprint).map_err(|e| match e {
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
        Simulation::resume(&scene, checkpoint).map_err(|e| Failure::input(path, e))?
    } else {
        Simulation::start(&scene).map_err(bad)?
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
            bar.set_length(total.unwrap_or(done + scene.run.rotations) as u64);
            bar.set_position(done as u64);
            if checkpoint_every.is_some_and(|k| done % k == 0) {
                write_checkpoint(&saved, &fingerprint, sim.checkpoint())?;
            }
        }
        Ok(())
    })();
    bar.finish_and_clear();
    result.map_err(bad)?;
    let out = sim.finish();
    let title = format!("jointwear run {}", path.display());
    write_outputs(&dir, &title, || write_run(&scene, &out, &dir))
        .map_err(|e| Failure::from(path, e))?;
    // A completed run needs no checkpoint; a failed one keeps its last.
    if saved.exists() {
        std::fs::remove_file(&saved).map_err(|source| {
            bad(Error::Io {
                path: saved.clone(),
                source,
            })
        })?;
    }
    print_summary(&scene, &out);
    println!("outputs in {}", dir.display());
    Ok(())
}

/// The fingerprint of a scene file as it is now (its resolved document).
fn scene_fingerprint(path: &Path) -> CliResult<String> {
    let doc = SceneFile::read_document(path).map_err(|e| Failure::input(path, e))?;
    Ok(fingerprint(&doc, &[]))
}

/// `run --ensemble`: members in parallel, their statistics as CSVs, a band plot and a summary.
fn run_ensemble(path: &Path, out: Option<PathBuf>, settings: EnsembleSettings) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    settings.validate().map_err(|e| Failure::input(path, e))?;
    let scene = load(path)?;
    let dir = out_dir(path, out);
    check_output_dir("--out", &dir).map_err(bad)?;
    let clock = std::time::Instant::now();
    let bar = progress_bar(settings.members as u64, "members");
    let members = ensemble::run(
        &scene,
        &settings,
        |_, o| ((summarize(&scene, &o), o.final_wear), o.wall_time),
        || bar.inc(1),
    );
    bar.finish_and_clear();
    let (members, walls): (Vec<Member>, Vec<f64>) = members.map_err(bad)?.into_iter().unzip();
    let wall = clock.elapsed().as_secs_f64();
    let title = format!(
        "jointwear run {} --ensemble {}",
        path.display(),
        settings.members
    );
    let stats = write_outputs(&dir, &title, || {
        write_ensemble(&scene, &settings, &members, &walls, &dir)
    })
    .map_err(bad)?;
    println!("{}", scene.title);
    println!(
        "  {} members (seed {}) of {} rotations in {wall:.2} s wall time",
        settings.members, settings.seed, scene.run.rotations
    );
    for j in &stats {
        println!("  joint {} (mean ± sd, [5 %, 95 %]):", j.name);
        for (name, d) in &j.scalars {
            if name == &"continuous_contact" {
                let k = (d.mean * d.n as f64).round();
                println!("    continuous contact in {k} of {} members", d.n);
            } else if d.n > 0 {
                println!(
                    "    {name:22} {:.6e} ± {:.2e}  [{:.6e}, {:.6e}]",
                    d.mean, d.sd, d.quantiles[0], d.quantiles[4]
                );
            }
        }
    }
    println!("outputs in {}", dir.display());
    Ok(())
}

/// One member of `run --ensemble`: its joint summaries and final wear profiles.
type Member = (Vec<JointSummary>, Vec<Vec<f64>>);

/// The ensemble's CSVs and band plot; returns the statistics it wrote.
fn write_ensemble(
    scene: &Scene,
    settings: &EnsembleSettings,
    members: &[Member],
    walls: &[f64],
    dir: &Path,
) -> jointwear::Result<Vec<JointStatistics>> {
    let m = &scene.mechanism;
    let joints: Vec<String> = m.clearance_joints.iter().map(|c| c.name.clone()).collect();
    // One row per member: its offsets d (journal body frame), then a sweep row's joint columns.
    let mut head = vec!["member".to_string()];
    for j in &joints {
        head.extend([
            format!("{j}.offset_body_x_m"),
            format!("{j}.offset_body_y_m"),
        ]);
    }
    head.extend(header(&[], &joints).into_iter().skip(1));
    let rows = members
        .iter()
        .zip(walls)
        .enumerate()
        .map(|(i, ((summary, _), secs))| {
            let mut row = vec![i.to_string()];
            for d in member_offsets(settings.seed, i, joints.len()) {
                row.extend([format!("{:e}", d.x), format!("{:e}", d.y)]);
            }
            let record = CaseResult {
                case: i,
                values: Vec::new(),
                outcome: Ok((Outcome::Run(summary.clone()), *secs)),
            }
            .record(header(&[], &joints).len() - 3);
            row.extend(record.into_iter().skip(1));
            row
        });
    write_rows(&dir.join("ensemble_members.csv"), &head, rows)?;
    let stats = joint_statistics(scene, members);
    let q = QUANTILES.map(|p| format!("q{:02.0}", 100.0 * p));
    let mut head = vec!["joint", "quantity", "n", "mean", "sd", "min"];
    head.extend(q.iter().map(String::as_str));
    head.push("max");
    let numbers = |d: &Distribution| -> Vec<String> {
        [d.mean, d.sd, d.min]
            .iter()
            .chain(&d.quantiles)
            .chain([&d.max])
            .map(|x| format!("{x:e}"))
            .collect()
    };
    let mut rows = Vec::new();
    for j in &stats {
        for (name, d) in &j.scalars {
            let mut row = vec![j.name.clone(), name.to_string(), d.n.to_string()];
            row.extend(numbers(d));
            rows.push(row);
        }
    }
    write_rows(&dir.join("ensemble_summary.csv"), &head, rows)?;
    let mut series = Vec::new();
    for j in &stats {
        let Some(band) = &j.wear else { continue };
        let angles = sector_angles_deg(band.sectors.len());
        let mut head = vec!["angle_deg".to_string()];
        head.extend(["mean_m", "sd_m", "min_m"].map(String::from));
        head.extend(q.iter().map(|q| format!("{q}_m")));
        head.push("max_m".into());
        let rows = band.sectors.iter().zip(&angles).map(|(d, a)| {
            let mut row = vec![format!("{a:e}")];
            row.extend(numbers(d));
            row
        });
        let file = format!("ensemble_wear_{}.csv", file_part(&j.name));
        write_rows(&dir.join(file), &head, rows)?;
        let um = |v: Vec<f64>| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
        let (mean, lo, hi) = (um(band.mean()), um(band.quantile(0)), um(band.quantile(4)));
        series.push((j.name.clone(), angles, mean, lo, hi));
    }
    if !series.is_empty() {
        let axes = Axes {
            x_range: Some((0.0, 360.0)),
            shades: series
                .iter()
                .enumerate()
                .map(|(i, (_, _, _, lo, hi))| Shade { series: i, lo, hi })
                .collect(),
            ..Axes::new(
                format!(
                    "Wear after {} rotations: mean of {} members, 5-95 % shaded",
                    scene.run.rotations, settings.members
                ),
                "bearing angle (deg)",
                "wear depth (µm)",
                series
                    .iter()
                    .map(|(n, a, mean, _, _)| Series::new(n, a, mean, Style::Line))
                    .collect(),
            )
        };
        render(&dir.join("wear.png"), &[axes])?;
    }
    Ok(stats)
}

/// Time series, final wear profiles and the default plots of a run.
fn write_run(scene: &Scene, out: &RunOutput, dir: &Path) -> jointwear::Result<()> {
    let m = &scene.mechanism;
    let rec = &out.recording;
    let mut header = vec!["time_s".to_string(), "driver_angle_rad".to_string()];
    let mut columns: Vec<&[f64]> = vec![&rec.time, &rec.driver_angle];
    for (cj, tr) in m.clearance_joints.iter().zip(&rec.joints) {
        let series: [(&str, &[f64]); 8] = [
            ("ex_m", &tr.ex),
            ("ey_m", &tr.ey),
            ("penetration_m", &tr.delta),
            ("normal_force_n", &tr.normal_force),
            ("friction_force_n", &tr.friction_force),
            ("sliding_velocity_m_s", &tr.sliding_velocity),
            ("pressure_pa", &tr.pressure),
            ("wear_rate_m_s", &tr.wear_rate),
        ];
        for (name, data) in series {
            header.push(format!("{}.{name}", cj.name));
            columns.push(data);
        }
    }
    for (body, acc) in m.bodies().iter().zip(&rec.accelerations) {
        for (name, data) in ["ax_m_s2", "ay_m_s2", "alpha_rad_s2"].iter().zip(acc) {
            header.push(format!("{}.{name}", body.name));
            columns.push(data);
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&dir.join("timeseries.csv"), &header, &columns)?;

    let worn: Vec<(usize, Vec<f64>, Vec<f64>)> = m
        .clearance_joints
        .iter()
        .enumerate()
        .filter(|(_, cj)| cj.wear.is_some())
        .map(|(k, _)| {
            let depth = &out.final_wear[k];
            (
                k,
                sector_angles_deg(depth.len()),
                depth.iter().map(|d| d * 1e6).collect(),
            )
        })
        .collect();
    for (k, angles, _) in &worn {
        let name = &m.clearance_joints[*k].name;
        let path = dir.join(format!("wear_{}.csv", file_part(name)));
        write_csv(
            &path,
            &["angle_deg", "depth_m"],
            &[angles, &out.final_wear[*k]],
        )?;
    }
    if !worn.is_empty() {
        let series = worn
            .iter()
            .map(|(k, a, um)| Series::new(&m.clearance_joints[*k].name, a, um, Style::Line))
            .collect();
        let axes = Axes {
            x_range: Some((0.0, 360.0)),
            ..Axes::new(
                format!("Wear after {} rotations", scene.run.rotations),
                "bearing angle (deg)",
                "wear depth (µm)",
                series,
            )
        };
        render(&dir.join("wear.png"), &[axes])?;
    }
    if rec.time.is_empty() {
        return Ok(());
    }
    let um = |v: &[f64]| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
    let orbits: Vec<(Vec<f64>, Vec<f64>)> =
        rec.joints.iter().map(|t| (um(&t.ex), um(&t.ey))).collect();
    let panels: Vec<Axes> = m
        .clearance_joints
        .iter()
        .zip(&orbits)
        .map(|(cj, (x, y))| {
            let c = (cj.r_bearing - cj.r_journal) * 1e6;
            Axes {
                equal_aspect: true,
                circles: vec![(0.0, 0.0, c)],
                ..Axes::new(
                    format!("{}: journal centre (c = {c:.3} µm)", cj.name),
                    "x (µm)",
                    "y (µm)",
                    vec![Series::new("journal centre", x, y, Style::Line)],
                )
            }
        })
        .collect();
    if !panels.is_empty() {
        render(&dir.join("trajectory.png"), &panels)?;
        let series = m
            .clearance_joints
            .iter()
            .zip(&rec.joints)
            .map(|(cj, t)| Series::new(&cj.name, &rec.time, &t.normal_force, Style::Line))
            .collect();
        let axes = Axes::new(
            "Contact normal force",
            "time (s)",
            "normal force (N)",
            series,
        );
        render(&dir.join("normal_force.png"), &[axes])?;
    }
    Ok(())
}

fn print_summary(scene: &Scene, out: &RunOutput) {
    let s = &out.stats;
    println!("{}", scene.title);
    println!(
        "  {} rotations in {:.2} s wall time: {} steps, {} rejected, {} evaluations, {} contact onsets",
        scene.run.rotations, out.wall_time, s.steps, s.rejected, s.evaluations, s.events
    );
    if let Some(e) = out.energy {
        println!("  energy balance residual {:.2e}", e.residual());
    }
    for j in summarize(scene, out) {
        println!("  joint {}:", j.name);
        println!(
            "    max normal force {:.2} N (recorded rotations), max penetration {:.3} µm",
            j.max_normal_force,
            j.max_penetration * 1e6
        );
        if let Some(m) = j.motion {
            println!(
                "    motion: {} ({:.0} % in contact, {:.1} impacts per rotation)",
                m.mode(),
                100.0 * m.contact_fraction,
                m.impacts_per_rotation
            );
        }
        for p in j.peaks.iter().take(3) {
            println!(
                "    wear peak at {:6.1} deg: depth {:.4} µm, width {:.0} deg",
                p.angle_deg,
                p.depth * 1e6,
                p.width_deg
            );
        }
    }
}

fn check(path: &Path) -> CliResult<()> {
    let file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    let scene = file.build().map_err(|e| Failure::from(path, e))?;
    let m = &scene.mechanism;
    println!("{}: {}", path.display(), scene.title);
    println!("bodies:");
    for b in &file.bodies {
        println!(
            "  {:12} mass {} kg, inertia {} kg m², points {}",
            b.name,
            b.mass_kg,
            b.inertia_kg_m2,
            b.points_mm.keys().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    println!("ideal joints:");
    for r in &file.revolute {
        println!("  revolute       {} - {}", r.a, r.b);
    }
    for t in &file.translational {
        println!(
            "  translational  {} along {} at {} deg",
            t.a, t.b, t.axis_deg
        );
    }
    let d = &file.driver;
    println!(
        "driver: {} at {} r/min from {} deg",
        d.body, d.speed_rpm, d.angle_deg
    );
    println!("clearance joints:");
    for c in &file.clearance {
        println!(
            "  {}: journal {} in bearing {}, R = {} mm, c = {} mm, {} on {}",
            c.name,
            c.journal,
            c.bearing,
            c.bearing_radius_mm,
            c.clearance_mm,
            c.journal_material,
            c.bearing_material
        );
        let k = &c.contact;
        println!(
            "    contact {:?}, restitution {}, exponent {}; friction {:?}",
            k.model, k.restitution, k.exponent, c.friction
        );
        match &c.wear {
            Some(w) => println!(
                "    wear: k/H = {:e} 1/Pa, {:?} pressure, L = {} mm, {} sectors",
                w.k_over_h_per_pa, w.pressure, w.length_mm, w.sectors
            ),
            None => println!("    no wear"),
        }
    }
    let r = &file.run;
    println!(
        "run: {} rotations ({} recorded every {} s), {:?}, rtol {:e}, atol {:e}, max step {:e} s",
        r.rotations,
        r.record_rotations,
        r.record_interval_s,
        r.method,
        r.rtol,
        r.atol,
        r.max_step_s
    );
    let dof = m.coordinates() as i64 - m.constraint_count() as i64;
    println!(
        "degrees of freedom: {dof} (2 per clearance joint; {} with the clearance joints ideal)",
        dof - 2 * m.clearance_joints.len() as i64
    );
    print_assembly(path, &scene)
}

/// Turn (deg) between a body's guessed and assembled angle beyond which `check` says the
/// loop may have closed on another branch than the guess meant.
const BRANCH_TURN_DEG: f64 = 30.0;

/// Assembles `scene` at t = 0 as a run does and prints every body's pose, noting bodies
/// assembled far from their guessed angle (another branch of the loop, e.g. elbow down).
fn print_assembly(path: &Path, scene: &Scene) -> CliResult<()> {
    let y = (scene.mechanism.assemble(&scene.guess)).map_err(|e| Failure::from(path, e))?;
    println!("assembled pose at t = 0 (clearance joints centred):");
    for (i, b) in scene.mechanism.bodies().iter().enumerate() {
        let (x, y, angle) = (y[3 * i], y[3 * i + 1], y[3 * i + 2].to_degrees());
        println!(
            "  {:12} x {:10.4} mm, y {:10.4} mm, angle {:9.3} deg",
            b.name,
            x * 1e3,
            y * 1e3,
            angle
        );
        let turn = (angle - scene.guess[3 * i + 2].to_degrees() + 180.0).rem_euclid(360.0) - 180.0;
        if turn.abs() > BRANCH_TURN_DEG {
            println!(
                "    note: {turn:.1} deg from its guessed angle: the loop may have closed on \
                 another branch (elbow up/down) than the guess meant"
            );
        }
    }
    Ok(())
}

fn sweep(
    path: &Path,
    sets: &[String],
    shard: Option<&str>,
    out: Option<PathBuf>,
    resume: bool,
    ensemble: Option<EnsembleSettings>,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    let sets = sets
        .iter()
        .map(|s| Assignment::parse(s))
        .collect::<Result<Vec<_>, _>>()
        .map_err(bad)?;
    let shard = shard
        .map(Shard::parse)
        .transpose()
        .map_err(bad)?
        .unwrap_or(Shard::ALL);
    let out = out.unwrap_or_else(|| {
        let name = if shard == Shard::ALL {
            "sweep.csv".to_string()
        } else {
            format!("sweep-{}-of-{}.csv", shard.index, shard.count)
        };
        out_dir(path, None).join(name)
    });
    let mut sweep = Sweep::new(path, sets, shard).map_err(|e| Failure::input(path, e))?;
    if let Some(e) = ensemble {
        sweep = sweep
            .with_ensemble(e)
            .map_err(|e| Failure::input(path, e))?;
    }
    check_output_file("--out", &out).map_err(bad)?;
    if !resume && out.exists() {
        eprintln!(
            "{} exists: starting over (--resume keeps its finished cases)",
            out.display()
        );
    }
    let journaled = JournaledSweep::open(&mut sweep, &out, resume).map_err(bad)?;
    interrupt::keep(format!(
        "finished cases stay in {} (rerun with --resume to skip them)",
        out.display()
    ));
    let id = journaled.id();
    eprintln!(
        "{} cases in shard {}/{} ({} already finished) on {} threads",
        id.cases,
        id.shard.index,
        id.shard.count,
        journaled.finished(),
        rayon::current_num_threads()
    );
    let bar = progress_bar((id.cases - journaled.finished()) as u64, "cases");
    let result = journaled.run(|| bar.inc(1));
    bar.finish_and_clear();
    let (rows, failed) = result.map_err(bad)?;
    println!("wrote {} ({rows} cases)", out.display());
    match failed.first() {
        None => Ok(()),
        Some(first) => Err(Failure {
            code: 1,
            message: format!(
                "{}: {} of {rows} cases failed (see the error column), first: case {first}",
                path.display(),
                failed.len(),
            ),
        }),
    }
}

fn longlife(
    path: &Path,
    rotations: f64,
    k_over_h: Option<f64>,
    max_change: f64,
    settle: u32,
    until_mm: Option<f64>,
    out: Option<PathBuf>,
) -> CliResult<()> {
    let bad = |e| Failure::from(path, e);
    if !((1.0..=1e12).contains(&rotations) && rotations.fract() == 0.0) {
        return Err(bad(Error::invalid(
            "--rotations",
            rotations,
            "an integer in [1, 1e12]",
        )));
    }
    let mut file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    if let Some(k) = k_over_h {
        for w in file.clearance.iter_mut().filter_map(|c| c.wear.as_mut()) {
            w.k_over_h_per_pa = k;
        }
    }
    let scene = file.build().map_err(bad)?;
    let dir = out_dir(path, out);
    check_output_dir("--out", &dir).map_err(bad)?;
    let target = rotations as u64;
    let settings = LongLifeSettings {
        rotations: target,
        settle_rotations: settle,
        max_change,
        snapshots: (1..5).map(|i| target * i / 5).collect(),
        until: until_mm.map(|d| d * 1e-3),
        ..LongLifeSettings::default()
    };
    let bar = progress_bar(target, "rotations");
    let result = predict(&scene, &settings, |done, _| bar.set_position(done));
    bar.finish_and_clear();
    let life = result.map_err(bad)?;
    let title = format!("jointwear longlife {}", path.display());
    write_outputs(&dir, &title, || write_longlife(&scene, &life, &dir)).map_err(bad)?;
    let last = life.history.last().map_or(0, |s| s.rotations);
    println!(
        "{}: {last} rotations predicted from {} simulated in {:.1} s ({} blocks)",
        scene.title,
        life.simulated,
        life.wall_time,
        life.history.len() - 1
    );
    match life.reached {
        Some((at, k)) => println!(
            "  joint {} reached its wear limit of {:.3} µm after {at} rotations{}",
            scene.mechanism.clearance_joints[k].name,
            life.limits[k] * 1e6,
            if until_mm.is_none() {
                " (clearance doubled)"
            } else {
                ""
            }
        ),
        None => println!("  no joint reached its wear limit within {target} rotations"),
    }
    for (k, cj) in scene.mechanism.clearance_joints.iter().enumerate() {
        let depth = life.history.last().map_or(0.0, |s| s.max_depth(k));
        println!(
            "  joint {}: max wear {:.3} µm ({:.0} % of its limit) after {last} rotations, \
             clearance {:.3} -> {:.3} µm",
            cj.name,
            depth * 1e6,
            100.0 * depth / life.limits[k],
            life.clearances[k] * 1e6,
            (life.clearances[k] + depth) * 1e6
        );
    }
    println!("outputs in {}", dir.display());
    Ok(())
}

/// Profiles at the snapshot counts and clearance growth, as CSVs and figures.
fn write_longlife(scene: &Scene, life: &LongLife, dir: &Path) -> jointwear::Result<()> {
    let m = &scene.mechanism;
    let worn: Vec<usize> = (0..m.clearance_joints.len())
        .filter(|&k| m.clearance_joints[k].wear.is_some())
        .collect();
    let rotations: Vec<f64> = life.history.iter().map(|s| s.rotations as f64).collect();
    let growth: Vec<(Vec<f64>, Vec<f64>)> = worn
        .iter()
        .map(|&k| {
            let depth: Vec<f64> = life.history.iter().map(|s| s.max_depth(k)).collect();
            let clearance = depth.iter().map(|d| d + life.clearances[k]).collect();
            (depth, clearance)
        })
        .collect();
    let mut header = vec!["rotations".to_string()];
    let mut columns: Vec<&[f64]> = vec![&rotations];
    for (&k, (depth, clearance)) in worn.iter().zip(&growth) {
        let name = &m.clearance_joints[k].name;
        header.extend([format!("{name}.max_depth_m"), format!("{name}.clearance_m")]);
        columns.extend([depth.as_slice(), clearance.as_slice()]);
    }
    let header_ref: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&dir.join("longlife_growth.csv"), &header_ref, &columns)?;
    let clearance_um: Vec<Vec<f64>> = growth
        .iter()
        .map(|(_, c)| c.iter().map(|x| x * 1e6).collect())
        .collect();
    let series = worn
        .iter()
        .zip(&clearance_um)
        .map(|(&k, c)| Series::new(&m.clearance_joints[k].name, &rotations, c, Style::Line))
        .collect();
    render(
        &dir.join("longlife_growth.png"),
        &[Axes::new(
            "Clearance growth: c + maximum wear depth",
            "rotations",
            "effective clearance (µm)",
            series,
        )],
    )?;
    let mut panels = Vec::new();
    let profiles: Vec<(Vec<f64>, Vec<Vec<f64>>)> = worn
        .iter()
        .map(|&k| {
            let n = life.snapshots.first().map_or(0, |s| s.depths[k].len());
            let um = life
                .snapshots
                .iter()
                .map(|s| s.depths[k].iter().map(|d| d * 1e6).collect())
                .collect();
            (sector_angles_deg(n), um)
        })
        .collect();
    for (&k, (angles, um)) in worn.iter().zip(&profiles) {
        let name = &m.clearance_joints[k].name;
        let mut header = vec!["angle_deg".to_string()];
        header.extend(
            life.snapshots
                .iter()
                .map(|s| format!("rot{}_m", s.rotations)),
        );
        let metres: Vec<&[f64]> = life
            .snapshots
            .iter()
            .map(|s| s.depths[k].as_slice())
            .collect();
        let mut columns: Vec<&[f64]> = vec![angles];
        columns.extend(metres);
        let header_ref: Vec<&str> = header.iter().map(String::as_str).collect();
        let path = dir.join(format!("longlife_profiles_{}.csv", file_part(name)));
        write_csv(&path, &header_ref, &columns)?;
        let series = life
            .snapshots
            .iter()
            .zip(um)
            .map(|(s, d)| Series::new(format!("{} rotations", s.rotations), angles, d, Style::Line))
            .collect();
        panels.push(Axes {
            x_range: Some((0.0, 360.0)),
            ..Axes::new(
                format!("{name}: bearing wear profile"),
                "bearing angle (deg)",
                "wear depth (µm)",
                series,
            )
        });
    }
    if !panels.is_empty() {
        render(&dir.join("longlife_profiles.png"), &panels)?;
    }
    Ok(())
}
