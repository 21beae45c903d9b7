//! The claims of section 6.2 of the paper, the effect of clearance size (0.02, 0.2 and 0.5 mm
//! at 2000 r/min): figure 8 (free flight, impact and contact at the larger clearances),
//! figures 8-9 (penetration and acceleration peaks grow with clearance), figure 10 (the same
//! wear regions at every clearance) and figure 11 (more uniform wear, similar depth).

use super::{across, decreasing, increasing, within, Claims, Ensembles};
use crate::paper::cases::{recorded_window, SteadyEnsemble, SteadyMember, WearMember};
use crate::paper::figures::mean_profile_regions;
use crate::paper::figures::wear_profiles::deepest_wear_states;
use crate::paper::golden::Golden;

/// Range of the deepest wear's ratio 0.5 mm : 0.02 mm within which the depth is "not
/// seriously affected by clearance" (figure 11): within a factor of two either way.
const NOT_SERIOUSLY_AFFECTED: (f64, f64) = (0.5, 2.0);

/// A member's (deepest − third region) / deepest ([`WearMember::region_spread`]), NaN with
/// fewer than three regions (left out of the statistics, undefined for the rule).
fn spread(m: &WearMember) -> f64 {
    m.region_spread().unwrap_or(f64::NAN)
}

/// Adds the claims of figures 8-11.
pub(super) fn claims(c: &mut Claims, e: &Ensembles, golden: &Golden) {
    let tol = golden.standard_wear.angle_tolerance_deg;
    let big = [e.steady.clearance_0_2mm, e.steady.clearance_0_5mm];
    c.claim(
        "Fig. 8",
        "at 0.2 and 0.5 mm free flight, impact and continuous contact modes all appear",
        "motion mode free flight and impact at each clearance (the motion rule of Table 3)",
        format!(
            "0.2 / 0.5 mm, over {}: free flight and impact in {} / {} of {}; in contact {} % of the time, {} onsets per rotation",
            recorded_window(&big),
            big[0].members.len() - big[0].continuous(),
            big[1].members.len() - big[1].continuous(),
            big[0].members.len(),
            across(&big, e.n, SteadyEnsemble::contact_states, 100.0, 1),
            across(&big, e.n, SteadyEnsemble::onset_states, 1.0, 1)
        ),
        &|m| {
            Some(
                [m.steady.clearance_0_2mm, m.steady.clearance_0_5mm]
                    .iter()
                    .map(|s| !s.motion.continuous())
                    .collect(),
            )
        },
    );
    let cl = e.steady.by_clearance().map(|s| *s);
    c.claim(
        "Fig. 8, 9",
        "penetration depth and slider acceleration peaks grow with the clearance",
        "both increase with clearance",
        format!(
            "over {}, max penetration {} µm, max |slider acceleration| {} m/s² at 0.02 / 0.2 / 0.5 mm",
            recorded_window(&cl),
            across(&cl, e.n, |e| e.states(|m| m.max_penetration), 1e6, 2),
            across(&cl, e.n, |e| e.states(|m| m.max_slider_acc), 1.0, 0)
        ),
        &|m| {
            let v = |f: &dyn Fn(&SteadyMember) -> f64| -> Vec<f64> {
                m.steady.by_clearance().iter().map(|s| f(s)).collect()
            };
            [
                increasing(&v(&|s| s.max_penetration)),
                increasing(&v(&|s| s.max_slider_acc)),
            ]
            .into_iter()
            .collect()
        },
    );
    let regions = |w| {
        mean_profile_regions(w)
            .iter()
            .take(3)
            .map(|p| format!("{:.0}", p.angle_deg))
            .collect::<Vec<_>>()
            .join(", ")
    };
    c.claim(
        "Fig. 10",
        "the regions experiencing wear are similar for all clearances",
        format!(
            "every region of the larger clearances within {} deg (twice the golden tolerance) of a region of the standard case; undefined in a member without regions at the larger clearances",
            2.0 * tol
        ),
        format!(
            "regions of the mean profiles at {} deg (0.2 mm) and {} deg (0.5 mm) against {} deg (0.02 mm)",
            regions(e.wear.clearance_0_2mm),
            regions(e.wear.clearance_0_5mm),
            regions(e.wear.standard)
        ),
        &|m| {
            let std = m.wear.standard.region_angles();
            Some(
                [m.wear.clearance_0_2mm, m.wear.clearance_0_5mm]
                    .iter()
                    .flat_map(|w| w.region_angles())
                    .map(|a| within(&std, a, 2.0 * tol))
                    .collect(),
            )
        },
    );
    let wcl = e.wear.by_clearance().map(|w| *w);
    c.claim(
        "Fig. 11",
        "a larger clearance gives a more uniform wear distribution (smaller differences between the regions)",
        "(deepest − third most prominent region) / deepest decreases with clearance; undefined in a member with fewer than three regions at a clearance",
        format!(
            "(deepest − third most prominent region) / deepest: {} at 0.02 / 0.2 / 0.5 mm",
            across(&wcl, e.n, |e| e.states(spread), 1.0, 2)
        ),
        &|m| decreasing(&m.wear.by_clearance().map(|w| spread(w))).map(|d| vec![d]),
    );
    c.claim(
        "Fig. 11",
        "although the contact force is much larger, the accumulated wear depth is not seriously affected by clearance",
        format!(
            "max wear ratio 0.5 mm : 0.02 mm within [{}, {}] (our number for \"not seriously\": \
             within a factor of two either way)",
            NOT_SERIOUSLY_AFFECTED.0, NOT_SERIOUSLY_AFFECTED.1
        ),
        format!(
            "max wear after {} rotations {} µm at 0.02 / 0.2 / 0.5 mm",
            e.wear.standard.scene.run.rotations,
            // (each with its states where the members split)
            across(&wcl, e.n, deepest_wear_states, 1e6, 3),
        ),
        &|m| {
            let r = m.wear.clearance_0_5mm.max_depth() / m.wear.standard.max_depth();
            let (lo, hi) = NOT_SERIOUSLY_AFFECTED;
            Some(vec![(lo..=hi).contains(&r)])
        },
    );
}
