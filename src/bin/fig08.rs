//! Paper figure 8: see `jointwear::figures::fig08`.
fn main() {
    jointwear::figures::figure_main("fig08");
}
