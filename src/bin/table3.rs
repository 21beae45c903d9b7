//! Table 3: motion mode and concordances of the five cases beside the paper's values;
//! writes `data/table3.csv`. See `jointwear::figures::table3`.
use jointwear::figures::{exit_on_error, table3};
use jointwear::golden::Golden;

fn main() {
    let golden = exit_on_error(Golden::load());
    let (rows, _) = exit_on_error(table3());
    println!("wrote data/table3.csv");
    println!(
        "{:>6} {:>6} | {:<23} {:>7} {:>7} {:>4} | {:<23} {:>7} {:>7} {:>4}",
        "c mm", "r/min", "paper: motion", "P-w", "s-w", "", "measured: motion", "P-w", "s-w", ""
    );
    for (r, g) in rows.iter().zip(&golden.table3) {
        let c = &r.concordance;
        println!(
            "{:>6} {:>6} | {:<23} {:>7.4} {:>7.4} {:>4} | {:<23} {:>7.4} {:>7.4} {:>4}",
            r.clearance_mm,
            r.speed_rpm,
            g.motion,
            g.pw,
            g.sw,
            g.dominant(),
            r.motion.mode(),
            c.pressure_wear,
            c.sliding_wear,
            c.dominant()
        );
    }
}
