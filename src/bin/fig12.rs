//! Paper figure 12: see `jointwear::paper::figures::time_series::fig12`.
fn main() {
    jointwear::paper::figures::figure_main("fig12");
}
