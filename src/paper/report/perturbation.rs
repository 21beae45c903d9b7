//! How much the ensembles depend on the perturbation protocol (section 2 of `paper.md`), from
//! `data/perturbation_sensitivity.csv` ([`crate::paper::perturbation`]): every sentence is
//! computed from the file's rows.

use super::markdown::md_table;
use crate::paper::format::{sci, sig};
use crate::paper::perturbation::{read_perturbation, SensitivityRow, PROTOCOLS, SIGNIFICANT_P};
use std::fmt::Write as _;

/// A row's value as the table shows it: `7/32` for a share, the mean otherwise; `*` marks a
/// difference from the default at [`SIGNIFICANT_P`], with its p.
fn cell(r: &SensitivityRow) -> String {
    let value = match r.count {
        Some(k) => format!("{k}/{}", r.members),
        None if r.members == 0 => "none".into(),
        None => sci(r.mean),
    };
    match (r.test.is_empty(), r.differs()) {
        (true, _) => value,
        (false, true) => format!("**{value}** (p {})", sci(r.p)),
        (false, false) => format!("{value} (p {})", sig(r.p)),
    }
}

/// The section: the protocols, a table of every statistic under each, and which statistics
/// are robust to the protocol and which are not.
pub(super) fn perturbation_section() -> String {
    let mut md = String::from("### How much the ensembles depend on the perturbation\n\n");
    let protocols: Vec<String> = PROTOCOLS
        .iter()
        .map(|p| format!("`{}` ({})", p.key(), p.describe()))
        .collect();
    let _ = writeln!(
        md,
        "Every ensemble statistic is a property of the model *and* of how its members are perturbed. The \
         perturbation study (`cargo run --release --bin perturbation`, `src/paper/perturbation.rs`) runs \
         Table 3's ensembles and the standard case's wear run under {} protocols: {}. The first is the \
         default. Where the default's members of a statistic fall into two states (largest-gap rule, \
         `src/analysis/states.rs`), every protocol's members are assigned to them by the default's gap, and \
         each state's mean and the low state's share are compared too. A mean is compared with the \
         default's by Welch's t test, a share by Fisher's exact test; p below {SIGNIFICANT_P} is bold.\n",
        PROTOCOLS.len(),
        protocols.join("; ")
    );
    let Some(rows) = read_perturbation() else {
        md.push_str("*`data/perturbation_sensitivity.csv` is missing: run `cargo run --release --bin perturbation`.*\n\n");
        return md;
    };
    let default = PROTOCOLS[0].key();
    let base: Vec<&SensitivityRow> = rows.iter().filter(|r| r.protocol == default).collect();
    let others: Vec<String> = PROTOCOLS[1..].iter().map(|p| p.key()).collect();
    let same = |a: &SensitivityRow, b: &SensitivityRow| {
        (a.case == b.case) && (a.quantity == b.quantity) && (a.state == b.state)
    };
    let mut header = vec!["case", "quantity", "state", default.as_str()];
    header.extend(others.iter().map(String::as_str));
    let table: Vec<Vec<String>> = base
        .iter()
        .map(|b| {
            let mut row = vec![b.case.clone(), b.quantity.clone(), b.state.clone(), cell(b)];
            row.extend(others.iter().map(|p| {
                rows.iter()
                    .find(|r| r.protocol == *p && same(r, b))
                    .map_or(String::new(), cell)
            }));
            row
        })
        .collect();
    md_table(&mut md, &header, &table);
    // the standard case's wear states under the default
    let wear = |state: &str| {
        base.iter().find(|r| {
            r.case == "standard" && r.quantity.starts_with("deepest_wear_m") && r.state == state
        })
    };
    if let (Some(pooled), Some(low), Some(high)) = (wear("pooled"), wear("low"), wear("high")) {
        let _ = write!(
            md,
            "Under the default the standard case's members end their wear run in two wear states: {} of \
             {} in a low state (deepest wear {} ± {} µm) and {} in a high one ({} ± {} µm); the pooled {} µm \
             is their share-weighted mean, so it moves with the share in each. ",
            low.members,
            pooled.members,
            sig(low.mean * 1e6),
            sig(low.sd * 1e6),
            high.members,
            sig(high.mean * 1e6),
            sig(high.sd * 1e6),
            sig(pooled.mean * 1e6)
        );
    }
    let tested: Vec<&SensitivityRow> = rows.iter().filter(|r| !r.test.is_empty()).collect();
    let differing: Vec<&SensitivityRow> = tested.iter().copied().filter(|r| r.differs()).collect();
    let _ = write!(
        md,
        "Of {} comparisons with the default, {} differ at p < {SIGNIFICANT_P} (about {} would by chance \
         alone). ",
        tested.len(),
        differing.len(),
        sig(tested.len() as f64 * SIGNIFICANT_P)
    );
    let robust = base
        .iter()
        .filter(|b| !differing.iter().any(|r| same(r, b)))
        .count();
    let _ = write!(
        md,
        "{robust} of the {} statistics differ from the default under no protocol: robust to the perturbation \
         at this ensemble size. ",
        base.len()
    );
    if !differing.is_empty() {
        let list: Vec<String> = differing
            .iter()
            .map(|r| {
                let why = match (r.state.as_str(), r.protocol.starts_with("tolerance")) {
                    ("share", _) => "which state the members reach depends on the perturbation",
                    (_, true) => {
                        "its members all start from the centred journal and differ by their step \
                                  sequences only, so they sample the state differently"
                    }
                    ("pooled", false) => {
                        "the pooled mean moves with the members' spread over the states"
                    }
                    _ => "the state itself is sampled differently",
                };
                format!(
                    "{} {} ({}) under `{}`: {} against {} (p {}): {why}",
                    r.case,
                    r.quantity,
                    r.state,
                    r.protocol,
                    sci(r.mean),
                    base.iter()
                        .find(|b| same(b, r))
                        .map_or(String::new(), |b| sci(b.mean)),
                    sci(r.p)
                )
            })
            .collect();
        let _ = write!(md, "Not robust: {}. ", list.join("; "));
    }
    md.push_str(
        "A statistic that differs under a protocol is a property of that protocol's ensemble as much as of \
         the model; one that does not is, at this ensemble size, a property of the model.\n\n",
    );
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_section_reads_the_committed_study_without_nan() {
        let md = perturbation_section();
        println!("{md}");
        assert!(read_perturbation().is_some(), "the committed CSV parses");
        assert!(md.contains("| case | quantity | state |"), "{md}");
        assert!(md.contains("differ from the default under no protocol"));
        assert!(!md.contains("NaN") && !md.contains("missing"), "{md}");
    }
}
