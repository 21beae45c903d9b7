//! Paper figure 9: see `jointwear::figures::fig09`.
fn main() {
    jointwear::figures::figure_main("fig09");
}
