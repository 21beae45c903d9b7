//! Paper figure 14: see `jointwear::paper::figures::wear_profiles::fig14`.
fn main() {
    jointwear::paper::figures::figure_main("fig14");
}
