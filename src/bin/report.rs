//! Rebuilds everything the reproducibility report shows and writes `paper.md`.
//!
//! `report` computes the ensembles of every case once, draws every figure and Table 3 from
//! them, reruns the accuracy-dependence study and the stability suite, and reads the other
//! studies' last results from `data/` (`report::READ_BACK`; the work-precision figure is
//! redrawn from `data/work_precision.csv`). It first checks each of those against the record its
//! run left (`jointwear::paper::provenance`) and stops (exit 2), naming every study whose
//! results are not this checkout's and the command that remakes them, before any work.
//! `report --all` also reruns the slow studies (calibration, work-precision, the ensemble-size
//! study and the two contact-law studies) instead of reading them.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::figures::output_root;
use jointwear::paper::golden::Golden;
use jointwear::paper::report::{check_read_back, run_figures, write, Studies};
use jointwear::paper::{calibration, convergence, program, studies};
use jointwear::simulation::ensemble::EnsembleSettings;

fn main() {
    let claim = program::flags(
        "report",
        "Computes every ensemble once, draws every figure and Table 3, reruns the accuracy study \
         and the stability suite and writes paper.md",
        &[(
            "--all",
            "also rerun the slow studies (calibration, work-precision, ensemble size, the two \
             contact-law studies) instead of reading their last results from data/",
        )],
    );
    let clock = std::time::Instant::now();
    let golden = exit_on_error(Golden::load());
    let rerun_all = claim.flags.contains(&"--all");
    // Results read back that are not this checkout's stop the report before its minutes of work.
    exit_on_error(check_read_back(rerun_all));
    if rerun_all {
        let bar = progress_bar(0, "calibration sets");
        exit_on_error(calibration::study(&bar));
        bar.finish_and_clear();
        let bar = progress_bar(0, "work-precision runs");
        exit_on_error(studies::work_precision(&bar));
        bar.finish_and_clear();
        let bar = progress_bar(0, "convergence members");
        exit_on_error(convergence::convergence_study(&bar));
        bar.finish_and_clear();
        exit_on_error(studies::contact_laws::contact_laws_study());
        let bar = progress_bar(0, "contact-law members");
        exit_on_error(studies::contact_law_wear::contact_law_wear_study(
            false, &golden, &bar,
        ));
        bar.finish_and_clear();
    } else {
        // the study's last results stay; its figure follows changes of the drawing
        exit_on_error(studies::redraw_work_precision());
    }
    let bar = progress_bar(0, "ensemble members");
    let (runs, drawn) = exit_on_error(run_figures(EnsembleSettings::default(), &bar));
    bar.finish_and_clear();
    let bar = progress_bar(0, "accuracy runs");
    let accuracy = exit_on_error(studies::accuracy_dependence(&bar));
    bar.finish_and_clear();
    let bar = progress_bar(0, "stability cases");
    let stability = exit_on_error(studies::stability(&bar));
    bar.finish_and_clear();
    let studies = Studies {
        accuracy: &accuracy,
        stability: &stability,
        rerun_all,
    };
    exit_on_error(write(
        &runs,
        &drawn,
        &golden,
        &studies,
        clock.elapsed().as_secs_f64(),
    ));
    println!(
        "wrote {} in {:.1} s",
        output_root().join("paper.md").display(),
        clock.elapsed().as_secs_f64()
    );
}
