//! Table 3's ensembles at looser tolerances against the scenes' own (see
//! `jointwear::paper::studies::ensemble_tolerance`): writes `data/ensemble_tolerance.csv`.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::studies;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "ensemble_tolerance",
        "Table 3's ensembles at looser tolerances against the scenes' own: writes data/ensemble_tolerance.csv",
        &[],
    );
    let bar = progress_bar(0, "ensemble members");
    let rows = exit_on_error(studies::ensemble_tolerance(&bar));
    bar.finish_and_clear();
    for r in &rows {
        println!(
            "{:>16} rtol {:e}: continuous {:>2}/{}, P-w dominant {:>2}, pw z {:>6.2}, sw z {:>6.2}, {:.0} evaluations/member",
            r.case, r.rtol, r.continuous, r.members, r.pressure_dominated, r.pw.z, r.sw.z, r.evaluations
        );
    }
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/ensemble_tolerance.csv")
    );
}
