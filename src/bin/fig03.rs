//! Paper figure 3: see `jointwear::figures::fig03`.
fn main() {
    jointwear::figures::figure_main("fig03");
}
