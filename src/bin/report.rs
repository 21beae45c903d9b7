//! Rebuilds everything the reproducibility report shows and writes `paper.md`.
//!
//! `report` reruns every figure, Table 3 and the stability suite (about a minute); `report --all`
//! also reruns the slow studies (calibration, work-precision, accuracy dependence: several
//! minutes each) instead of reading their last results from `data/`.
use jointwear::figures::exit_on_error;
use jointwear::golden::Golden;
use jointwear::output::progress_bar;
use jointwear::report::{
    performance_section, run_figures, stability_section, work_precision_section, write, FIGURES,
};
use jointwear::{calibration, studies};

fn main() {
    let clock = std::time::Instant::now();
    let all = std::env::args().any(|a| a == "--all");
    let golden = exit_on_error(Golden::load());
    if all {
        eprintln!("calibration study ...");
        exit_on_error(calibration::study(|done, total| {
            eprint!("\r  {done}/{total} parameter sets")
        }));
        eprintln!("\nwork-precision study ...");
        exit_on_error(studies::work_precision(|s| {
            eprintln!("  {} {}", s.method_name(), s.setting())
        }));
        eprintln!("accuracy-dependence study ...");
        exit_on_error(studies::accuracy_dependence(|case, setting| {
            eprintln!("  {case} {setting}")
        }));
    }
    let bar = progress_bar((FIGURES.len() + 1) as u64, "figures and tables");
    let results = exit_on_error(run_figures(|done, _, name, secs| {
        bar.set_position(done as u64);
        bar.set_message(format!("{name} {secs:.1} s"));
    }));
    bar.finish_and_clear();
    let cases = exit_on_error(studies::stability_cases());
    let bar = progress_bar(cases.len() as u64, "stability cases");
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
