//! Does Table 3 need the scenes' tolerance? The scenes' rtol ([`SCENE`]) is chosen on
//! first-rotation orbit and peak-force errors (the default-tolerance rule over members), while this
//! project's results are ensemble statistics. This study runs Table 3's ensembles (every case,
//! [`DEFAULT_MEMBERS`] members, settled, two rotations recorded) with Dopri5 at each rtol of
//! [`RTOLS`] with the scenes' step control (`atol = 1e-3·rtol`, step cap 1e-3 s, as in the
//! work-precision study) and sets each
//! statistic beside the same ensemble at the scenes' setting. Member `i` starts from the same
//! offsets at every tolerance, so the two ensembles are paired and a mean's change is judged
//! by the spread of the members' own changes `dᵢ = xᵢ − xᵢ,scene`:
//!
//! ```text
//! z = mean(d) / (sd(d) / sqrt(N))
//! ```
//!
//! `z` is Student's t with N − 1 degrees of freedom; over the statistics tested at a tolerance,
//! `|z|` up to [`family_z`] is what sampling alone gives (Bonferroni, 5 % over them). It also
//! counts the members in continuous contact and those whose P-w concordance dominates (Table 3's
//! motion mode and dominance). Writes `data/ensemble_tolerance.csv`; the report's section 5 reads
//! it. The scenes keep their tolerance: this measures what a looser one would change.

use super::integration::Integration;
use super::work_precision::SCENE;
use crate::analysis::significance::student_two_sided_quantile;
use crate::analysis::statistics::Distribution;
use crate::io::output::{read_rows, write_rows};
use crate::io::progress::Progress;
use crate::ode::Method;
use crate::paper::cases::{Need, Runs, SteadyEnsemble, CASES};
use crate::paper::figures::output_path;
use crate::paper::provenance::{self, Inputs};
use crate::simulation::ensemble::{EnsembleSettings, DEFAULT_MEMBERS};
use crate::Result;

/// Dopri5 relative tolerances compared, each with the scenes' step control; the first is the
/// scenes' own setting ([`SCENE`], atol `1e-3·rtol`, step cap 1e-3 s), the one the others are
/// measured against.
pub const RTOLS: [f64; 4] = [SCENE.rtol, 1e-6, 1e-5, 1e-4];

/// File of the study under `data/`.
pub const ENSEMBLE_TOLERANCE_FILE: &str = "ensemble_tolerance.csv";

/// Columns of [`ENSEMBLE_TOLERANCE_FILE`].
pub const ENSEMBLE_TOLERANCE_HEADER: [&str; 13] = [
    "case",
    "rtol",
    "members",
    "continuous_contact_members",
    "pw_dominant_members",
    "pw_mean",
    "pw_se",
    "pw_z",
    "sw_mean",
    "sw_se",
    "sw_z",
    "evaluations_per_member",
    "wall_time_s",
];

/// A concordance's mean over the members at one tolerance, with its paired z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairedMean {
    /// Mean over the members.
    pub mean: f64,
    /// Its standard error, sd/√N.
    pub se: f64,
    /// Paired z of the mean against the scenes' setting (0 for that setting).
    pub z: f64,
}

/// One case at one tolerance: a row of [`ENSEMBLE_TOLERANCE_FILE`].
#[derive(Clone, Debug, PartialEq)]
pub struct ToleranceRow {
    /// Case scene.
    pub case: String,
    /// Dopri5 rtol.
    pub rtol: f64,
    /// Members.
    pub members: usize,
    /// Members in continuous contact.
    pub continuous: usize,
    /// Members whose P-w concordance exceeds their s-w one.
    pub pressure_dominated: usize,
    /// CMF(P, w).
    pub pw: PairedMean,
    /// CMF(s, w).
    pub sw: PairedMean,
    /// Mean right-hand-side evaluations of a member (settling included).
    pub evaluations: f64,
    /// Wall time of all ensembles at this tolerance (s).
    pub wall_time: f64,
}

impl ToleranceRow {
    /// The row as written, in the order of [`ENSEMBLE_TOLERANCE_HEADER`].
    fn fields(&self) -> Vec<String> {
        let (pw, sw) = (self.pw, self.sw);
        vec![
            self.case.clone(),
            format!("{:e}", self.rtol),
            self.members.to_string(),
            self.continuous.to_string(),
            self.pressure_dominated.to_string(),
            format!("{:.7}", pw.mean),
            format!("{:.2e}", pw.se),
            format!("{:.2}", pw.z),
            format!("{:.7}", sw.mean),
            format!("{:.2e}", sw.se),
            format!("{:.2}", sw.z),
            format!("{:.0}", self.evaluations),
            format!("{:.2}", self.wall_time),
        ]
    }

    /// A row as [`ToleranceRow::fields`] wrote it; `None` if a field does not parse.
    fn parse(f: &[String]) -> Option<ToleranceRow> {
        let x = |i: usize| f.get(i)?.parse::<f64>().ok();
        let count = |i: usize| f.get(i)?.parse::<usize>().ok();
        let mean = |i: usize| {
            Some(PairedMean {
                mean: x(i)?,
                se: x(i + 1)?,
                z: x(i + 2)?,
            })
        };
        Some(ToleranceRow {
            case: f.first()?.clone(),
            rtol: x(1)?,
            members: count(2)?,
            continuous: count(3)?,
            pressure_dominated: count(4)?,
            pw: mean(5)?,
            sw: mean(8)?,
            evaluations: x(11)?,
            wall_time: x(12)?,
        })
    }
}

/// The rows an earlier run of the study wrote; `None` if the file is missing or not of this
/// study's columns.
pub fn read_ensemble_tolerance() -> Option<Vec<ToleranceRow>> {
    let (header, rows) = read_rows(&output_path("data", ENSEMBLE_TOLERANCE_FILE)).ok()?;
    if header != ENSEMBLE_TOLERANCE_HEADER {
        return None;
    }
    rows.iter().map(|r| ToleranceRow::parse(r)).collect()
}

/// Largest `|z|` that sampling alone gives to one of `tested` statistics of a tolerance, each
/// a paired mean change over `members` members, with 95 % probability over all of them
/// (Bonferroni): `z` is Student's t with `members − 1` degrees of freedom, and the bound its
/// two-sided quantile of 5 % / `tested` ([`student_two_sided_quantile`]). (It was
/// the normal quantile over ten, 2.81, where eight were tested: with 31 degrees of freedom,
/// 2.93.)
pub fn family_z(tested: usize, members: usize) -> f64 {
    let dof = members.saturating_sub(1).max(1) as f64;
    student_two_sided_quantile(0.05 / tested.max(1) as f64, dof)
}

/// Paired `z` of `values` against `base`, member by member (see the module documentation);
/// NaN with fewer than two members, ±∞ (or 0) when every member changed alike.
fn paired_z(values: &[f64], base: &[f64]) -> f64 {
    let d = Distribution::of(values.iter().zip(base).map(|(v, b)| v - b));
    let se = d.standard_error();
    if d.n < 2 {
        f64::NAN
    } else if se > 0.0 {
        d.mean / se
    } else if d.mean == 0.0 {
        0.0
    } else {
        d.mean.signum() * f64::INFINITY
    }
}

/// What produced `data/ensemble_tolerance.csv` ([`provenance`]): every case scene, the
/// tolerances and the ensembles.
pub const PROVENANCE: provenance::Study = provenance::Study {
    files: &[ENSEMBLE_TOLERANCE_FILE],
    figures: &[],
    command: "cargo run --release --bin ensemble_tolerance",
    rerun_by_all: false,
    variants: &[],
    inputs: |_| {
        Inputs::new(
            CASES.list().map(|c| c.scene).to_vec(),
            false,
            (
                RTOLS,
                SCENE.control,
                DEFAULT_MEMBERS,
                EnsembleSettings::default(),
            ),
        )
    },
};

/// Runs the study, telling `progress` the members finished, and writes its CSV with its record
/// ([`PROVENANCE`]).
pub fn ensemble_tolerance(progress: &dyn Progress) -> Result<Vec<ToleranceRow>> {
    provenance::recorded(&PROVENANCE, &[], || study(progress))
}

/// The study itself ([`ensemble_tolerance`]).
fn study(progress: &dyn Progress) -> Result<Vec<ToleranceRow>> {
    let needs: Vec<Need> = CASES.list().iter().map(|c| Need::Steady(c.scene)).collect();
    let ensemble = EnsembleSettings {
        members: DEFAULT_MEMBERS,
        ..EnsembleSettings::default()
    };
    let mut rows: Vec<ToleranceRow> = Vec::new();
    // Per case, the members' (P-w, s-w) at the scenes' setting, the first tolerance.
    let mut scene_members: Vec<(&str, Vec<f64>, Vec<f64>)> = Vec::new();
    for rtol in RTOLS {
        let integration = Integration::adaptive(Method::Dopri5, rtol).with_control(SCENE.control);
        let runs = Runs::compute(&needs, ensemble, &|f| integration.apply(f), progress)?;
        for case in CASES.list() {
            let e: &SteadyEnsemble = runs.steady(case.scene)?;
            let pw: Vec<f64> = e
                .members
                .iter()
                .map(|m| m.concordance.pressure_wear)
                .collect();
            let sw: Vec<f64> = e
                .members
                .iter()
                .map(|m| m.concordance.sliding_wear)
                .collect();
            let (pw_z, sw_z) = match scene_members.iter().find(|(c, ..)| *c == case.scene) {
                Some((_, pw0, sw0)) => (paired_z(&pw, pw0), paired_z(&sw, sw0)),
                None => (0.0, 0.0),
            };
            let mean = |values: &[f64], z| {
                let d = Distribution::of(values.iter().copied());
                PairedMean {
                    mean: d.mean,
                    se: d.standard_error(),
                    z,
                }
            };
            rows.push(ToleranceRow {
                case: case.scene.to_string(),
                rtol,
                members: e.members.len(),
                continuous: e.continuous(),
                pressure_dominated: e.pressure_dominated(),
                pw: mean(&pw, pw_z),
                sw: mean(&sw, sw_z),
                evaluations: e.stat(|m| m.evaluations as f64).mean,
                wall_time: runs.seconds,
            });
            if rtol == RTOLS[0] {
                scene_members.push((case.scene, pw, sw));
            }
        }
    }
    write_rows(
        &output_path("data", ENSEMBLE_TOLERANCE_FILE),
        &ENSEMBLE_TOLERANCE_HEADER,
        rows.iter().map(ToleranceRow::fields),
    )?;
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Student's two-sided quantiles, computed independently by Simpson's rule on the t density
    /// and bisection: 3.0221 at 5 %/10 with 31 degrees of freedom (ten statistics of 32
    /// members), 2.9338 at 5 %/8; with many degrees of freedom the normal 2.8070 (`statistics.
    /// NormalDist().inv_cdf(1 - 0.0025)` in Python), the bound the study used before.
    #[test]
    fn the_family_bound_is_students_bonferroni_quantile() {
        approx::assert_abs_diff_eq!(family_z(10, 32), 3.0221, epsilon = 1e-4);
        approx::assert_abs_diff_eq!(family_z(8, 32), 2.9338, epsilon = 1e-4);
        approx::assert_abs_diff_eq!(family_z(10, 100_000), 2.8070, epsilon = 1e-3);
    }
    use approx::assert_relative_eq;

    #[test]
    fn rows_read_back_as_written() {
        let mean = |mean, se, z| PairedMean { mean, se, z };
        let row = ToleranceRow {
            case: "standard".into(),
            rtol: 1e-6,
            members: 32,
            continuous: 30,
            pressure_dominated: 1,
            pw: mean(0.25, 1.5e-3, -2.25),
            sw: mean(0.75, 2.5e-4, 1.5),
            evaluations: 98584.0,
            wall_time: 11.25,
        };
        assert_eq!(ToleranceRow::parse(&row.fields()), Some(row.clone()));
        let mut short = row.fields();
        short.pop();
        assert_eq!(ToleranceRow::parse(&short), None);
    }

    #[test]
    fn paired_z_judges_the_members_own_changes() {
        let base = [1.0, 5.0, -3.0, 10.0];
        // Changes 0.1, 0.3 (mean 0.2, sd 0.1155, se 0.0577 over 4): z = 3.46, whatever the
        // spread of the members themselves.
        let values = [1.1, 5.3, -2.9, 10.3];
        assert_relative_eq!(
            paired_z(&values, &base),
            0.2 / ((0.04f64 / 3.0).sqrt() / 2.0),
            max_relative = 1e-9
        );
        assert_eq!(paired_z(&base, &base), 0.0);
        assert_eq!(paired_z(&base.map(|b| b + 1.0), &base), f64::INFINITY);
        assert!(paired_z(&[1.0], &[0.0]).is_nan());
    }
}
