//! `jointwear sweep` and `jointwear sweep-merge`: the command-line side of parameter sweeps
//! (arguments, default file names, progress, messages); the sweeps themselves and their files
//! are [`jointwear::sweep`].

use crate::failure::{CliResult, Failure};
use crate::scene_out;
use jointwear::io::interrupt;
use jointwear::io::output::check_output_file;
use jointwear::io::progress::progress_bar;
use jointwear::simulation::ensemble::EnsembleSettings;
use jointwear::sweep::file::{merge, JournaledSweep};
use jointwear::sweep::{Assignment, Shard, Sweep};
use jointwear::Error;
use std::path::{Path, PathBuf};

/// `sweep-merge`: joins the shard files `inputs` of one sweep into `out`.
pub fn sweep_merge(inputs: &[PathBuf], out: &Path, allow_partial: bool) -> CliResult<()> {
    check_output_file("--out", out).map_err(|e| Failure::from(out, e))?;
    let _claim = crate::claim_out_file(out, out)?;
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

/// `sweep`: runs the cases of the scene at `path` varied by `sets` (of `shard`, resumed from
/// `out` if `resume`, each as an ensemble if given), appending each row to `out` as it finishes.
pub fn sweep(
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
        scene_out(path).join(name)
    });
    let mut sweep = Sweep::new(path, sets, shard).map_err(|e| Failure::input(path, e))?;
    for note in &sweep.notes {
        eprintln!("note: {note}");
    }
    if let Some(e) = ensemble {
        crate::ensemble::checked(path, &e)?;
        sweep = sweep
            .with_ensemble(e)
            .map_err(|e| Failure::input(path, e))?;
    }
    check_output_file("--out", &out).map_err(bad)?;
    let _claim = crate::claim_out_file(path, &out)?;
    let replaced = !resume && out.exists();
    let journaled = JournaledSweep::open(&mut sweep, &out, resume).map_err(bad)?;
    if replaced {
        eprintln!("{} exists: replacing it", out.display());
    }
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
    let result = journaled.run(&bar);
    bar.finish_and_clear();
    let (rows, failed) = result.map_err(bad)?;
    println!("wrote {} ({rows} cases)", out.display());
    match failed.first() {
        None => Ok(()),
        Some(first) => Err(Failure::running(format!(
            "{}: {} of {rows} cases failed (see the error column), first: case {first}",
            path.display(),
            failed.len(),
        ))),
    }
}
