//! Figure 7 of the paper (section 6.1): how the bearing radius grows in the three severe wear
//! regions of the standard case, crank position by crank position. A staircase means each
//! region wears only during part of every rotation: contact alternates between the regions.
//!
//! Owns the staircase measure the Fig. 7 claim reads ([`staircase_shares`],
//! [`region_share_stats`]): per member and region, the share of crank positions that carry
//! 90 % of its wear.

use super::output_path;
use super::wear_profiles::{band_axes, mean_profile_regions, write_band_csv, BandCurve};
use crate::analysis::states::States;
use crate::analysis::statistics::{Band, Distribution};
use crate::io::plot::render;
use crate::paper::cases::{Runs, WearEnsemble, CASES, HISTORY_PER_ROTATION};
use crate::Result;

/// Share of history intervals that carry 90 % of the wear of a sector's depth history.
pub fn share_for_90pct(depth: &[f64]) -> f64 {
    let mut steps: Vec<f64> = depth.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(|a, b| b.total_cmp(a));
    let total: f64 = steps.iter().sum();
    let mut acc = 0.0;
    let carrying = steps.iter().take_while(|d| {
        acc += **d;
        acc - **d < 0.9 * total
    });
    carrying.count() as f64 / steps.len().max(1) as f64
}

/// Per member, the share of crank positions that carry 90 % of the wear of each of its own
/// three most prominent regions (figure 7's staircase).
pub fn staircase_shares(e: &WearEnsemble) -> Vec<Vec<f64>> {
    e.members
        .iter()
        .map(|m| {
            m.regions
                .iter()
                .take(3)
                .map(|p| {
                    // from the unworn bearing: the first history point is after one interval
                    let depth: Vec<f64> = std::iter::once(0.0)
                        .chain(m.history.iter().map(|(_, d)| d[p.sector]))
                        .collect();
                    share_for_90pct(&depth)
                })
                .collect()
        })
        .collect()
}

/// What [`staircase_shares`] are shares of, for the printouts and `paper.md`: `the 10° crank
/// intervals of its 40 rotations` (the profile history's intervals of the whole run, not the
/// positions of one rotation).
pub fn share_window(e: &WearEnsemble) -> String {
    format!(
        "the {}° crank intervals of its {} rotations",
        360 / HISTORY_PER_ROTATION,
        e.scene.run.rotations
    )
}

/// The spacing of [`staircase_shares`] in `e`: one of the crank intervals of its whole run
/// ([`share_window`]), which a share counts.
pub fn share_quantum(e: &WearEnsemble) -> f64 {
    1.0 / f64::from(e.scene.run.rotations * HISTORY_PER_ROTATION)
}

/// For the first, second and third most prominent region: the states over the members of
/// [`staircase_shares`] (members with fewer regions left out: NaN, in no state), counts of
/// crank intervals split only across an empty level ([`States::of_quantised`], `quantum` of
/// [`share_quantum`]).
pub fn region_share_stats(shares: &[Vec<f64>], quantum: f64) -> [States; 3] {
    [0, 1, 2].map(|i| {
        let values: Vec<f64> = (shares.iter())
            .map(|s| s.get(i).copied().unwrap_or(f64::NAN))
            .collect();
        States::of_quantised(&values, quantum)
    })
}

/// The lines figure 7's program prints: per region rank, the states over the members of the
/// share of [`share_window`] that carries 90 % of the region's wear.
fn share_lines(e: &WearEnsemble) -> Vec<String> {
    region_share_stats(&staircase_shares(e), share_quantum(e))
        .iter()
        .enumerate()
        .map(|(i, d)| {
            format!(
                "region {} of each member: 90% of its wear in {} % of {} (of the {} members \
                 with that region)",
                i + 1,
                d.mean_sd_with_states(100.0, 0),
                share_window(e),
                d.pooled.n
            )
        })
        .collect()
}

/// Figure 7: bearing radius in the three severe regions of the mean profile against crank
/// position, mean over the members with the 5-95 % band.
pub fn fig07(runs: &Runs) -> Result<Vec<String>> {
    let e = runs.wear(CASES.standard.scene)?;
    let r = e.scene.mechanism.clearance_joints[0].r_bearing * 1e3;
    let points = e.members.iter().map(|m| m.history.len()).min().unwrap_or(0);
    let interval = e.period / HISTORY_PER_ROTATION as f64;
    let crank: Vec<f64> = (1..=points)
        .map(|k| k as f64 * interval / e.period)
        .collect();
    let mut curves = Vec::new();
    for p in mean_profile_regions(e).iter().take(3) {
        let per_point = Band {
            sectors: (0..points)
                .map(|k| {
                    Distribution::of(e.members.iter().map(|m| r + m.history[k].1[p.sector] * 1e3))
                })
                .collect(),
        };
        let label = format!("region at {:.1} deg", p.angle_deg);
        let tag = format!("region_at_{:.1}_deg", p.angle_deg);
        curves.push(BandCurve::new(label, tag, &per_point, 1.0));
    }
    let lines = share_lines(e);
    let axes = band_axes(
        format!(
            "Bearing radius in the severe wear regions (0.02 mm, 2000 r/min), mean of {}",
            e.members.len()
        ),
        "crank position (rotations)",
        &crank,
        &curves,
        "bearing radius (mm)",
    );
    render(&output_path("figures", "fig07.png"), &[axes])?;
    let columns: Vec<(String, &BandCurve)> = curves.iter().map(|c| (c.tag.clone(), c)).collect();
    write_band_csv("fig07", "crank_rotations", &crank, &columns, 1.0)?;
    Ok(lines)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails on the lines as they were: "90% of its wear in 25 ± 0 % of the crank positions",
    // shares of the 1440 intervals of 10° of the 40 rotations, read as positions of one.
    #[test]
    fn the_staircase_lines_name_the_intervals_they_share_out() {
        let scene = crate::simulation::Scene::load(crate::scene::scene_path("standard")).unwrap();
        let e = WearEnsemble {
            scene,
            members: Vec::new(),
            period: 0.03,
        };
        let lines = share_lines(&e);
        assert_eq!(lines.len(), 3);
        for line in &lines {
            assert!(
                line.contains("% of the 10° crank intervals of its 40 rotations (of the"),
                "{line}"
            );
        }
    }
}
