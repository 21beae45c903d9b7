//! Paper figure 4: see `jointwear::paper::figures::time_series::fig04`.
fn main() {
    jointwear::paper::figures::figure_main("fig04");
}
