//! Records the model's ensemble statistics into `data/golden/ensemble.toml`, which the golden
//! tests hold the model to. Run it only for a reason (a physics fix, a new statistic), given
//! as the argument; the reason is written into the file and belongs in the commit message and
//! in `paper.md`. Never to make a chaotic number pass: the bounds already allow for chaos.
use jointwear::error::exit_on_error;
use jointwear::io::output::write_atomic;
use jointwear::io::paper_claim::{output_root, output_root_moved, OUTPUT_ROOT_VAR};
use jointwear::io::progress::progress_bar;
use jointwear::paper::cases::Runs;
use jointwear::paper::golden::{
    ensemble_path, measure, EnsembleGolden, Golden, Recorded, GOLDEN_MEMBERS, GOLDEN_NEEDS,
};
use jointwear::simulation::ensemble::EnsembleSettings;
use jointwear::Error;

fn main() {
    let reason = jointwear::paper::program::reason(
        "golden_record",
        "Records the model's ensemble statistics into data/golden/ensemble.toml, with REASON, \
         why they are recorded (a physics fix, a new statistic)",
    );
    if output_root_moved() {
        // (Its file is an input of the checkout's tests, not an output to move.)
        exit_on_error::<()>(Err(Error::invalid(
            OUTPUT_ROOT_VAR,
            output_root().display(),
            "unset: golden_record records data/golden/ensemble.toml of the checkout it was \
             built from, which the golden tests read",
        )));
    }
    let _claim = jointwear::paper::program::claim_outputs();
    let golden = exit_on_error(Golden::load());
    let ensemble = EnsembleSettings {
        members: GOLDEN_MEMBERS,
        ..EnsembleSettings::default()
    };
    let bar = progress_bar(0, "ensemble members");
    let runs = exit_on_error(Runs::compute(&GOLDEN_NEEDS, ensemble, &|_| {}, &bar));
    bar.finish_and_clear();
    let quantity = exit_on_error(measure(&runs, &golden))
        .into_iter()
        .map(|m| Recorded {
            name: m.quantity.name(),
            n: m.distribution.n,
            mean: m.distribution.mean,
            sd: m.distribution.sd,
            floor: m.floor,
        })
        .collect();
    let file = EnsembleGolden {
        members: ensemble.members,
        seed: ensemble.seed,
        reason,
        quantity,
    };
    let path = ensemble_path();
    let body = exit_on_error(toml::to_string(&file).map_err(|e| Error::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    }));
    let text = format!(
        "# Recorded ensemble statistics of the model, written by `cargo run --release --bin \
         golden_record -- REASON`;\n# do not edit by hand. tests/golden.rs holds the model to them \
         (src/paper/golden.rs gives the bound).\n{body}"
    );
    exit_on_error(write_atomic(&path, |tmp| {
        std::fs::write(tmp, &text).map_err(|source| Error::Io {
            path: tmp.to_path_buf(),
            source,
        })
    }));
    println!(
        "wrote {} ({} quantities, {} members, seed {})",
        path.display(),
        file.quantity.len(),
        file.members,
        file.seed
    );
}
