//! The claims of section 6.1 of the paper about the standard case (0.02 mm, 2000 r/min):
//! figure 3 (wear rate follows the contact force), figure 4 (continuous contact over the
//! whole bearing), figures 5-6 (three severe wear regions around 50, 180 and 320 deg, the
//! one at 180 deg leading) and figure 7 (staircase growth of the regions).

use super::{deepest_angle, within, Claims, Ensembles};
use crate::paper::cases::WearMember;
use crate::paper::figures::wear_history::region_share_stats;
use crate::paper::golden::{angle_distance, Golden};

/// Depth of a member's three most prominent regions after snapshot `i`: the first (the
/// deepest) over the mean of the other two.
fn lead(m: &WearMember, i: usize) -> f64 {
    let d = |k: usize| {
        m.regions
            .get(k)
            .map_or(f64::NAN, |p| m.snapshots[i].1[p.sector])
    };
    d(0) / (0.5 * (d(1) + d(2)))
}

/// Adds the claims of figures 3-7.
pub(super) fn claims(c: &mut Claims, e: &Ensembles, golden: &Golden) {
    let tol = golden.standard_wear.angle_tolerance_deg;
    let std_st = e.steady.standard;
    c.claim(
        "Fig. 3",
        "slider acceleration oscillates at high frequency; the wear rate follows it (the contact force)",
        "both correlations ≥ 0.5",
        format!(
            "correlation of wear rate with contact force {}, with |slider acceleration| {}",
            std_st.stat(|m| m.force_wear_correlation).mean_sd(1.0, 2),
            std_st.stat(|m| m.acc_wear_correlation).mean_sd(1.0, 2)
        ),
        &|m| {
            let s = m.steady.standard;
            vec![s.force_wear_correlation >= 0.5, s.acc_wear_correlation >= 0.5]
        },
    );
    c.claim(
        "Fig. 4",
        "continuous contact, no free flight or impact; the whole bearing surface sees contact",
        "motion mode continuous contact (the motion rule of Table 3); ≥ 90% of the circumference touched",
        format!(
            "continuous contact in {} of {}; in contact {} % of the time, {} contact onsets per rotation, {} % of the circumference touched",
            std_st.continuous(),
            std_st.members.len(),
            std_st.stat(|m| m.motion.contact_fraction).mean_sd(100.0, 1),
            std_st.stat(|m| m.motion.impacts_per_rotation).mean_sd(1.0, 1),
            std_st.stat(|m| m.contact_coverage).mean_sd(100.0, 0)
        ),
        &|m| {
            let s = m.steady.standard;
            vec![s.motion.continuous(), s.contact_coverage >= 0.9]
        },
    );
    let std_we = e.wear.standard;
    let region_angle = |target: f64| {
        std_we.angle_stat(move |m| {
            m.region_angles()
                .into_iter()
                .min_by(|a, b| angle_distance(*a, target).total_cmp(&angle_distance(*b, target)))
                .unwrap_or(f64::NAN)
        })
    };
    let claimed = &golden.standard_wear.peak_angles_deg;
    c.claim(
        "Fig. 5, 6",
        "wear concentrates in three severe regions around 50, 180 and 320 deg",
        "one of the three most prominent regions within the golden tolerance (10 deg) of each claimed angle",
        format!(
            "nearest region to 50 / 180 / 320 deg at {} deg",
            claimed
                .iter()
                .map(|&a| region_angle(a).mean_sd(1.0, 0))
                .collect::<Vec<_>>()
                .join(" / ")
        ),
        &|m| {
            let angles = m.wear.standard.region_angles();
            claimed.iter().map(|&a| within(&angles, a, tol)).collect()
        },
    );
    let last = std_we.members[0].snapshots.len().saturating_sub(1);
    c.claim(
        "Fig. 6",
        "the 180 deg region wears most, and its lead grows drastically as wear evolves",
        "deepest region within 10 deg of 180; its lead (depth over the mean of the other two) grows from 10 to 40 rotations",
        format!(
            "deepest region at {} deg; lead {} after 10 rotations, {} after 40",
            std_we.angle_stat(deepest_angle).mean_sd(1.0, 0),
            std_we.stat(|m| lead(m, 0)).mean_sd(1.0, 2),
            std_we.stat(|m| lead(m, last)).mean_sd(1.0, 2)
        ),
        &|m| {
            let w = m.wear.standard;
            let at_180 = w.deepest_angle().is_some_and(|a| angle_distance(a, 180.0) <= tol);
            vec![at_180, lead(w, last) > lead(w, 0)]
        },
    );
    c.claim(
        "Fig. 7",
        "the radius of each region grows like a staircase: contact alternates between the regions",
        "every region gets 90% of its wear in less than half of the crank positions",
        format!(
            "the three most prominent regions get 90% of their wear in {} % of the crank positions",
            region_share_stats(&e.shares)
                .map(|d| d.mean_sd(100.0, 0))
                .join(", ")
        ),
        &|m| m.shares.iter().map(|&s| s < 0.5).collect(),
    );
}
