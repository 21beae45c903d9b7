//! How fast two ensemble members separate, per rotation, for every Table 3 case:
//! `data/member_separation.csv`. See `jointwear::paper::separation`.
use jointwear::error::exit_on_error;
use jointwear::paper::separation::separation_study;

fn main() {
    for s in exit_on_error(separation_study()) {
        let cells: Vec<String> = s.per_rotation.iter().map(|v| format!("{v:.1e}")).collect();
        println!("{:>16}: {}", s.case, cells.join(" "));
    }
    println!("wrote data/member_separation.csv");
}
