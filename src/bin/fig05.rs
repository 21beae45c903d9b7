//! Paper figure 5: see `jointwear::paper::figures::wear_profiles::fig05`.
fn main() {
    jointwear::paper::figures::figure_main("fig05");
}
