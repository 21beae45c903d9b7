//! Paper figure 11: see `jointwear::figures::fig11`.
fn main() {
    jointwear::figures::figure_main("fig11");
}
