//! Paper figure 7: see `jointwear::paper::figures::wear_history::fig07`.
fn main() {
    jointwear::paper::figures::figure_main("fig07");
}
