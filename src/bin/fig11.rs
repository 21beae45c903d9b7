//! Paper figure 11: see `jointwear::paper::figures::wear_profiles::fig11`.
fn main() {
    jointwear::paper::figures::figure_main("fig11");
}
