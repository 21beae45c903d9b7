//! Paper figure 8: see `jointwear::paper::figures::time_series::fig08`.
fn main() {
    jointwear::paper::figures::figure_main("fig08");
}
