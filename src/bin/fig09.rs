//! Paper figure 9: see `jointwear::paper::figures::time_series::fig09`.
fn main() {
    jointwear::paper::figures::figure_main("fig09");
}
