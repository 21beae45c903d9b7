//! Golden data: the paper's numbers (`data/golden/paper.toml`, written by hand from the paper)
//! and the model's recorded ensemble statistics (`data/golden/ensemble.toml`, written by
//! `cargo run --release --bin golden_record`).
//!
//! A chaotic model cannot be held to one trajectory's numbers, so the golden tests hold it to
//! statistics: for each quantity, the mean over an ensemble must agree with the recorded mean
//! within
//!
//! ```text
//! |mean − mean_rec| ≤ SIGMAS · sqrt(sd² + sd_rec²) / sqrt(N) + floor
//! ```
//!
//! the sampling error of the difference of two ensemble means, plus a floor for quantities whose
//! members agree to rounding (non-chaotic cases), set at the resolution the quantity is read
//! with. A change of rounding, seed or thread count leaves the statistics inside that bound; a
//! change of physics moves them out (`tests/golden.rs` shows both).

use crate::analysis::CONTINUOUS_CONTACT_FRACTION;
use crate::runs::{Need, Runs, CASES};
use crate::statistics::Distribution;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Path of the paper's golden file.
pub fn golden_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/paper.toml")
}

/// Path of the recorded ensemble statistics.
pub fn ensemble_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/ensemble.toml")
}

/// The paper's golden numbers.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Golden {
    /// Severe wear regions of the standard case (figures 5-7).
    pub standard_wear: PeakClaim,
    /// Wear location at 30 r/min (figure 14).
    pub low_speed_wear: PeakClaim,
    /// Tolerance on concordance values.
    pub concordance_tolerance: f64,
    /// Why that tolerance.
    pub concordance_tolerance_reason: String,
    /// Table 3, in the paper's order (that of [`CASES`]).
    pub table3: Vec<Table3Golden>,
}

/// Severe wear regions claimed for a case after its 40 rotations.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeakClaim {
    /// Scene of the case.
    pub scene: String,
    /// Angles of the severe regions (deg).
    pub peak_angles_deg: Vec<f64>,
    /// The region that wears most (deg).
    pub largest_peak_deg: f64,
    /// Tolerance on each angle (deg).
    pub angle_tolerance_deg: f64,
    /// Why that tolerance.
    pub angle_tolerance_reason: String,
    /// Why the model departs from the paper, where it does.
    pub deviation: Option<Deviation>,
}

/// Why the model departs from a paper value (the recorded statistics say by how much).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Deviation {
    /// The explanation, shown in `paper.md`.
    pub reason: String,
}

/// One row of Table 3.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table3Golden {
    /// Radial clearance (mm).
    pub clearance_mm: f64,
    /// Crank speed (r/min).
    pub speed_rpm: f64,
    /// "free flight and impact" or "continuous contact".
    pub motion: String,
    /// CMF(P, w).
    pub pw: f64,
    /// CMF(s, w).
    pub sw: f64,
    /// Why the model departs from the paper, where it does.
    pub deviation: Option<Deviation>,
}

impl Table3Golden {
    /// "P-w" or "s-w", whichever the paper found larger.
    pub fn dominant(&self) -> &'static str {
        if self.pw > self.sw {
            "P-w"
        } else {
            "s-w"
        }
    }
}

fn read_toml<T: for<'de> Deserialize<'de>>(path: PathBuf) -> Result<T> {
    let text = std::fs::read_to_string(&path).map_err(|source| Error::Io {
        path: path.clone(),
        source,
    })?;
    toml::from_str(&text).map_err(|e| Error::Parse {
        path,
        message: e.to_string(),
    })
}

impl Golden {
    /// Reads the golden file; its Table 3 rows must be the cases of [`CASES`], in order.
    pub fn load() -> Result<Golden> {
        let golden: Golden = read_toml(golden_path())?;
        let rows: Vec<(f64, f64)> = golden
            .table3
            .iter()
            .map(|r| (r.clearance_mm, r.speed_rpm))
            .collect();
        let cases: Vec<(f64, f64)> = CASES.iter().map(|(_, c, s)| (*c, *s)).collect();
        if rows != cases {
            return Err(Error::invalid(
                "data/golden/paper.toml table3",
                format!("rows (clearance mm, r/min) {rows:?}"),
                format!("the cases of runs::CASES in order: {cases:?}"),
            ));
        }
        Ok(golden)
    }
}

/// Smallest angular distance between two angles (deg).
pub fn angle_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// `a − b` wrapped into (−180, 180] (deg).
pub fn angle_offset(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// Width of the sampling-error bound, in standard errors of the difference of two means:
/// with normal sampling a single quantity leaves it by chance once in 16 000 comparisons.
pub const SIGMAS: f64 = 4.0;

/// Recorded statistics of one quantity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recorded {
    /// `case.quantity`, e.g. `standard.pw`.
    pub name: String,
    /// Members it was measured over.
    pub n: usize,
    /// Mean over the members.
    pub mean: f64,
    /// Sample standard deviation over the members.
    pub sd: f64,
    /// Resolution floor of the bound (same unit).
    pub floor: f64,
}

/// The recorded statistics file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleGolden {
    /// Ensemble size they were recorded with.
    pub members: usize,
    /// Seed they were recorded with.
    pub seed: u64,
    /// Why they were (re-)recorded.
    pub reason: String,
    /// One entry per quantity.
    pub quantity: Vec<Recorded>,
}

impl EnsembleGolden {
    /// Reads the recorded statistics.
    pub fn load() -> Result<EnsembleGolden> {
        read_toml(ensemble_path())
    }
}

/// Members of the golden ensembles. At 16 members a change of restitution from 0.9 to 0.8
/// shifts a dozen statistics by 2-4 standard errors and none past [`SIGMAS`]; at 32 the
/// sampling error is small enough for such a change to show (`tests/golden.rs`).
pub const GOLDEN_MEMBERS: usize = 32;

/// Resolution floors (why each is what it is): the members of the non-chaotic 30 r/min case
/// agree on their concordances to an sd of 2e-7; the floor is 50 times that;
const CONCORDANCE_FLOOR: f64 = 1e-5;
/// fractions of time or of members to one part in a thousand;
const FRACTION_FLOOR: f64 = 1e-3;
/// angles to one 1-degree sector of the wear profile;
const ANGLE_FLOOR: f64 = 1.0;
/// wear depths to 0.1 nm, 0.2 % of the shallowest wear of the paper's cases (50 nm at 30 r/min).
const DEPTH_FLOOR: f64 = 1e-10;

/// The ensembles the golden statistics are measured on.
pub const GOLDEN_NEEDS: [Need; 7] = [
    Need::Steady("speed_30rpm"),
    Need::Steady("speed_600rpm"),
    Need::Steady("standard"),
    Need::Steady("clearance_0.2mm"),
    Need::Steady("clearance_0.5mm"),
    Need::Wear("standard"),
    Need::Wear("speed_30rpm"),
];

/// Every golden quantity measured on `runs` (which must hold [`GOLDEN_NEEDS`]):
/// `(name, distribution over the members, floor)`.
pub fn measure(runs: &Runs, golden: &Golden) -> Result<Vec<(String, Distribution, f64)>> {
    let mut q = Vec::new();
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    for (name, _, _) in CASES {
        let e = runs.steady(name)?;
        let mut add = |what: &str, f: &dyn Fn(&crate::runs::SteadyMember) -> f64, floor| {
            q.push((format!("{name}.{what}"), e.stat(f), floor));
        };
        add("pw", &|m| m.concordance.pressure_wear, CONCORDANCE_FLOOR);
        add("sw", &|m| m.concordance.sliding_wear, CONCORDANCE_FLOOR);
        add(
            "contact_fraction",
            &|m| m.motion.contact_fraction,
            FRACTION_FLOOR,
        );
        add(
            "continuous_contact",
            &|m| flag(m.motion.contact_fraction >= CONTINUOUS_CONTACT_FRACTION),
            FRACTION_FLOOR,
        );
        add(
            "pw_dominant",
            &|m| flag(m.concordance.dominant() == "P-w"),
            FRACTION_FLOOR,
        );
    }
    let claim = &golden.standard_wear;
    let w = runs.wear(&claim.scene)?;
    for &a in &claim.peak_angles_deg {
        // signed offset of the nearest of the three deepest regions from the paper's angle
        let nearest = move |m: &crate::runs::WearMember| {
            m.peak_angles()
                .into_iter()
                .map(|p| angle_offset(p, a))
                .min_by(|x, y| x.abs().total_cmp(&y.abs()))
                .unwrap_or(f64::NAN)
        };
        q.push((
            format!("{}.region_near_{a:.0}_deg_offset", claim.scene),
            w.stat(nearest),
            ANGLE_FLOOR,
        ));
    }
    let deepest = |m: &crate::runs::WearMember| {
        m.peaks.first().map_or(f64::NAN, |p| {
            angle_offset(p.angle_deg, claim.largest_peak_deg)
        })
    };
    q.push((
        format!("{}.deepest_region_deg_offset", claim.scene),
        w.stat(deepest),
        ANGLE_FLOOR,
    ));
    q.push((
        format!("{}.max_depth_m", claim.scene),
        w.stat(|m| m.max_depth()),
        DEPTH_FLOOR,
    ));
    let low = &golden.low_speed_wear;
    let slow = runs.wear(&low.scene)?;
    q.push((
        format!("{}.deepest_region_deg_offset", low.scene),
        slow.stat(|m| {
            m.peaks.first().map_or(f64::NAN, |p| {
                angle_offset(p.angle_deg, low.largest_peak_deg)
            })
        }),
        ANGLE_FLOOR,
    ));
    q.push((
        format!("{}.max_depth_m", low.scene),
        slow.stat(|m| m.max_depth()),
        DEPTH_FLOOR,
    ));
    Ok(q)
}

/// A golden quantity outside its bound.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The quantity.
    pub name: String,
    /// Mean measured now.
    pub mean: f64,
    /// Recorded mean.
    pub recorded: f64,
    /// The bound on their difference.
    pub bound: f64,
}

/// The measured quantities against the recorded ones: every violation, and a quantity missing
/// on either side as a violation with a NaN bound.
pub fn compare(
    measured: &[(String, Distribution, f64)],
    recorded: &EnsembleGolden,
) -> Vec<Violation> {
    let mut out = Vec::new();
    for r in &recorded.quantity {
        let Some((_, d, _)) = measured.iter().find(|(n, _, _)| *n == r.name) else {
            out.push(Violation {
                name: r.name.clone(),
                mean: f64::NAN,
                recorded: r.mean,
                bound: f64::NAN,
            });
            continue;
        };
        let se = (d.sd.powi(2) / d.n as f64 + r.sd.powi(2) / r.n as f64).sqrt();
        let bound = SIGMAS * se + r.floor;
        // a NaN mean (no finite member) is a violation too, and so is a member that no longer
        // has the quantity (a wear region that disappeared)
        let inside = (d.mean - r.mean).abs() <= bound && d.n == r.n;
        if !inside {
            out.push(Violation {
                name: r.name.clone(),
                mean: d.mean,
                recorded: r.mean,
                bound,
            });
        }
    }
    for (name, d, _) in measured {
        if !recorded.quantity.iter().any(|r| &r.name == name) {
            out.push(Violation {
                name: name.clone(),
                mean: d.mean,
                recorded: f64::NAN,
                bound: f64::NAN,
            });
        }
    }
    out
}
