//! How much do the ensembles depend on how members are perturbed? Table 3's ensembles (every
//! case, settled, two recorded rotations) and the standard case's 40-rotation wear run, each
//! run under every protocol of [`PROTOCOLS`] with [`DEFAULT_MEMBERS`] members (seed
//! [`DEFAULT_SEED`]), every statistic set beside the default protocol's:
//!
//! * a mean (deepest wear, largest penetration, the P-w and s-w concordances): pooled, and
//!   within each state where the default ensemble splits into two ([`States`]; the other
//!   protocols' members are assigned by the default's gap midpoint, so a state means the same
//!   under every protocol), each against the default by Welch's t test;
//! * a share (the low state's; the members in continuous contact; those whose P-w concordance
//!   dominates) against the default by Fisher's exact test;
//! * every claim of the report, checked in each member as the report checks it: the members
//!   with each verdict ([`ClaimTally`]), so the report can say which verdicts another protocol
//!   changes. The ensembles are those of the report's figures (`figures::all_needs`).
//!
//! Each p is also Holm-adjusted within its family, one statistic's comparisons under the
//! other protocols ([`SensitivityRow::family_test`]), and a difference is called significant
//! on the adjusted p alone ([`SensitivityRow::differs`]).
//!
//! Members of different protocols are independent draws, so the tests are unpaired. Writes
//! `data/perturbation_sensitivity.csv` ([`PERTURBATION_FILE`]); paper.md's section 2 reads it.
//!
//! [`DEFAULT_MEMBERS`]: crate::simulation::ensemble::DEFAULT_MEMBERS
//! [`DEFAULT_SEED`]: crate::simulation::ensemble::DEFAULT_SEED

use crate::analysis::significance::{adjust_within_families, fisher_two_sided, FamilyTest, Welch};
use crate::analysis::states::States;
use crate::analysis::statistics::Distribution;
use crate::io::output::{read_rows, write_rows};
use crate::io::progress::Progress;
use crate::paper::cases::{Need, Runs, SteadyMember, CASES};
use crate::paper::figures::{all_needs, output_path};
use crate::paper::format::{csv_statistic, parse_adjusted, parse_statistic};
use crate::paper::provenance::{self, Inputs};

use crate::simulation::ensemble::{EnsembleSettings, Perturbation, OFFSET_RADIUS};
use crate::Result;
use std::path::Path;

/// The protocols compared; the first is the default every other is measured against.
pub const PROTOCOLS: [Perturbation; 6] = [
    Perturbation::Disc(OFFSET_RADIUS),
    Perturbation::Disc(1e-9),
    Perturbation::Disc(100e-9),
    Perturbation::Axis(OFFSET_RADIUS),
    Perturbation::Velocity(10e-6),
    Perturbation::Tolerance(1e-3),
];

/// The `case` of the rows that hold a claim's verdicts ([`ClaimTally`]: `quantity` the claim's
/// id, `state` a verdict's label, `count` its members with that verdict).
pub const CLAIMS_CASE: &str = "claims";

/// A claim of the report checked in every member of one protocol's ensembles.
#[derive(Clone, Debug, PartialEq)]
pub struct ClaimTally {
    /// What identifies the claim (`crate::paper::report::Claim::id`).
    pub id: String,
    /// `(verdict label, members with it)` of every verdict.
    pub counts: Vec<(&'static str, usize)>,
    /// Members checked.
    pub members: usize,
}

/// What checks the report's claims in a protocol's ensembles (`paper::report::claim_tallies`,
/// passed in by the study's program so that this module does not depend on the report).
pub type ClaimCheck<'a> = &'a dyn Fn(&Runs) -> Result<Vec<ClaimTally>>;

/// File of the study under `data/`.
pub const PERTURBATION_FILE: &str = "perturbation_sensitivity.csv";

/// Columns of [`PERTURBATION_FILE`]. `p_holm` was added after `p`: a file without it is of
/// another layout and is not read.
pub const PERTURBATION_HEADER: [&str; 14] = [
    "protocol",
    "case",
    "quantity",
    "state",
    "members",
    "count",
    "mean",
    "sd",
    "test",
    "statistic",
    "dof",
    "p",
    "p_holm",
    "wall_time_s",
];

/// A difference from the default protocol is called significant when its Holm-adjusted p
/// ([`SensitivityRow::p_holm`]) is below this: the family-wise error rate of each statistic's
/// comparisons under the other protocols. The study tests about 110 such families (about 550
/// comparisons); decided on the raw p at 0.01, about 5.5 would be called significant by chance
/// alone if no protocol mattered. With Holm a family makes any false call with chance at most
/// 1 %.
pub const SIGNIFICANT_P: f64 = 0.01;

/// One statistic of one protocol: a mean (`count` empty) or a share (`count` of `members`).
#[derive(Clone, Debug, PartialEq)]
pub struct SensitivityRow {
    /// [`Perturbation::key`].
    pub protocol: String,
    /// Case scene.
    pub case: String,
    /// What was measured (SI unit in its name, or a concordance or a share).
    pub quantity: String,
    /// `pooled`, `low` or `high` (a state's members), or `share` (of the low state, or of the
    /// members the quantity names).
    pub state: String,
    /// Members counted.
    pub members: usize,
    /// For a share: how many of `members`.
    pub count: Option<usize>,
    /// Mean over the members (the share itself for a share).
    pub mean: f64,
    /// Sample standard deviation (NaN for a share).
    pub sd: f64,
    /// `welch`, `fisher`, or empty (the default protocol, or no test possible).
    pub test: String,
    /// Welch's t (NaN otherwise).
    pub statistic: f64,
    /// Welch's degrees of freedom (NaN otherwise).
    pub dof: f64,
    /// Two-sided p of the difference from the default (NaN without a test).
    pub p: f64,
    /// `p` Holm-adjusted within its family ([`SensitivityRow::family_test`]; NaN without a
    /// test): what [`SensitivityRow::differs`] decides on.
    pub p_holm: f64,
    /// Wall time of the protocol's ensembles (s).
    pub wall_time_s: f64,
}

impl SensitivityRow {
    /// Whether it differs from the default: Holm-adjusted p below [`SIGNIFICANT_P`].
    pub fn differs(&self) -> bool {
        self.p_holm < SIGNIFICANT_P
    }

    fn fields(&self) -> Vec<String> {
        vec![
            self.protocol.clone(),
            self.case.clone(),
            self.quantity.clone(),
            self.state.clone(),
            self.members.to_string(),
            self.count.map_or(String::new(), |c| c.to_string()),
            csv_statistic(self.mean),
            csv_statistic(self.sd),
            self.test.clone(),
            csv_statistic(self.statistic),
            csv_statistic(self.dof),
            csv_statistic(self.p),
            csv_statistic(self.p_holm),
            format!("{:.1}", self.wall_time_s),
        ]
    }

    fn parse(f: &[String]) -> Option<SensitivityRow> {
        let x = |i: usize| parse_statistic(f.get(i)?);
        Some(SensitivityRow {
            protocol: f.first()?.clone(),
            case: f.get(1)?.clone(),
            quantity: f.get(2)?.clone(),
            state: f.get(3)?.clone(),
            members: f.get(4)?.parse().ok()?,
            count: f.get(5)?.parse().ok(),
            mean: x(6)?,
            sd: x(7)?,
            test: f.get(8)?.clone(),
            statistic: x(9)?,
            dof: x(10)?,
            p: x(11)?,
            p_holm: x(12)?,
            wall_time_s: x(13)?,
        })
    }
}

/// One statistic (case, quantity and state; a claim's verdict) under one protocol other than
/// the default is one comparison of the family of that statistic's comparisons under the
/// other protocols; the default's rows and an undefined test carry none.
impl FamilyTest for SensitivityRow {
    type Family = (String, String, String);
    fn family_test(&self) -> Option<(Self::Family, f64)> {
        let family = (self.case.clone(), self.quantity.clone(), self.state.clone());
        (!self.test.is_empty()).then_some((family, self.p))
    }
    fn adjusted_p(&self) -> f64 {
        self.p_holm
    }
    fn set_adjusted_p(&mut self, p: f64) {
        self.p_holm = p;
    }
}

/// The rows of `data/perturbation_sensitivity.csv`; `None` when it is missing, of another
/// layout (a file written before `p_holm`, whose 13 columns would shift), or when a `p_holm`
/// is not the Holm adjustment of its family's raw p ([`parse_adjusted`]).
pub fn read_perturbation() -> Option<Vec<SensitivityRow>> {
    read_perturbation_at(&output_path("data", PERTURBATION_FILE))
}

/// The rows of the study's CSV at `path`, as [`read_perturbation`] reads them.
pub fn read_perturbation_at(path: &Path) -> Option<Vec<SensitivityRow>> {
    parse_adjusted(
        read_rows(path).ok()?,
        &PERTURBATION_HEADER,
        SensitivityRow::parse,
    )
}

/// The members' values of every statistic of one protocol: `(case, quantity, values)` for
/// means, `(case, quantity, count, members)` for shares.
struct Measured {
    means: Vec<(&'static str, &'static str, Vec<f64>)>,
    shares: Vec<(&'static str, &'static str, usize, usize)>,
    /// Every claim of the report checked in these members.
    claims: Vec<ClaimTally>,
    seconds: f64,
}

fn measure(runs: &Runs, check: ClaimCheck) -> Result<Measured> {
    let mut means = Vec::new();
    let mut shares = Vec::new();
    for case in CASES.list() {
        let e = runs.steady(case.scene)?;
        let of = |f: &dyn Fn(&SteadyMember) -> f64| e.members.iter().map(f).collect::<Vec<f64>>();
        means.push((
            case.scene,
            "max_penetration_recorded_m",
            of(&|m| m.max_penetration),
        ));
        means.push((
            case.scene,
            "pw_concordance",
            of(&|m| m.concordance.pressure_wear),
        ));
        means.push((
            case.scene,
            "sw_concordance",
            of(&|m| m.concordance.sliding_wear),
        ));
        let n = e.members.len();
        shares.push((case.scene, "continuous_contact", e.continuous(), n));
        shares.push((case.scene, "pw_dominant", e.pressure_dominated(), n));
    }
    let wear = runs.wear(CASES.standard.scene)?;
    means.push((
        CASES.standard.scene,
        "deepest_wear_m",
        wear.members.iter().map(|m| m.max_depth()).collect(),
    ));
    let claims = check(runs)?;
    Ok(Measured {
        means,
        shares,
        claims,
        seconds: runs.seconds,
    })
}

/// The rows of one protocol against the default's measurement (`base`; `None` for the default
/// itself).
fn rows_of(
    protocol: &Perturbation,
    m: &Measured,
    base: Option<&Measured>,
    split_at: &[(&str, &str, Option<f64>)],
) -> Vec<SensitivityRow> {
    let row = |case: &str, quantity: &str, state: &str| SensitivityRow {
        protocol: protocol.key(),
        case: case.to_string(),
        quantity: quantity.to_string(),
        state: state.to_string(),
        members: 0,
        count: None,
        mean: f64::NAN,
        sd: f64::NAN,
        test: String::new(),
        statistic: f64::NAN,
        dof: f64::NAN,
        p: f64::NAN,
        p_holm: f64::NAN,
        wall_time_s: m.seconds,
    };
    let mean_row =
        |case: &str, quantity: &str, state: &str, d: Distribution, b: Option<Distribution>| {
            let mut r = row(case, quantity, state);
            (r.members, r.mean, r.sd) = (d.n, d.mean, d.sd);
            if let Some(w) = b.and_then(|b| Welch::of(&d, &b)) {
                (r.test, r.statistic, r.dof, r.p) = ("welch".into(), w.t, w.dof, w.p);
            }
            r
        };
    let share_row = |case: &str, quantity: &str, k: usize, n: usize, b: Option<(usize, usize)>| {
        let mut r = row(case, quantity, "share");
        (r.members, r.count, r.mean) = (n, Some(k), k as f64 / n.max(1) as f64);
        if let Some((kb, nb)) = b {
            (r.test, r.p) = ("fisher".into(), fisher_two_sided(k, n, kb, nb));
        }
        r
    };
    let mut rows = Vec::new();
    for (i, (case, quantity, values)) in m.means.iter().enumerate() {
        let base_values = base.map(|b| &b.means[i].2);
        let pooled = |v: &[f64]| Distribution::of(v.iter().copied());
        rows.push(mean_row(
            case,
            quantity,
            "pooled",
            pooled(values),
            base_values.map(|v| pooled(v)),
        ));
        let Some(threshold) = split_at[i].2 else {
            continue;
        };
        let part = |v: &[f64], low: bool| {
            Distribution::of(v.iter().copied().filter(|x| (*x < threshold) == low))
        };
        for (state, low) in [("low", true), ("high", false)] {
            rows.push(mean_row(
                case,
                quantity,
                state,
                part(values, low),
                base_values.map(|v| part(v, low)),
            ));
        }
        let low = |v: &[f64]| v.iter().filter(|x| **x < threshold).count();
        rows.push(share_row(
            case,
            &format!("{quantity}.low_state"),
            low(values),
            values.len(),
            base_values.map(|v| (low(v), v.len())),
        ));
    }
    for (i, &(case, quantity, count, n)) in m.shares.iter().enumerate() {
        let b = base.map(|b| (b.shares[i].2, b.shares[i].3));
        rows.push(share_row(case, quantity, count, n, b));
    }
    for (i, claim) in m.claims.iter().enumerate() {
        for (k, &(verdict, count)) in claim.counts.iter().enumerate() {
            let b = base.map(|b| (b.claims[i].counts[k].1, b.claims[i].members));
            let mut r = share_row(CLAIMS_CASE, &claim.id, count, claim.members, b);
            r.state = verdict.into();
            rows.push(r);
        }
    }
    rows
}

/// What produced `data/perturbation_sensitivity.csv` ([`provenance`]): the scenes of the
/// report's ensembles and the paper's values (its claims are checked per member), the
/// ensembles and the protocols.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[PERTURBATION_FILE],
    figures: &[],
    command: "cargo run --release --bin perturbation",
    rerun_by_all: false,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            all_needs().iter().map(Need::scene).collect(),
            true,
            (PROTOCOLS, all_needs(), EnsembleSettings::default()),
        )
    },
};

/// Runs the study ([`PROTOCOLS`], module documentation), checks the report's claims in each
/// protocol's members with `check`, writes `data/perturbation_sensitivity.csv` with its
/// record ([`PROVENANCE`]) and returns its rows; `progress` counts members.
pub fn perturbation_study(
    check: ClaimCheck,
    progress: &dyn Progress,
) -> Result<Vec<SensitivityRow>> {
    provenance::recorded(&PROVENANCE, &[], || study(check, progress))
}

/// The study itself ([`perturbation_study`]).
fn study(check: ClaimCheck, progress: &dyn Progress) -> Result<Vec<SensitivityRow>> {
    // every ensemble the report's figures and claims read, so every claim can be checked
    let needs = all_needs();
    let measured = PROTOCOLS
        .iter()
        .map(|&perturbation| {
            let ensemble = EnsembleSettings {
                perturbation,
                ..EnsembleSettings::default()
            };
            measure(&Runs::compute(&needs, ensemble, &|_| {}, progress)?, check)
        })
        .collect::<Result<Vec<Measured>>>()?;
    let base = &measured[0];
    // the default's states, as thresholds every protocol's members are assigned by
    let split_at: Vec<(&str, &str, Option<f64>)> = base
        .means
        .iter()
        .map(|(case, quantity, v)| {
            let threshold = States::of(v)
                .low_high()
                .map(|(low, high)| 0.5 * (low.distribution.max + high.distribution.min));
            (*case, *quantity, threshold)
        })
        .collect();
    let mut rows: Vec<SensitivityRow> = PROTOCOLS
        .iter()
        .zip(&measured)
        .enumerate()
        .flat_map(|(i, (p, m))| rows_of(p, m, (i > 0).then_some(base), &split_at))
        .collect();
    adjust_within_families(&mut rows);
    write_rows(
        &output_path("data", PERTURBATION_FILE),
        &PERTURBATION_HEADER,
        rows.iter().map(SensitivityRow::fields),
    )?;
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_through_their_fields() {
        let r = SensitivityRow {
            protocol: "axis_10nm".into(),
            case: "standard".into(),
            quantity: "deepest_wear_m.low_state".into(),
            state: "share".into(),
            members: 32,
            count: Some(5),
            mean: 5.0 / 32.0,
            sd: f64::NAN,
            test: "fisher".into(),
            statistic: f64::NAN,
            dof: f64::NAN,
            p: 0.0123,
            p_holm: 0.0246,
            wall_time_s: 41.0,
        };
        let back = SensitivityRow::parse(&r.fields()).unwrap();
        assert_eq!(back.count, Some(5));
        assert_eq!(back.quantity, r.quantity);
        assert!(back.sd.is_nan() && back.statistic.is_nan());
        assert!((back.p - 0.0123).abs() < 1e-9 && !back.differs());
        assert_eq!(PERTURBATION_HEADER.len(), r.fields().len());
    }

    /// A file written before `p_holm` (13 columns) is refused, not read with its wall time as
    /// the adjusted p; so is one whose adjusted p is not its raw p's. Checked to fail when the
    /// file is read without the recheck.
    #[test]
    fn a_file_without_the_adjusted_p_or_with_another_is_refused() {
        let text = std::fs::read_to_string(output_path("data", PERTURBATION_FILE)).unwrap();
        crate::test_support::assert_refuses_stale_adjusted(
            "perturbation",
            &text,
            &PERTURBATION_HEADER,
            read_perturbation_at,
        );
    }

    /// A family is one statistic (case, quantity, state; a claim's verdict) under the other
    /// protocols: the default's rows keep NaN, and the same p of another state is adjusted
    /// apart. Raw 0.00315 among five protocols (the committed `disc_100nm` deepest wear) is
    /// 5 × 0.00315 = 0.01575 adjusted: not significant. Checked to fail deciding on the raw p.
    #[test]
    fn a_difference_at_the_raw_p_alone_is_not_significant() {
        let row = |protocol: usize, state: &str, p: f64| SensitivityRow {
            protocol: PROTOCOLS[protocol].key(),
            case: "standard".into(),
            quantity: "deepest_wear_m".into(),
            state: state.into(),
            members: 32,
            count: None,
            mean: 1.0,
            sd: 0.1,
            test: if protocol == 0 { "" } else { "welch" }.into(),
            statistic: f64::NAN,
            dof: f64::NAN,
            p: if protocol == 0 { f64::NAN } else { p },
            p_holm: f64::NAN,
            wall_time_s: 1.0,
        };
        let raw = [f64::NAN, 0.00315, 0.2, 0.5, 0.6, 0.9];
        let mut rows: Vec<SensitivityRow> = (0..6).map(|i| row(i, "pooled", raw[i])).collect();
        rows.extend((0..6).map(|i| row(i, "low", raw[i])));
        adjust_within_families(&mut rows);
        assert!(rows[0].p_holm.is_nan() && rows[6].p_holm.is_nan());
        for r in [&rows[1], &rows[7]] {
            approx::assert_relative_eq!(r.p_holm, 5.0 * 0.00315, max_relative = 1e-12);
            assert!(r.p < SIGNIFICANT_P && !r.differs(), "{r:?}");
        }
        // one protocol's smaller p is significant after the adjustment too
        rows[2].p = 0.001;
        adjust_within_families(&mut rows);
        approx::assert_relative_eq!(rows[2].p_holm, 0.005, max_relative = 1e-12);
        assert!(rows[2].differs() && !rows[1].differs());
    }
}
