//! The accuracy-dependence study (see `jointwear::paper::studies::accuracy`): writes
//! `data/accuracy_dependence.csv` and prints, per paper result, which integrations reproduce it.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "accuracy",
        "The accuracy-dependence study: writes data/accuracy_dependence.csv and prints, per paper result, which integrations reproduce it",
        &[],
    );
    let bar = progress_bar(0, "accuracy runs");
    let a = exit_on_error(jointwear::paper::studies::accuracy_dependence(&bar));
    bar.finish_and_clear();
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/accuracy_dependence.csv")
    );
    for f in &a.findings {
        println!(
            "{:34} paper {:28} holds [converged, ode45, rk4 1e-5, rk4 1e-4] = {:?}{}",
            f.result,
            f.paper,
            f.holds,
            if f.only_under_resolved() {
                "  ONLY UNDER-RESOLVED"
            } else {
                ""
            }
        );
    }
}
