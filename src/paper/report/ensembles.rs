//! What the ensembles show (end of section 2 of `paper.md`): the steady states each case
//! settles in, with their basins, and the ensemble-size study (`data/ensemble_convergence.csv`,
//! [`crate::paper::convergence`]) with the default size it picks, and how fast members separate
//! (`data/member_separation.csv`, [`crate::paper::separation`]).

use super::markdown::md_table;
use crate::analysis::statistics::Distribution;
use crate::io::output::read_rows;
use crate::paper::cases::{recorded_window, Runs, SteadyMember, CASES};
use crate::paper::convergence::{MAX_MEMBERS, SE_SHARE, SIZES};
use crate::paper::figures::output_path;
use crate::paper::format::sci;
use crate::paper::golden::Golden;
use crate::paper::separation::{
    first_reaching, level, pair_offset_distance, read_separation, SEPARATION_ROTATIONS,
};
use crate::simulation::ensemble::DEFAULT_MEMBERS;
use crate::Result;
use std::fmt::Write as _;

/// What the ensembles reveal: the steady states each case settles in, with their basins.
pub(super) fn ensemble_section(runs: &Runs, golden: &Golden) -> Result<String> {
    let n = runs.ensemble.members;
    let mut md = String::from("### What the ensembles show: where single runs disagree\n\n");
    let settle = runs.steady(CASES.standard.scene)?.scene.run.settle;
    let _ = writeln!(
        md,
        "Each member settles (orbit repeating within {} % of the clearance from one rotation to the next, or \
         at most {} rotations) and is then classified by its two recorded rotations: its motion mode (in \
         contact at least 90 % of the time or not), continuous contact split by whether the journal still \
         leaves the wall at times. Where the members of a case fall into different states, one run's \
         classification is a draw, and Table 3's motion column for that case is a probability rather than a \
         property. Where every member of a state repeats its orbit, the state is a distinct periodic \
         attractor; where the orbits never repeat (last column), these ensembles cannot tell coexisting \
         attractors from one chaotic attractor whose recorded windows fall on either side of the \
         threshold.\n",
        settle.map_or(f64::NAN, |s| 100.0 * s.tolerance),
        settle.map_or(0, |s| s.max_rotations)
    );
    let mut rows = Vec::new();
    let steady = runs.steady_cases()?;
    let force = format!(
        "max normal force (N), {}",
        recorded_window(&steady.list().map(|e| *e))
    );
    for (case, e) in CASES.zip(&steady).list() {
        let (c_mm, rpm) = (case.clearance_mm, case.speed_rpm);
        for (mode, of_mode) in e.groups(SteadyMember::steady_state) {
            let k = of_mode.len();
            let stat =
                |f: &dyn Fn(&SteadyMember) -> f64| Distribution::of(of_mode.iter().map(|m| f(m)));
            rows.push(vec![
                format!("{c_mm} mm, {rpm} r/min"),
                mode.to_string(),
                format!("{k} of {n}"),
                stat(&|m| m.max_normal_force).mean_sd(1.0, 0),
                stat(&|m| m.motion.impacts_per_rotation).mean_sd(1.0, 1),
                stat(&|m| m.motion.contact_fraction).mean_sd(100.0, 1),
                stat(&|m| m.concordance.pressure_wear).mean_sd(1.0, 4),
                stat(&|m| m.concordance.sliding_wear).mean_sd(1.0, 4),
                format!(
                    "{} of {k}",
                    of_mode.iter().filter(|m| m.settling.steady).count()
                ),
            ]);
        }
    }
    md_table(
        &mut md,
        &[
            "case",
            "steady state",
            "members",
            &force,
            "onsets per rotation",
            "in contact (%)",
            "P-w",
            "s-w",
            "orbit repeated",
        ],
        &rows,
    );
    md.push_str(
        "A mechanism that makes runs of one case disagree, consistent with these ensembles but not measured \
         by them: eq. 3 scales the damping of every contact by the normal velocity captured at its onset, \
         δ̇⁻, and keeps it until the contact ends. A contact entered gently keeps a small damping and can \
         persist as continuous contact; one entered hard keeps a large damping, loses more energy per \
         rebound and can settle into a pattern of impacts. Which pattern a run falls into then depends on \
         its first few onsets, and so on nanometres of initial offset: single runs of the same case can \
         disagree qualitatively, which is why every number of this report is an ensemble statistic and every \
         claim states in how many members it holds. Claims that hold in every member are properties of the \
         model; claims that hold in some are properties of some of its runs.\n\n",
    );
    md.push_str(&convergence_section(golden));
    md.push_str(&separation_section(runs)?);
    md.push_str(&super::perturbation::perturbation_section());
    Ok(md)
}

/// Separation (over the clearance) below which members count as identical either way.
const AGREE: f64 = 1e-3;

/// Whether members could share a settling phase (`data/member_separation.csv`,
/// [`crate::paper::separation`]), and why each member settles on its own.
fn separation_section(runs: &Runs) -> Result<String> {
    let mut md = String::from(
        "### Could members share a settling phase?\n\n\
         Settling takes most of a steady run: its median per member is ",
    );
    let mut settling = Vec::new();
    for case in CASES.list() {
        let e = runs.steady(case.scene)?;
        let d = e.stat(|m| f64::from(m.settling.rotations));
        settling.push((case.scene, d.median()));
    }
    let limit = (runs.steady(CASES.standard.scene)?.scene.run.settle).map(|s| s.max_rotations);
    let listed: Vec<String> = settling
        .iter()
        .map(|(c, r)| format!("{r:.0} rotations ({c})"))
        .collect();
    let _ = write!(
        md,
        "{}{}, before two recorded ones. Sharing it would settle one run and continue it once per member \
         with that member's perturbation. The study runs exactly that (`cargo run --release --bin separation`, \
         `src/paper/separation.rs`): member 0 of each case settles, and members 1-8 continue its settled state \
         for {SEPARATION_ROTATIONS} rotations, each with its own journal offset (pairs 1-2, 3-4, 5-6, 7-8, \
         offsets on average {:.1} nm apart). `shared r`: the RMS distance between a pair's journal orbits in \
         rotation r after the shared settling, over the radial clearance, mean of the pairs; `independent`: \
         the same pairs started each from its own assembly, over their last four of {SEPARATION_ROTATIONS} \
         rotations, the spread of independent members:\n\n",
        listed.join(", "),
        limit.map_or(String::new(), |l| format!(" ({l} is `steady_state.max_rotations`, reached where the orbit never repeats)")),
        1e9 * pair_offset_distance()
    );
    let Some(study) = read_separation() else {
        md.push_str("*`data/member_separation.csv` is missing or not the study's whole table (a number for each of its rotations): run `cargo run --release --bin separation`.*\n\n");
        return Ok(md);
    };
    const SHOWN: [usize; 5] = [1, 2, 4, 8, 12];
    let mut header = vec!["case".to_string()];
    header.extend(SHOWN.map(|r| format!("shared {r}")));
    header.extend([
        "independent".to_string(),
        "shared reaches half of independent".to_string(),
    ]);
    let (mut mixing, mut holding, mut agreeing) = (Vec::new(), Vec::new(), Vec::new());
    let rows: Vec<Vec<String>> = study
        .iter()
        .map(|s| {
            let independent = level(&s.independent);
            let reached = first_reaching(&s.shared, 0.5 * independent);
            if independent < AGREE && level(&s.shared) < AGREE {
                agreeing.push(s.case.clone());
            } else if let Some(r) = reached {
                mixing.push(format!("{} in rotation {r}", s.case));
            } else {
                holding.push(format!(
                    "{}: {} against {}",
                    s.case,
                    sci(level(&s.shared)),
                    sci(independent)
                ));
            }
            std::iter::once(s.case.clone())
                .chain(SHOWN.map(|r| s.shared.get(r - 1).map_or(String::new(), |v| sci(*v))))
                .chain([
                    sci(independent),
                    reached.map_or("no".into(), |r| format!("rotation {r}")),
                ])
                .collect()
        })
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    md_table(&mut md, &header, &rows);
    if !mixing.is_empty() {
        let _ = write!(
            md,
            "Where the shared pairs reach half the independent separation within a few rotations ({}), the \
             settled motion mixes its perturbations: settling once and running that many rotations per member \
             would sample the same spread at a fraction of the settling cost. ",
            mixing.join(", ")
        );
    }
    if !holding.is_empty() {
        let _ = write!(
            md,
            "Where they do not within {SEPARATION_ROTATIONS} rotations (over the last four, {}), the settled \
             state spreads its perturbations only slowly: sharing would narrow the ensemble towards one \
             member's state, a different measurement. ",
            holding.join(", ")
        );
    }
    if !agreeing.is_empty() {
        let _ = write!(
            md,
            "Where members agree to {} of the clearance either way ({}), sharing changes nothing and saves little. ",
            sci(AGREE),
            agreeing.join(", ")
        );
    }
    md.push_str(
        "Which kind a case is shows only by running it, so every member settles from its own start; a \
         per-case switch to shared settling, checked against these independent ensembles' Table 3 \
         statistics, is where the steady runs' cost could fall.\n\n",
    );
    Ok(md)
}

/// The ensemble-size study (`data/ensemble_convergence.csv`) and the default it picks, its rule
/// stated with the tolerances of `golden`.
fn convergence_section(golden: &Golden) -> String {
    let mut md = String::from(
        "### How many members: the convergence study

",
    );
    let _ = writeln!(
        md,
        "One ensemble of {} members of every Table 3 case and of the standard wear case; its first N members \
         stand for an ensemble of N (`cargo run --release --bin convergence`, `src/paper/convergence.rs`). Rule: the \
         smallest N at which the standard error of every Table 3 concordance is at most {SE_SHARE} × the {} \
         tolerance, and that of every severe-region angle at most {SE_SHARE} × the {}° tolerance, so that a \
         comparison with the paper does not depend on which members were drawn. The library default is \
         {} members (`src/simulation/ensemble.rs`).\n",
        MAX_MEMBERS,
        golden.concordance_tolerance,
        golden.standard_wear.angle_tolerance_deg,
        DEFAULT_MEMBERS
    );
    // The study's table, whole: its sizes in order (the first column, which names each row),
    // every row of the header's length and the profile columns the note below explains; a
    // renamed or lost column or row was dropped from the table without a word.
    let whole = |header: &[String], rows: &[Vec<String>]| {
        let sizes = rows.iter().map(|r| r.first()?.parse::<usize>().ok());
        header.first().is_some_and(|h| h == "members")
            && rows.len() == SIZES.len()
            && rows.iter().all(|r| r.len() == header.len())
            && sizes.eq(SIZES.map(Some))
            && ["standard.mean_profile_rms_rel", "standard.band_width_rel"]
                .iter()
                .all(|c| header.iter().any(|h| h == c))
    };
    match read_rows(&output_path("data", "ensemble_convergence.csv")) {
        Ok((header, rows)) if whole(&header, &rows) => {
            let pick: Vec<usize> = header
                .iter()
                .enumerate()
                .filter(|(_, h)| {
                    *h == "members"
                        || h.ends_with(".pw.se")
                        || h.ends_with(".sw.se")
                        || h.ends_with("_rel")
                })
                .map(|(i, _)| i)
                .collect();
            let h: Vec<&str> = pick.iter().map(|&i| header[i].as_str()).collect();
            let rows: Vec<Vec<String>> = rows
                .iter()
                .map(|r| {
                    pick.iter()
                        .map(|&i| match r[i].parse::<f64>() {
                            Ok(v) if i == 0 => format!("{v}"),
                            Ok(v) => sci(v),
                            Err(_) => r[i].clone(),
                        })
                        .collect()
                })
                .collect();
            md_table(&mut md, &h, &rows);
        }
        _ => md.push_str(
            "*`data/ensemble_convergence.csv` is missing or not the study's whole table: run `cargo run --release --bin convergence`.*\n\n",
        ),
    }
    md.push_str(
        "`.se`: standard error of the mean; `mean_profile_rms_rel`: RMS distance of the N-member mean wear \
         profile from the full ensemble's, over the deepest mean wear; `band_width_rel`: mean width of the \
         5-95 % band over the deepest mean wear.\n\n![ensemble convergence](figures/ensemble_convergence.png)\n\n",
    );
    md
}
