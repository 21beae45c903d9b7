//! Paper figure 15: see `jointwear::paper::figures::wear_profiles::fig15`.
fn main() {
    jointwear::paper::figures::figure_main("fig15");
}
