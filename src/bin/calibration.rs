//! The calibration study of the lost Table 2 (see `jointwear::paper::calibration`): writes
//! `data/calibration.csv` and `figures/calibration.png` and prints the best parameter sets.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::calibration::FACTORIAL_GROUP;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "calibration",
        "The calibration study of the lost Table 2: writes data/calibration.csv and figures/calibration.png",
        &[],
    );
    let bar = progress_bar(0, "parameter sets");
    let study = exit_on_error(jointwear::paper::calibration::study(&bar));
    bar.finish_and_clear();
    let ranked = &study.ranked;
    println!("best parameter sets (lower score is better; * = admissible, friction present):");
    // the best admissible set of the factorial (the scene keeps the one the study first chose;
    // the one-at-a-time rows measure sensitivity)
    let best_admissible = ranked
        .iter()
        .find(|r| r.1.admissible() && r.0 == FACTORIAL_GROUP);
    for (group, p, m) in ranked.iter().take(8).chain(best_admissible) {
        println!(
            "{} {:.3}  {group:9} {} mu_d {} v_s {} {:?} grazing {} k/H {:e} L {} sectors {} | regions {:?} err {:.1} deg, 180 largest {}, modes {}/5, dominance {}/5, CMF rms {:.4}, 30 r/min wear at {:.0} deg",
            if p.admissible() { '*' } else { ' ' },
            m.score,
            p.rotation(), p.mu_d, p.v_s, p.pressure, p.grazing, p.k_over_h, p.length_mm,
            p.sectors, m.region_angles, m.region_error_deg, m.largest_at_180, m.modes_matched, m.dominance_matched, m.concordance_rms, m.low_speed_angle
        );
    }
    for (group, p, why) in &study.failed {
        println!(
            "left the model ({group}, mu_d {} v_s {} {:?} grazing {} k/H {:e} L {} sectors {}): {why}",
            p.mu_d, p.v_s, p.pressure, p.grazing, p.k_over_h, p.length_mm, p.sectors
        );
    }
}
