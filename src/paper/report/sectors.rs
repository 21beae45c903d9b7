//! Section 5's paragraph on the bearing's sector count (`data/sector_resolution.csv`, written
//! by `cargo run --release --bin sector_resolution`).

use super::markdown::csv_table;
use crate::paper::figures::output_path;
use crate::paper::format::count;
use crate::paper::studies::sector_resolution::{
    read_sector_resolution, SectorRow, SECTOR_CASES, SECTOR_MEMBERS, SECTOR_RESOLUTION_FILE,
};
use crate::scene::{scene_path, SceneFile};
use std::fmt::Write as _;

const COMMAND: &str = "cargo run --release --bin sector_resolution";

/// The study's table and, per case, how its deepest wear at the scene's own sector count
/// compares with the finest count every member ran within the gap's validity bound.
pub(super) fn sector_resolution(md: &mut String) {
    let _ = write!(
        md,
        "**Does the wear depend on how finely the bearing is divided?** Each sector holds its mean \
         depth (eq. 9), so a scar a few sectors wide reads shallower than it is, and its slope, which the \
         gap's validity bound watches, is smoothed. The wear cases' rotations (those of figures 5-15) at other sector counts \
         ({SECTOR_MEMBERS} members each, seed 1; `{COMMAND}`): the deepest sector's depth at the end, mean \
         and sd over the members that stayed within the bound; the deepest region's angle and width at \
         half its prominence; the earliest rotation in which a member left the bound:\n\n"
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

/// The sector count `case`'s scene runs with (`None` if it cannot be read or does not wear).
fn scene_sectors(case: &str) -> Option<usize> {
    let file = SceneFile::read(scene_path(case)).ok()?;
    let wear = file.clearance.first()?.wear.as_ref()?;
    Some(wear.sectors)
}

/// One line on `case`: its depth at the scene's `own` sector count against the finest count
/// at which every member stayed within the bound, judged against the members' standard error,
/// and the counts at which members left the bound.
fn finding(case: &str, rows: &[SectorRow], own: Option<usize>) -> String {
    let rows: Vec<&SectorRow> = rows.iter().filter(|r| r.case == case).collect();
    let at = own.and_then(|n| rows.iter().find(|r| r.sectors == n && r.within > 0));
    let complete = |r: &&&SectorRow| r.within == r.members && r.within > 1;
    let finest = rows.iter().filter(complete).max_by_key(|r| r.sectors);
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
    let (Some(at), Some(finest)) = (at, finest) else {
        return format!(
            "- `{case}`: no comparison (no row at the scene's own sector count or none where \
             every member stayed within the bound); {left}.\n"
        );
    };
    if finest.sectors == at.sectors {
        return format!(
            "- `{case}`: the scene's {} sectors are the finest count every member ran within the \
             bound; {left}.\n",
            at.sectors
        );
    }
    let change = finest.deepest_mean / at.deepest_mean - 1.0;
    // The standard error of the difference of two independent means.
    let se = (at.deepest_sd.powi(2) / at.within as f64
        + finest.deepest_sd.powi(2) / finest.within as f64)
        .sqrt();
    let z = (finest.deepest_mean - at.deepest_mean) / se;
    let verdict = if z.abs() <= 2.0 {
        "within twice the standard error of the difference of the two means: no dependence \
         this ensemble can resolve"
            .to_string()
    } else {
        format!(
            "{:.0} standard errors of the difference: the scene's count reads this wear {} than \
             a finer one, far beyond the members' spread",
            z.abs(),
            if change > 0.0 { "shallower" } else { "deeper" }
        )
    };
    // Members that stay within the bound at the scene's count but leave it at a finer one: the
    // scene's sectors smooth the flanks the bound watches.
    let smoothed = at.within == at.members
        && rows
            .iter()
            .any(|r| r.sectors > at.sectors && r.within < r.members);
    let left = if smoothed {
        format!(
            "{left}: at the scene's count every member stays within the bound only because its \
             sectors smooth the scar's flanks"
        )
    } else {
        left
    };
    format!(
        "- `{case}`: at the scene's {} sectors ({:.3}° each) the deepest sector is {:.4} µm; at {} \
         sectors, the finest at which every member stayed within the bound, {:.4} µm ({:+.1} %), \
         {verdict}; a member took {} evaluations at the scene's count and {} at that one; {left}.\n",
        at.sectors,
        360.0 / at.sectors as f64,
        at.deepest_mean * 1e6,
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

    fn row(sectors: usize, within: usize, mean: f64, sd: f64, stop: Option<u32>) -> SectorRow {
        SectorRow {
            case: "c".into(),
            sectors,
            members: 8,
            within,
            earliest_stop: stop,
            deepest_mean: mean,
            deepest_sd: sd,
            region_deg: 180.0,
            region_width_deg: 2.0,
            evaluations: 1.0,
            wall_time: 1.0,
        }
    }

    /// A depth that grows with the count beyond the spread is called a misreading; one within
    /// the spread is not; counts where members left the bound are named and not compared.
    #[test]
    fn findings_compare_the_scenes_count_with_the_finest_complete_one() {
        let rows = [
            row(360, 8, 0.050, 1e-5, None),
            row(1080, 8, 0.064, 1e-5, None),
            row(1440, 0, f64::NAN, f64::NAN, Some(40)),
        ];
        let f = finding("c", &rows, Some(360));
        assert!(
            f.contains("at 1080 sectors") && f.contains("+28.0 %"),
            "{f}"
        );
        assert!(
            f.contains("shallower")
                && f.contains("smooth the scar")
                && f.contains("8 of 8 members at 1440 sectors (the first in rotation 40)"),
            "{f}"
        );
        let rows = [
            row(360, 8, 0.65, 0.05, None),
            row(1080, 8, 0.66, 0.05, None),
        ];
        let f = finding("c", &rows, Some(360));
        assert!(
            f.contains("no dependence") && f.contains("no member left"),
            "{f}"
        );
        assert!(finding("c", &rows, Some(720)).contains("no comparison"));
        assert!(finding("c", &rows[..1], Some(360)).contains("are the finest count"));
    }
}
