//! Paper figure 14: see `jointwear::figures::fig14`.
fn main() {
    jointwear::figures::figure_main("fig14");
}
