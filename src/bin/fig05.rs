//! Paper figure 5: see `jointwear::figures::fig05`.
fn main() {
    jointwear::figures::figure_main("fig05");
}
