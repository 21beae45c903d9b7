//! Paper figure 4: see `jointwear::figures::fig04`.
fn main() {
    jointwear::figures::figure_main("fig04");
}
