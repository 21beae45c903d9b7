//! Section 2 of `paper.md`: Table 3 of the paper (motion state and the concordances P-w and
//! s-w of each case, section 6.4) beside the ensembles' statistics, where and why the model
//! departs from the paper (`data/golden/paper.toml`), and the golden statistics it is held
//! to.

use super::markdown::md_table;
use super::text::ode45_outcome;
use crate::paper::cases::{Runs, CASES};
use crate::paper::figures::table3_rows;
use crate::paper::golden::{EnsembleGolden, Golden, SIGMAS};
use crate::paper::studies::accuracy::WINDOWS;
use crate::paper::studies::AccuracyDependence;
use crate::Result;
use std::fmt::Write as _;

/// Section 2 up to the ensembles' steady states: Table 3, the deviations (each with what the
/// accuracy study measured for its case under an ode45-like integration, from `accuracy`) and
/// the golden statistics.
pub(super) fn table3_section(
    md: &mut String,
    runs: &Runs,
    golden: &Golden,
    accuracy: &AccuracyDependence,
) -> Result<()> {
    let n = runs.ensemble.members;
    md.push_str("\n## 2. Table 3: concordance of wear-rate drivers\n\n");
    let _ = writeln!(
        md,
        "CMF(x, y) = Σxy / sqrt(Σx² Σy²) over the two recorded rotations after the steady state, on a uniform \
         grid, every series zero out of contact; P = peak contact pressure of the pressure model, s = |v_t|·Δt, \
         w = k·P·|v_t|/H (`src/analysis/concordance.rs`). Each value is mean ± sd over the {n} members; \"in band\" says \
         whether the paper's value lies between the 5 % and 95 % quantiles of the members.\n"
    );
    let rows: Vec<Vec<String>> = table3_rows(runs, golden)?
        .list()
        .iter()
        .map(|row| {
            let (pw, sw, g) = (&row.pw, &row.sw, row.paper);
            let in_band = |inside: bool| if inside { "yes" } else { "no" };
            vec![
                format!("{}", row.case.clearance_mm),
                format!("{}", row.case.speed_rpm),
                g.motion.clone(),
                format!("{} of {n}", row.continuous),
                format!("{:.4}", g.pw),
                pw.mean_sd(1.0, 4),
                in_band(row.paper_pw_in_band()).into(),
                format!("{:.4}", g.sw),
                sw.mean_sd(1.0, 4),
                in_band(row.paper_sw_in_band()).into(),
                format!(
                    "{}; ours: P-w in {} of {n}",
                    g.dominant(),
                    row.pressure_dominated
                ),
                format!(
                    "{} % / {}",
                    row.contact_fraction.mean_sd(100.0, 1),
                    row.impacts_per_rotation.mean_sd(1.0, 1)
                ),
            ]
        })
        .collect();
    md_table(
        md,
        &[
            "c (mm)",
            "r/min",
            "paper motion",
            "our members in continuous contact",
            "paper P-w",
            "our P-w",
            "in band",
            "paper s-w",
            "our s-w",
            "in band",
            "larger: paper; ours",
            "in contact / onsets per rotation",
        ],
        &rows,
    );
    md.push_str("Command: `cargo run --release --bin table3`. Data: `data/table3.csv`.\n\n");
    md.push_str("Where the model departs from the paper, and why (`data/golden/paper.toml`):\n\n");
    for (case, g) in CASES.zip(&golden.table3).list() {
        if let Some(d) = &g.deviation {
            let (c_mm, rpm) = (case.clearance_mm, case.speed_rpm);
            // what loose integration gives is measured, so it is quoted, not written in the golden file
            let loose = ode45_outcome(accuracy, **case).map_or(String::new(), |o| {
                format!(
                    "; integrated like ode45 at its defaults (section 5, one trajectory's {WINDOWS} windows): {o}"
                )
            });
            let _ = writeln!(md, "- {c_mm} mm, {rpm} r/min: {}{loose}", d.reason);
        }
    }
    if let Some(d) = &golden.standard_wear.deviation {
        let _ = writeln!(
            md,
            "- severe wear regions of the standard case: {}",
            d.reason
        );
    }
    let recorded = EnsembleGolden::load()?;
    let _ = writeln!(
        md,
        "\nThe golden tests (`tests/golden.rs`) hold the model to {} ensemble statistics recorded in \
         `data/golden/ensemble.toml` ({} members, seed {}), each within {}× the standard error of the \
         difference of two ensemble means plus a resolution floor (`src/paper/golden.rs`). Why they were last \
         recorded: {}.\n",
        recorded.quantity.len(),
        recorded.members,
        recorded.seed,
        SIGMAS,
        recorded.reason
    );
    Ok(())
}
