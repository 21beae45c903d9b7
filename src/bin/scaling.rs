//! Wall time of the standard scene against rotations and clearance: data/scaling.csv,
//! figures/scaling.png; and what sets its step: data/step_limit.csv.
fn main() {
    let _claim = jointwear::paper::program::flags(
        "scaling",
        "Wall time of the standard scene against rotations and clearance: writes data/scaling.csv, figures/scaling.png and data/step_limit.csv",
        &[],
    );
    print!(
        "{}",
        jointwear::error::exit_on_error(jointwear::paper::performance::scaling_study())
    );
}
