//! How much Table 3's ensembles and the standard case's wear depend on how members are
//! perturbed (see `jointwear::paper::perturbation`): writes `data/perturbation_sensitivity.csv`.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::golden::Golden;
use jointwear::paper::perturbation::perturbation_study;
use jointwear::paper::report::claim_tallies;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "perturbation",
        "How much the ensembles depend on how members are perturbed: writes data/perturbation_sensitivity.csv",
        &[],
    );
    let bar = progress_bar(0, "ensemble members");
    let golden = exit_on_error(Golden::load());
    let rows = exit_on_error(perturbation_study(
        &|runs| claim_tallies(runs, &golden),
        &bar,
    ));
    bar.finish_and_clear();
    for r in rows.iter().filter(|r| r.differs()) {
        println!(
            "{:>16} {:>16} {:>32} {:>6}: {:.4e} (p = {:.1e}, Holm {:.1e}, {})",
            r.protocol, r.case, r.quantity, r.state, r.mean, r.p, r.p_holm, r.test
        );
    }
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/perturbation_sensitivity.csv")
    );
}
