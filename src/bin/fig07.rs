//! Paper figure 7: see `jointwear::figures::fig07`.
fn main() {
    jointwear::figures::figure_main("fig07");
}
