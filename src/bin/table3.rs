//! Table 3: motion mode and concordances of the five cases as ensemble statistics beside the
//! paper's values; writes `data/table3.csv`. See `jointwear::figures::FIGURES`.
fn main() {
    jointwear::figures::figure_main("table3");
}
