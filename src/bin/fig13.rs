//! Paper figure 13: see `jointwear::figures::fig13`.
fn main() {
    jointwear::figures::figure_main("fig13");
}
