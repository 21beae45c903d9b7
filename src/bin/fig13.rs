//! Paper figure 13: see `jointwear::paper::figures::time_series::fig13`.
fn main() {
    jointwear::paper::figures::figure_main("fig13");
}
