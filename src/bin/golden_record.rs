//! Records the model's ensemble statistics into `data/golden/ensemble.toml`, which the golden
//! tests hold the model to. Run it only for a reason (a physics fix, a new statistic), given
//! as the argument; the reason is written into the file and belongs in the commit message and
//! in `paper.md`. Never to make a chaotic number pass: the bounds already allow for chaos.
use jointwear::ensemble::EnsembleSettings;
use jointwear::figures::exit_on_error;
use jointwear::golden::{
    ensemble_path, measure, EnsembleGolden, Golden, Recorded, GOLDEN_MEMBERS, GOLDEN_NEEDS,
};
use jointwear::output::write_atomic;
use jointwear::runs::Runs;
use jointwear::Error;

fn main() {
    let Some(reason) = std::env::args().nth(1) else {
        eprintln!("usage: golden_record \"REASON\"  (why the statistics are recorded)");
        std::process::exit(2);
    };
    let golden = exit_on_error(Golden::load());
    let ensemble = EnsembleSettings {
        members: GOLDEN_MEMBERS,
        ..EnsembleSettings::default()
    };
    let runs = exit_on_error(Runs::compute(&GOLDEN_NEEDS, ensemble, &|_| {}, |_, _| {}));
    let quantity = exit_on_error(measure(&runs, &golden))
        .into_iter()
        .map(|(name, d, floor)| Recorded {
            name,
            n: d.n,
            mean: d.mean,
            sd: d.sd,
            floor,
        })
        .collect();
    let file = EnsembleGolden {
        members: ensemble.members,
        seed: ensemble.seed,
        reason,
        quantity,
    };
    let body = toml::to_string(&file).unwrap_or_else(|e| {
        eprintln!("error: the statistics do not serialise: {e}");
        std::process::exit(1)
    });
    let text = format!(
        "# Recorded ensemble statistics of the model, written by `cargo run --release --bin \
         golden_record -- REASON`;\n# do not edit by hand. tests/golden.rs holds the model to them \
         (src/golden.rs gives the bound).\n{body}"
    );
    let path = ensemble_path();
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
