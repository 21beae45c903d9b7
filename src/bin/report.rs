//! Rebuilds everything the reproducibility report shows and writes `paper.md`.
//!
//! `report` reruns every figure, Table 3, the accuracy-dependence study and the stability suite
//! (about half a minute); `report --all` also reruns the slow studies (calibration and
//! work-precision, a few minutes) instead of reading their last results from `data/`.
use jointwear::figures::{exit_on_error, CASES};
use jointwear::golden::Golden;
use jointwear::output::progress_bar;
use jointwear::report::{
    performance_section, run_figures, stability_section, work_precision_section, write, FIGURES,
};
use jointwear::{calibration, studies};

fn main() {
    let clock = std::time::Instant::now();
    let golden = exit_on_error(Golden::load());
    if std::env::args().any(|a| a == "--all") {
        let bar = progress_bar(0, "calibration sets");
        exit_on_error(calibration::study(|done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        }));
        bar.finish_and_clear();
        let bar = progress_bar(
            studies::work_precision_settings().len() as u64 + 2,
            "work-precision runs",
        );
        exit_on_error(studies::work_precision(|_| bar.inc(1)));
        bar.finish_and_clear();
    }
    let bar = progress_bar((FIGURES.len() + 1) as u64, "figures and tables");
    let results = exit_on_error(run_figures(|done, _, name, secs| {
        bar.set_position(done as u64);
        bar.set_message(format!("{name} {secs:.1} s"));
    }));
    bar.finish_and_clear();
    // every Table 3 case and the standard wear case, under each integration setting
    let runs = studies::accuracy_settings().len() * (CASES.len() + 1);
    let bar = progress_bar(runs as u64, "accuracy runs");
    exit_on_error(studies::accuracy_dependence(|_, _| bar.inc(1)));
    bar.finish_and_clear();
    let bar = progress_bar(
        exit_on_error(studies::stability_cases()).len() as u64,
        "stability cases",
    );
    exit_on_error(studies::stability(|_| bar.inc(1)));
    bar.finish_and_clear();
    let sections = vec![
        work_precision_section(),
        stability_section(),
        performance_section(),
    ];
    exit_on_error(write(
        &results,
        &golden,
        &sections,
        clock.elapsed().as_secs_f64(),
    ));
    println!("wrote paper.md in {:.1} s", clock.elapsed().as_secs_f64());
}
