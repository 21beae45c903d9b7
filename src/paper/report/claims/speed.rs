//! The claims of section 6.3 of the paper, the effect of crank speed (30, 600 and 2000 r/min
//! at 0.02 mm): figure 12 (rebounds at 30 r/min, permanent contact at 600 r/min), figures 12
//! and 14 (wear at the bottom of the bearing at 30 r/min), figures 12-13 (penetration,
//! acceleration and wear rate rise with speed) and figures 14-15 (wear spreads with speed).

use super::{
    across, decreasing, deepest_angle, increasing, mean_sd, Claims, Ensembles, WHOLE_SURFACE,
};
use crate::paper::cases::{recorded_window, SteadyMember};
use crate::paper::golden::{angle_distance, Golden};

/// Adds the claims of figures 12-15.
pub(super) fn claims(c: &mut Claims, e: &Ensembles, golden: &Golden) {
    let slow = e.steady.speed_30rpm;
    let n = slow.members.len();
    c.claim(
        "Fig. 12",
        "at 30 r/min the journal rebounds after impacts instead of staying in contact",
        "motion mode free flight and impact (the motion rule of Table 3)",
        format!(
            "over {}: free flight and impact in {} of {n}; {} contact onsets per rotation, in contact {} % of the time",
            recorded_window(&[slow]),
            n - slow.continuous(),
            mean_sd(&slow.onset_states(), n, 1.0, 1),
            mean_sd(&slow.contact_states(), n, 100.0, 1)
        ),
        &|m| Some(vec![!m.steady.speed_30rpm.motion.continuous()]),
    );
    let low = &golden.low_speed_wear;
    c.claim(
        "Fig. 12, 14",
        "at 30 r/min contact and wear concentrate at the bottom of the bearing, around 270 deg",
        format!(
            "deepest wear within the golden tolerance ({} deg) of {} deg; undefined in a member without wear regions",
            low.angle_tolerance_deg, low.largest_peak_deg
        ),
        format!(
            "deepest wear at {} deg",
            mean_sd(&e.wear.speed_30rpm.angle_states(deepest_angle), n, 1.0, 0)
        ),
        &|m| {
            let a = m.wear.speed_30rpm.deepest_angle()?;
            Some(vec![angle_distance(a, low.largest_peak_deg) <= low.angle_tolerance_deg])
        },
    );
    let mid = e.steady.speed_600rpm;
    c.claim(
        "Fig. 12",
        "at 600 r/min the journal is in permanent contact and the whole bearing surface sees contact",
        format!(
            "motion mode continuous contact (the motion rule of Table 3) and ≥ {:.0} % of the circumference touched",
            100.0 * WHOLE_SURFACE
        ),
        format!(
            "over {}: continuous contact in {} of {n}; in contact {} % of the time, {} % of the circumference touched",
            recorded_window(&[mid]),
            mid.continuous(),
            mean_sd(&mid.contact_states(), n, 100.0, 1),
            mean_sd(&mid.coverage_states(), n, 100.0, 0)
        ),
        &|m| {
            let s = m.steady.speed_600rpm;
            Some(vec![s.motion.continuous(), s.contact_coverage >= WHOLE_SURFACE])
        },
    );
    let sp = e.steady.by_speed().map(|s| *s);
    c.claim(
        "Fig. 12, 13",
        "penetration, slider acceleration and wear rate rise with crank speed",
        "all three increase with speed",
        format!(
            "at 30 / 600 / 2000 r/min, over {}: max penetration {} µm; max |acceleration| {} m/s²; max wear rate {} µm/s",
            recorded_window(&sp),
            across(&sp, n, |e| e.states(|m| m.max_penetration), 1e6, 2),
            across(&sp, n, |e| e.states(|m| m.max_slider_acc), 1.0, 0),
            across(&sp, n, |e| e.states(|m| m.max_wear_rate), 1e6, 3)
        ),
        &|m| {
            let v = |f: &dyn Fn(&SteadyMember) -> f64| -> Vec<f64> {
                m.steady.by_speed().iter().map(|s| f(s)).collect()
            };
            [
                increasing(&v(&|s| s.max_penetration)),
                increasing(&v(&|s| s.max_slider_acc)),
                increasing(&v(&|s| s.max_wear_rate)),
            ]
            .into_iter()
            .collect()
        },
    );
    let wsp = e.wear.by_speed().map(|w| *w);
    c.claim(
        "Fig. 14, 15",
        "with speed the wear regions spread to a more uniform distribution; low speed concentrates wear",
        "deepest / mean wear depth decreases with speed",
        format!(
            "deepest / mean wear depth {} at 30 / 600 / 2000 r/min",
            across(&wsp, n, |e| e.states(|m| m.max_depth() / m.mean_depth()), 1.0, 1)
        ),
        &|m| {
            let u = m.wear.by_speed().map(|w| w.max_depth() / w.mean_depth());
            decreasing(&u).map(|d| vec![d])
        },
    );
}
