//! Table 3: motion mode and concordances of the five cases as ensemble statistics beside the
//! paper's values; writes `data/table3.csv`. See `jointwear::paper::figures::table3`.
fn main() {
    jointwear::paper::figures::figure_main("table3");
}
