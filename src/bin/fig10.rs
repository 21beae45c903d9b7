//! Paper figure 10: see `jointwear::figures::fig10`.
fn main() {
    jointwear::figures::figure_main("fig10");
}
