//! How ensemble statistics settle with the number of members, and the default size it picks:
//! `data/ensemble_convergence.csv`, `figures/ensemble_convergence.png`. See
//! `jointwear::paper::convergence`.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::convergence::convergence_study;
use jointwear::simulation::ensemble::DEFAULT_MEMBERS;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "convergence",
        "How ensemble statistics settle with the number of members: writes data/ensemble_convergence.csv and figures/ensemble_convergence.png",
        &[],
    );
    let bar = progress_bar(0, "members");
    let study = exit_on_error(convergence_study(&bar));
    bar.finish_and_clear();
    println!(
        "{}",
        jointwear::paper::program::in_root(
            "wrote data/ensemble_convergence.csv and figures/ensemble_convergence.png"
        )
    );
    for (n, rms, width) in &study.profile {
        println!(
            "{n:3} members: mean wear profile {:.2} % RMS from the full ensemble's, band width {:.1} %",
            100.0 * rms,
            100.0 * width
        );
    }
    match study.chosen {
        Some(n) => println!("the rule picks {n} members (library default: {DEFAULT_MEMBERS})"),
        None => println!("no size meets the rule (library default: {DEFAULT_MEMBERS})"),
    }
}
