//! The work-precision study (see `jointwear::paper::studies::work_precision`): writes
//! `data/work_precision.csv` and `figures/work_precision.png` and prints the error floor and
//! the default tolerance. `work_precision --redraw` only redraws the figure from the CSV.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::studies;

fn main() {
    if std::env::args().any(|a| a == "--redraw") {
        exit_on_error(studies::redraw_work_precision());
        println!("redrew figures/work_precision.png from data/work_precision.csv");
        return;
    }
    let bar = progress_bar(0, "work-precision runs");
    let wp = exit_on_error(studies::work_precision(&bar));
    bar.finish_and_clear();
    println!("wrote data/work_precision.csv and figures/work_precision.png");
    println!("error floor (reference disagreement): {:?}", wp.floor);
    println!(
        "default Dopri5 rtol by the stated rule: {:?}",
        wp.default_rtol
    );
}
