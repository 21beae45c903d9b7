//! Wall time of the standard scene against rotations and clearance: data/scaling.csv, figures/scaling.png.
fn main() {
    print!(
        "{}",
        jointwear::figures::exit_on_error(jointwear::performance::scaling_study())
    );
}
