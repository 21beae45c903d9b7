//! Paper figure 15: see `jointwear::figures::fig15`.
fn main() {
    jointwear::figures::figure_main("fig15");
}
