//! How ensemble statistics settle with the number of members, and the choice of the default.
//!
//! One ensemble of [`MAX_MEMBERS`] members of every Table 3 case (steady runs) and of the
//! standard wear case is run; its first `N` members, for `N` in [`SIZES`], stand for an
//! ensemble of `N`. For every golden quantity ([`crate::paper::golden::measure`]) the study records
//! the mean and its standard error `sd/√N`; for the standard wear profile, the RMS distance of
//! the `N`-member mean profile from the full ensemble's and the mean width of the 5-95 % band.
//!
//! Rule for the default size: the smallest `N` of [`SIZES`] at which the standard error of
//! every Table 3 concordance is at most [`SE_SHARE`] of the concordance tolerance and that
//! of every severe-region angle at most [`SE_SHARE`] of the angle tolerance (both from the
//! golden data), so that the comparison with the paper is decided by the physics, not by
//! which members were drawn.

use crate::analysis::statistics::{Band, Distribution};
use crate::io::output::write_csv;
use crate::io::plot::{render, Axes, Series, Style};
use crate::io::progress::Progress;
use crate::paper::cases::{Need, Runs, CASES};
use crate::paper::figures::output_path;
use crate::paper::golden::{measure, Golden, Quantity, SteadyQuantity, GOLDEN_NEEDS};
use crate::paper::provenance::{self, Inputs};
use crate::simulation::ensemble::EnsembleSettings;
use crate::Result;

/// Members of the study's ensemble.
pub const MAX_MEMBERS: usize = 64;
/// Ensemble sizes compared.
pub const SIZES: [usize; 5] = [4, 8, 16, 32, 64];
/// The rule's largest standard error of a quantity, as a share of the tolerance within which
/// the report compares it with the paper's: a fifth.
pub const SE_SHARE: f64 = 0.2;

/// One quantity at one ensemble size.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceRow {
    /// The golden quantity.
    pub quantity: Quantity,
    /// Members.
    pub members: usize,
    /// Mean over the first `members` members.
    pub mean: f64,
    /// Its standard error.
    pub standard_error: f64,
}

/// What the study found.
#[derive(Clone, Debug, PartialEq)]
pub struct Convergence {
    /// Every golden quantity at every size.
    pub rows: Vec<ConvergenceRow>,
    /// `(members, RMS distance of the mean wear profile from the full ensemble's over the
    /// deepest mean wear, mean 5-95 % band width over the deepest mean wear)`.
    pub profile: Vec<(usize, f64, f64)>,
    /// The size the rule picks.
    pub chosen: Option<usize>,
}

/// Whether the rule is met by the rows of one size.
fn meets_rule(rows: &[&ConvergenceRow], golden: &Golden) -> bool {
    rows.iter().all(|r| {
        let bound = if r.quantity.is_concordance() {
            golden.concordance_tolerance * SE_SHARE
        } else if r.quantity.is_angle() {
            golden.standard_wear.angle_tolerance_deg * SE_SHARE
        } else {
            return true;
        };
        r.standard_error <= bound
    })
}

/// The study's table under `data/`.
pub const CONVERGENCE_FILE: &str = "ensemble_convergence.csv";

/// The study's figure under `figures/`.
const CONVERGENCE_FIGURE: &str = "ensemble_convergence.png";

/// What produced `data/ensemble_convergence.csv` ([`provenance`]): the golden ensembles'
/// scenes, the paper's tolerances the rule is stated against, the sizes and the ensemble.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[CONVERGENCE_FILE],
    figures: &[CONVERGENCE_FIGURE],
    command: "cargo run --release --bin convergence",
    rerun_by_all: true,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            GOLDEN_NEEDS.iter().map(Need::scene).collect(),
            true,
            (
                (MAX_MEMBERS, SIZES, SE_SHARE),
                GOLDEN_NEEDS,
                EnsembleSettings::default(),
            ),
        )
    },
};

/// Runs the study and writes `data/ensemble_convergence.csv` and
/// `figures/ensemble_convergence.png`, and the CSV's record ([`PROVENANCE`]); `progress`
/// counts members.
pub fn convergence_study(progress: &dyn Progress) -> Result<Convergence> {
    provenance::recorded(&PROVENANCE, &[], || study(progress))
}

/// The study itself ([`convergence_study`]).
fn study(progress: &dyn Progress) -> Result<Convergence> {
    let golden = Golden::load()?;
    let ensemble = EnsembleSettings {
        members: MAX_MEMBERS,
        ..EnsembleSettings::default()
    };
    let runs = Runs::compute(&GOLDEN_NEEDS, ensemble, &|_| {}, progress)?;
    let mut rows = Vec::new();
    let mut profile = Vec::new();
    let wear = runs.wear(&golden.standard_wear.scene)?;
    let full = wear.band().mean();
    let top = full.iter().cloned().fold(0.0, f64::max);
    for &n in &SIZES {
        let sub = runs.first_members(n);
        for m in measure(&sub, &golden)? {
            rows.push(ConvergenceRow {
                quantity: m.quantity,
                members: n,
                mean: m.distribution.mean,
                standard_error: m.distribution.standard_error(),
            });
        }
        let band = Band::of(wear.members[..n].iter().map(|m| m.final_wear.as_slice()));
        let rms = (band
            .mean()
            .iter()
            .zip(&full)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            / full.len() as f64)
            .sqrt();
        let width = Distribution::of(band.sectors.iter().map(|d| d.quantiles[4] - d.quantiles[0]));
        profile.push((n, rms / top, width.mean / top));
    }
    let chosen = SIZES.iter().copied().find(|&n| {
        let of_n: Vec<&ConvergenceRow> = rows.iter().filter(|r| r.members == n).collect();
        meets_rule(&of_n, &golden)
    });
    let study = Convergence {
        rows,
        profile,
        chosen,
    };
    write_convergence(&study)?;
    Ok(study)
}

fn write_convergence(c: &Convergence) -> Result<()> {
    let quantities: Vec<Quantity> = c
        .rows
        .iter()
        .filter(|r| r.members == SIZES[0])
        .map(|r| r.quantity)
        .collect();
    let mut header = vec!["members".to_string()];
    let mut cols: Vec<Vec<f64>> = vec![SIZES.iter().map(|&n| n as f64).collect()];
    for q in &quantities {
        for (what, pick) in [
            (
                "mean",
                (|r: &ConvergenceRow| r.mean) as fn(&ConvergenceRow) -> f64,
            ),
            ("se", |r: &ConvergenceRow| r.standard_error),
        ] {
            header.push(format!("{}.{what}", q.name()));
            cols.push(
                SIZES
                    .iter()
                    .map(|&n| {
                        c.rows
                            .iter()
                            .find(|r| r.members == n && r.quantity == *q)
                            .map_or(f64::NAN, pick)
                    })
                    .collect(),
            );
        }
    }
    header.push("standard.mean_profile_rms_rel".into());
    cols.push(c.profile.iter().map(|p| p.1).collect());
    header.push("standard.band_width_rel".into());
    cols.push(c.profile.iter().map(|p| p.2).collect());
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    write_csv(&output_path("data", CONVERGENCE_FILE), &h, &refs)?;

    let x: Vec<f64> = SIZES.iter().map(|&n| n as f64).collect();
    let shown = [
        (CASES.standard, SteadyQuantity::Pw),
        (CASES.standard, SteadyQuantity::Sw),
        (CASES.clearance_0_2mm, SteadyQuantity::Sw),
        (CASES.clearance_0_5mm, SteadyQuantity::Pw),
        (CASES.clearance_0_5mm, SteadyQuantity::Sw),
    ]
    .map(|(case, q)| Quantity::Steady(case, q));
    let se: Vec<(String, Vec<f64>)> = shown
        .iter()
        .map(|q| {
            let v = SIZES
                .iter()
                .map(|&n| {
                    c.rows
                        .iter()
                        .find(|r| r.members == n && r.quantity == *q)
                        .map_or(f64::NAN, |r| r.standard_error.max(1e-12))
                })
                .collect();
            (format!("{} (concordance)", q.name()), v)
        })
        .collect();
    let ctol = Golden::load()?.concordance_tolerance;
    let tolerance = vec![ctol * SE_SHARE; SIZES.len()];
    let mut series: Vec<Series> = se
        .iter()
        .map(|(l, v)| Series::new(l.clone(), &x, v, Style::LinePoints))
        .collect();
    series.push(Series::new(
        format!("rule: {SE_SHARE} × the {ctol} tolerance"),
        &x,
        &tolerance,
        Style::Reference,
    ));
    // the full ensemble is the reference of the distance: it is left out of that curve
    let partial = &x[..x.len() - 1];
    let rms: Vec<f64> = c.profile[..partial.len()].iter().map(|p| p.1).collect();
    let width: Vec<f64> = c.profile.iter().map(|p| p.2).collect();
    fn log_log(a: Axes) -> Axes {
        Axes {
            x_log: true,
            y_log: true,
            ..a
        }
    }
    let panels = [
        log_log(Axes::new(
            "Standard error of the ensemble mean",
            "members",
            "standard error",
            series,
        )),
        log_log(Axes::new(
            "Standard wear profile (0.02 mm, 2000 r/min)",
            "members",
            "value / deepest mean wear",
            vec![
                Series::new(
                    format!("RMS distance of the mean profile from the {MAX_MEMBERS}-member one"),
                    partial,
                    &rms,
                    Style::LinePoints,
                ),
                Series::new(
                    "mean width of the 5-95 % band",
                    &x,
                    &width,
                    Style::LinePoints,
                ),
            ],
        )),
    ];
    render(&output_path("figures", CONVERGENCE_FIGURE), &panels)
}
