//! Paper figure 10: see `jointwear::paper::figures::wear_profiles::fig10`.
fn main() {
    jointwear::paper::figures::figure_main("fig10");
}
