//! Does Table 3 need the scenes' tolerance? The scenes' rtol 1e-7 is chosen on single
//! trajectories (the work-precision study's first-rotation orbit and peak force), while this
//! project's results are ensemble statistics. This study runs Table 3's ensembles (every case,
//! [`DEFAULT_MEMBERS`] members, settled, two rotations recorded) with Dopri5 at each rtol of
//! [`RTOLS`] (`atol = 1e-3·rtol`, step cap 1e-3 s, as in the work-precision study) and sets each
//! statistic beside the same ensemble at the scenes' setting, in units of their joint standard
//! error:
//!
//! ```text
//! z = (mean − mean_scene) / sqrt(se² + se_scene²),   se = sd / sqrt(N)
//! ```
//!
//! `|z|` below about 2 cannot be told from the scene setting with these members. It also
//! counts the members in continuous contact and those whose P-w concordance dominates (Table 3's
//! motion mode and dominance). Writes `data/ensemble_tolerance.csv`; the report's section 5 reads
//! it. The scenes keep their tolerance: this measures what a looser one would change.

use super::integration::Integration;
use crate::analysis::statistics::Distribution;
use crate::io::output::write_rows;
use crate::io::progress::Progress;
use crate::ode::Method;
use crate::paper::cases::{Need, Runs, SteadyEnsemble, CASES};
use crate::paper::figures::output_path;
use crate::simulation::ensemble::{EnsembleSettings, DEFAULT_MEMBERS};
use crate::Result;

/// Dopri5 relative tolerances compared; the first is the scenes' own setting (rtol 1e-7,
/// atol 1e-10, step cap 1e-3 s), the one the others are measured against.
pub const RTOLS: [f64; 4] = [1e-7, 1e-6, 1e-5, 1e-4];

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

/// One case at one tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct ToleranceRow {
    /// Case scene.
    pub case: &'static str,
    /// Dopri5 rtol.
    pub rtol: f64,
    /// Members.
    pub members: usize,
    /// Members in continuous contact.
    pub continuous: usize,
    /// Members whose P-w concordance exceeds their s-w one.
    pub pressure_dominated: usize,
    /// CMF(P, w) over the members.
    pub pw: Distribution,
    /// CMF(s, w) over the members.
    pub sw: Distribution,
    /// z of the P-w mean against the scenes' setting (0 for that setting).
    pub pw_z: f64,
    /// z of the s-w mean against the scenes' setting.
    pub sw_z: f64,
    /// Mean right-hand-side evaluations of a member (settling included).
    pub evaluations: f64,
    /// Wall time of all ensembles at this tolerance (s).
    pub wall_time: f64,
}

/// `z` of two means in units of their joint standard error; 0 when both are exact.
fn z(a: &Distribution, b: &Distribution) -> f64 {
    let se = a.standard_error().hypot(b.standard_error());
    if se > 0.0 {
        (a.mean - b.mean) / se
    } else {
        0.0
    }
}

/// Runs the study, telling `progress` the members finished, and writes its CSV.
pub fn ensemble_tolerance(progress: &dyn Progress) -> Result<Vec<ToleranceRow>> {
    let needs: Vec<Need> = CASES.list().iter().map(|c| Need::Steady(c.scene)).collect();
    let ensemble = EnsembleSettings {
        members: DEFAULT_MEMBERS,
        ..EnsembleSettings::default()
    };
    let mut rows: Vec<ToleranceRow> = Vec::new();
    for rtol in RTOLS {
        let integration = Integration::adaptive(Method::Dopri5, rtol);
        let runs = Runs::compute(&needs, ensemble, &|f| integration.apply(f), progress)?;
        for case in CASES.list() {
            let e: &SteadyEnsemble = runs.steady(case.scene)?;
            let pw = e.stat(|m| m.concordance.pressure_wear);
            let sw = e.stat(|m| m.concordance.sliding_wear);
            let scene_row = rows.iter().find(|r| r.case == case.scene);
            rows.push(ToleranceRow {
                case: case.scene,
                rtol,
                members: e.members.len(),
                continuous: e.continuous(),
                pressure_dominated: e.pressure_dominated(),
                pw_z: scene_row.map_or(0.0, |r| z(&pw, &r.pw)),
                sw_z: scene_row.map_or(0.0, |r| z(&sw, &r.sw)),
                pw,
                sw,
                evaluations: e.stat(|m| m.evaluations as f64).mean,
                wall_time: runs.seconds,
            });
        }
    }
    write_rows(
        &output_path("data", ENSEMBLE_TOLERANCE_FILE),
        &ENSEMBLE_TOLERANCE_HEADER,
        rows.iter().map(|r| {
            vec![
                r.case.to_string(),
                format!("{:e}", r.rtol),
                r.members.to_string(),
                r.continuous.to_string(),
                r.pressure_dominated.to_string(),
                format!("{:.7}", r.pw.mean),
                format!("{:.2e}", r.pw.standard_error()),
                format!("{:.2}", r.pw_z),
                format!("{:.7}", r.sw.mean),
                format!("{:.2e}", r.sw.standard_error()),
                format!("{:.2}", r.sw_z),
                format!("{:.0}", r.evaluations),
                format!("{:.2}", r.wall_time),
            ]
        }),
    )?;
    Ok(rows)
}
