//! The stability study (see `jointwear::paper::studies::stability`): writes `data/stability.csv`.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "stability",
        "The stability study on stiff and extreme cases: writes data/stability.csv",
        &[],
    );
    let bar = progress_bar(0, "stability cases");
    let rows = exit_on_error(jointwear::paper::studies::stability(&bar));
    bar.finish_and_clear();
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/stability.csv")
    );
    for r in rows {
        let outcome = r.failure.as_deref().unwrap_or("completed");
        println!(
            "{:16} max pen (whole run) {:10.3e} m  energy residual {:10.3e}  wear/c {:9.3e}  steps {:8} rejected {:6}  {:6.2} s  {outcome}",
            r.case, r.max_penetration_whole_run, r.energy_residual, r.max_wear / r.clearance, r.stats.steps, r.stats.rejected, r.wall_time
        );
    }
}
