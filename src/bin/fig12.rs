//! Paper figure 12: see `jointwear::figures::fig12`.
fn main() {
    jointwear::figures::figure_main("fig12");
}
