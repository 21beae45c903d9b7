//! Section 5's paragraph on the bearing's sector count (`data/sector_resolution.csv`, written
//! by `cargo run --release --bin sector_resolution`).

use super::markdown::csv_table;
use crate::paper::figures::output_path;
use crate::paper::format::{count, sci};
use crate::paper::studies::sector_resolution::{
    read_sector_resolution, scene_sectors, SectorRow, SECTOR_CASES, SECTOR_MEMBERS,
    SECTOR_RESOLUTION_FILE,
};
use std::fmt::Write as _;

const COMMAND: &str = "cargo run --release --bin sector_resolution";

/// The study's table and, per case, how its deepest wear at the scene's own sector count
/// compares with the finest count every member ran within the gap's validity bound.
pub(super) fn sector_resolution(md: &mut String) {
    let _ = write!(
        md,
        "**Does the wear depend on how finely the bearing is divided?** Each sector holds its mean \
         depth (eq. 9), so a scar a few sectors wide reads shallower than it is, and its slope, which the \
         gap's validity bound watches, is smoothed. The wear cases' rotations (those of figures 5-15) at \
         other sector counts ({SECTOR_MEMBERS} members each, seed 1; `{COMMAND}`), over the members that \
         stayed within the bound: each member's deepest sector depth at the end, mean and sd, and its change \
         from the scene's own count member by member (the same seeds at every count), mean and standard \
         error; the angle of \
         each member's most prominent wear region (circular mean: where members' most prominent scars \
         differ, as at 0.5 mm, it falls between them) and its width at half its prominence; the mean \
         evaluations and the summed wall time of those members; and the earliest rotation in which a \
         member left the bound:\n\n"
    );
    csv_table(md, SECTOR_RESOLUTION_FILE, COMMAND);
    match read_sector_resolution() {
        Some(rows) => {
            for case in SECTOR_CASES {
                md.push_str(&finding(case, &rows, scene_sectors(case)));
            }
            md.push('\n');
        }
        None if !output_path("data", SECTOR_RESOLUTION_FILE).exists() => {}
        None => {
            let _ = write!(
                md,
                "*No findings: `data/{SECTOR_RESOLUTION_FILE}` is damaged or of another layout \
                 (rerun `{COMMAND}`).*\n\n"
            );
        }
    }
}

/// One line on `case`: its depth at the scene's `own` sector count against the finest count
/// at which every member stayed within the bound, judged by the standard error of the members'
/// own changes (paired by seed),
/// and the counts at which members left the bound.
fn finding(case: &str, rows: &[SectorRow], own: Option<usize>) -> String {
    let rows: Vec<&SectorRow> = rows.iter().filter(|r| r.case == case).collect();
    let complete = |r: &SectorRow| r.within == r.members && r.within > 1;
    let at = own.and_then(|n| rows.iter().find(|r| r.sectors == n));
    let left: Vec<String> = rows
        .iter()
        .filter_map(|r| {
            let stop = r.earliest_stop?;
            Some(format!(
                "{} of {} members at {} sectors (the first in rotation {stop})",
                r.members - r.within,
                r.members,
                r.sectors
            ))
        })
        .collect();
    let left = if left.is_empty() {
        "no member left the gap's validity bound at any count".to_string()
    } else {
        format!("left the gap's validity bound: {}", left.join("; "))
    };
    let Some(at) = at.filter(|r| complete(r)) else {
        return format!(
            "- `{case}`: no comparison (at the scene's own sector count not every member ran \
             within the bound, or there is no row for it); {left}.\n"
        );
    };
    let finer = rows
        .iter()
        .filter(|r| r.sectors > at.sectors && complete(r));
    let Some(finest) = finer.max_by_key(|r| r.sectors) else {
        return format!(
            "- `{case}`: no count finer than the scene's {} sectors at which every member ran \
             within the bound; {left}.\n",
            at.sectors
        );
    };
    let change = finest.deepest_mean / at.deepest_mean - 1.0;
    // Member by member (the same seeds at both counts), so the members' spread cancels.
    let (diff, se) = (finest.paired_change, finest.paired_change_se);
    let paired = format!(
        "member by member over the {} within the bound at both, {:+.4} ± {} µm",
        finest.paired,
        diff * 1e6,
        sci(se * 1e6)
    );
    let verdict = if diff == 0.0 {
        format!("{paired}: the same.")
    } else if se == 0.0 || !se.is_finite() {
        format!("{paired}, the members changing alike: the change is the count's.")
    } else if (diff / se).abs() <= 2.0 {
        format!(
            "{paired}, within twice its standard error: no dependence this ensemble can resolve."
        )
    } else {
        let narrows = if finest.region_width_deg < at.region_width_deg {
            format!(
                " The most prominent region narrows from {:.2}° to {:.2}° wide at half its \
                 prominence: the scar is not resolved even there, and {:.4} µm is not converged either.",
                at.region_width_deg,
                finest.region_width_deg,
                finest.deepest_mean * 1e6
            )
        } else {
            String::new()
        };
        format!(
            "{paired}, {:.0} standard errors: the scene's count reads this wear {} than a finer \
             one.{narrows}",
            (diff / se).abs(),
            if diff > 0.0 { "shallower" } else { "deeper" }
        )
    };
    // Members that stay within the bound at the scene's count but leave it at a finer one: the
    // bound is a steepness, and the finer profile resolves more of it.
    let steeper = rows
        .iter()
        .any(|r| r.sectors > at.sectors && r.within < r.members);
    let left = if steeper {
        format!(
            "{left}; at the scene's count every member stays within it: the bound is a steepness, \
             and the finer profiles are steeper"
        )
    } else {
        left
    };
    format!(
        "- `{case}`: at the scene's {} sectors ({:.3}° each) each member's deepest sector is {:.4} µm \
         (mean of {}); at {} sectors, the finest at which every member stayed within the bound, {:.4} µm \
         ({:+.1} %), {verdict} A member took {} evaluations at the scene's count and {} at that one (mean); \
         {left}.\n",
        at.sectors,
        360.0 / at.sectors as f64,
        at.deepest_mean * 1e6,
        at.within,
        finest.sectors,
        finest.deepest_mean * 1e6,
        100.0 * change,
        count(at.evaluations.round() as u64),
        count(finest.evaluations.round() as u64),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of `within` of 8 members, deepest `mean` ± `sd`, changed from the scene's count by
    /// `change` ± `se` member by member.
    fn row(
        sectors: usize,
        within: usize,
        (mean, sd): (f64, f64),
        (change, se): (f64, f64),
    ) -> SectorRow {
        SectorRow {
            case: "c".into(),
            sectors,
            members: 8,
            within,
            earliest_stop: (within < 8).then_some(40),
            deepest_mean: mean,
            deepest_sd: sd,
            paired: within,
            paired_change: change,
            paired_change_se: se,
            region_deg: 180.0,
            region_width_deg: 2.0,
            evaluations: 1.0,
            wall_time: 1.0,
        }
    }

    /// A depth that grows with the count beyond the paired spread is called a misreading, not
    /// converged where the scar narrows; one within it is not; counts where members left the
    /// bound are named and not compared, and only a strictly finer complete count is compared.
    /// Fails with the independent means' standard error in place of the paired one (the second
    /// case then reads "no dependence": tried).
    #[test]
    fn findings_compare_the_scenes_count_with_the_finest_complete_one() {
        let scene = row(360, 8, (0.050, 1e-5), (0.0, 0.0));
        let mut fine = row(1080, 8, (0.064, 1e-5), (0.014, 1e-6));
        fine.region_width_deg = 1.33;
        let gone = row(1440, 0, (f64::NAN, f64::NAN), (f64::NAN, f64::NAN));
        let f = finding("c", &[scene.clone(), fine, gone], Some(360));
        assert!(
            f.contains("at 1080 sectors") && f.contains("+28.0 %") && f.contains("not converged"),
            "{f}"
        );
        assert!(
            f.contains("shallower")
                && f.contains("finer profiles are steeper")
                && f.contains("8 of 8 members at 1440 sectors (the first in rotation 40)"),
            "{f}"
        );
        // Members spread by 0.05 but each moves by 0.01 ± 0.001: a dependence only pairing sees.
        let rows = [
            row(360, 8, (0.65, 0.05), (0.0, 0.0)),
            row(1080, 8, (0.66, 0.05), (0.01, 0.001)),
        ];
        let f = finding("c", &rows, Some(360));
        assert!(
            f.contains("10 standard errors") && f.contains("no member left"),
            "{f}"
        );
        let rows = [
            row(360, 8, (0.65, 0.05), (0.0, 0.0)),
            row(1080, 8, (0.66, 0.05), (0.01, 0.02)),
        ];
        assert!(finding("c", &rows, Some(360)).contains("no dependence"));
        assert!(finding("c", &rows, Some(720)).contains("no comparison"));
        assert!(finding("c", &rows[..1], Some(360)).contains("no count finer"));
        // A coarser complete count is not "finer"; members that left at the scene's count
        // leave nothing to compare.
        let rows = [
            row(180, 8, (0.60, 0.05), (-0.05, 0.01)),
            row(360, 6, (0.65, 0.05), (0.0, 0.0)),
        ];
        assert!(finding("c", &rows, Some(360)).contains("no comparison"));
        // Members that change alike: no division by a zero standard error.
        let rows = [scene, row(720, 8, (0.06, 0.0), (0.01, 0.0))];
        let f = finding("c", &rows, Some(360));
        assert!(
            f.contains("changing alike") && !f.contains("NaN") && !f.contains("inf"),
            "{f}"
        );
    }
}
