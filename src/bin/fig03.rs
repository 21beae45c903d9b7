//! Paper figure 3: see `jointwear::paper::figures::time_series::fig03`.
fn main() {
    jointwear::paper::figures::figure_main("fig03");
}
