//! Figure 6: bearing wear profile after 10, 20, 30 and 40 crank rotations (standard scene).
use jointwear::figures::{exit_on_error, fig06};

fn main() {
    let peaks = exit_on_error(fig06());
    println!("wrote figures/fig06.png and data/fig06.csv");
    println!("largest wear peaks after 40 rotations:");
    for p in peaks.iter().take(3) {
        println!(
            "  {:6.1} deg  depth {:.4} µm  width {:.0} deg",
            p.angle_deg,
            p.depth * 1e6,
            p.width_deg
        );
    }
}
