//! Rebuilds everything the reproducibility report shows and writes `paper.md`.
use jointwear::figures::exit_on_error;
use jointwear::golden::Golden;
use jointwear::report::{performance_section, run_figures, write};

fn main() {
    let clock = std::time::Instant::now();
    let golden = exit_on_error(Golden::load());
    let results = exit_on_error(run_figures(|done, total, name, secs| {
        eprintln!("[{done:2}/{total}] {name} ({secs:.1} s)");
    }));
    let sections = vec![performance_section()];
    exit_on_error(write(
        &results,
        &golden,
        &sections,
        clock.elapsed().as_secs_f64(),
    ));
    println!("wrote paper.md in {:.1} s", clock.elapsed().as_secs_f64());
}
