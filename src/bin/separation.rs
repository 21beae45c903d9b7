//! Could ensemble members share a settling phase? Pairs of members continued from one settled
//! run against the same pairs started independently, per rotation, for every Table 3 case:
//! `data/member_separation.csv`. See `jointwear::paper::separation`.
use jointwear::error::exit_on_error;
use jointwear::paper::separation::separation_study;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "separation",
        "Could ensemble members share a settling phase: writes data/member_separation.csv",
        &[],
    );
    let cells = |v: &[f64]| {
        v.iter()
            .map(|v| format!("{v:.1e}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for s in exit_on_error(separation_study()) {
        println!("{:>16} shared:      {}", s.case, cells(&s.shared));
        println!("{:>16} independent: {}", "", cells(&s.independent));
    }
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/member_separation.csv")
    );
}
