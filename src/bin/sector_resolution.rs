//! How the predicted wear depends on the bearing's sector count (see
//! `jointwear::paper::studies::sector_resolution`): writes `data/sector_resolution.csv`.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::studies::sector_resolution::sector_resolution;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "sector_resolution",
        "How the predicted wear depends on the bearing's sector count: writes data/sector_resolution.csv",
        &[],
    );
    let bar = progress_bar(0, "member runs");
    let rows = exit_on_error(sector_resolution(&bar));
    bar.finish_and_clear();
    for r in &rows {
        let stop = r.earliest_stop.map_or(String::new(), |s| {
            format!(", the first to leave the gap's validity bound did in rotation {s}")
        });
        let depth = if r.within == 0 {
            "no member within the gap's validity bound".to_string()
        } else {
            format!(
                "each member's deepest sector {:.4} um (mean, sd {:.4}) over {} of {} members within the bound, most prominent region at {:.1} deg (circular mean), {:.2} deg wide",
                r.deepest_mean * 1e6,
                r.deepest_sd * 1e6,
                r.within,
                r.members,
                r.region_deg,
                r.region_width_deg,
            )
        };
        println!("{:>12} {:>5} sectors: {depth}{stop}", r.case, r.sectors);
    }
    println!(
        "{}",
        jointwear::paper::program::in_root("wrote data/sector_resolution.csv")
    );
}
