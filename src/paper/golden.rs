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

use crate::analysis::statistics::Distribution;
use crate::analysis::CONTINUOUS_CONTACT_FRACTION;
use crate::io::format::exact;
use crate::paper::cases::{
    case_of_scene, Case, Need, PerCase, Runs, SteadyMember, WearMember, CASES,
};
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
#[derive(Clone, Debug)]
pub struct Golden {
    /// Severe wear regions of the standard case (figures 5-7).
    pub standard_wear: PeakClaim,
    /// Wear location at 30 r/min (figure 14).
    pub low_speed_wear: PeakClaim,
    /// Tolerance on concordance values.
    pub concordance_tolerance: f64,
    /// Why that tolerance.
    pub concordance_tolerance_reason: String,
    /// Table 3: the row of each case, looked up by the row's `scene`.
    pub table3: PerCase<Table3Golden>,
}

/// `data/golden/paper.toml` as written: Table 3 is a list of rows, each naming its scene.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GoldenFile {
    standard_wear: PeakClaim,
    low_speed_wear: PeakClaim,
    concordance_tolerance: f64,
    concordance_tolerance_reason: String,
    table3: Vec<Table3Golden>,
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
    /// Scene of the case the row belongs to (a scene of [`CASES`]).
    pub scene: String,
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

/// The TOML file at `path` as a `T`.
pub(crate) fn read_toml<T: for<'de> Deserialize<'de>>(path: PathBuf) -> Result<T> {
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
    /// Reads the golden file. Its Table 3 has one row per case of [`CASES`], named by the
    /// case's scene and stating the case's clearance and speed; a missing, duplicate, unknown
    /// or inconsistent row is an error naming its scene.
    pub fn load() -> Result<Golden> {
        Golden::from_file(read_toml(golden_path())?)
    }

    /// The golden numbers of a parsed file, with its Table 3 rows looked up by scene.
    fn from_file(file: GoldenFile) -> Result<Golden> {
        // A tolerance out of its range passes or fails every verdict it decides (a NaN one
        // failed them all, an angle's of 400 deg passed any angle), and angles must be angles.
        let (standard, low) = (&file.standard_wear, &file.low_speed_wear);
        let tolerances = [
            ("concordance_tolerance", file.concordance_tolerance, 1.0),
            (
                "standard_wear.angle_tolerance_deg",
                standard.angle_tolerance_deg,
                180.0,
            ),
            (
                "low_speed_wear.angle_tolerance_deg",
                low.angle_tolerance_deg,
                180.0,
            ),
        ];
        if let Some((name, v, hi)) = tolerances.iter().find(|(_, v, hi)| !(*v > 0.0 && v <= hi)) {
            return Err(Error::invalid(
                format!("data/golden/paper.toml {name}"),
                exact(*v),
                format!("a tolerance in (0, {hi}]"),
            ));
        }
        for (name, claim) in [("standard_wear", standard), ("low_speed_wear", low)] {
            let angles = claim
                .peak_angles_deg
                .iter()
                .chain([&claim.largest_peak_deg]);
            if let Some(a) = angles.copied().find(|a| !(0.0..360.0).contains(a)) {
                return Err(Error::invalid(
                    format!("data/golden/paper.toml {name}"),
                    exact(a),
                    "angles in [0, 360) deg",
                ));
            }
        }
        const FIELD: &str = "data/golden/paper.toml table3";
        if let Some(row) = file
            .table3
            .iter()
            .find(|r| case_of_scene(&r.scene).is_err())
        {
            return Err(Error::invalid(
                FIELD,
                format!("a row with scene = {:?}", row.scene),
                "rows whose scene is a case of cases::CASES",
            ));
        }
        let table3 = CASES.try_map(|case| {
            let mut rows = file.table3.iter().filter(|r| r.scene == case.scene);
            let row = rows.next().ok_or_else(|| {
                Error::invalid(
                    FIELD,
                    format!("no row with scene = {:?}", case.scene),
                    "a row for every case of cases::CASES",
                )
            })?;
            if rows.next().is_some() {
                return Err(Error::invalid(
                    FIELD,
                    format!("two rows with scene = {:?}", case.scene),
                    "one row per case",
                ));
            }
            if (row.clearance_mm, row.speed_rpm) != (case.clearance_mm, case.speed_rpm) {
                return Err(Error::invalid(
                    FIELD,
                    format!(
                        "scene = {:?} at {} mm, {} r/min",
                        row.scene, row.clearance_mm, row.speed_rpm
                    ),
                    format!(
                        "the case's {} mm, {} r/min (cases::CASES)",
                        case.clearance_mm, case.speed_rpm
                    ),
                ));
            }
            Ok(row.clone())
        })?;
        Ok(Golden {
            standard_wear: file.standard_wear,
            low_speed_wear: file.low_speed_wear,
            concordance_tolerance: file.concordance_tolerance,
            concordance_tolerance_reason: file.concordance_tolerance_reason,
            table3,
        })
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
    Need::Steady(CASES.speed_30rpm.scene),
    Need::Steady(CASES.speed_600rpm.scene),
    Need::Steady(CASES.standard.scene),
    Need::Steady(CASES.clearance_0_2mm.scene),
    Need::Steady(CASES.clearance_0_5mm.scene),
    Need::Wear(CASES.standard.scene),
    Need::Wear(CASES.speed_30rpm.scene),
];

/// A Table 3 measure of a steady ensemble's members, recorded as a golden statistic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SteadyQuantity {
    /// CMF(P, w).
    Pw,
    /// CMF(s, w).
    Sw,
    /// Share of the recorded time in contact.
    ContactFraction,
    /// 1 for a member in continuous contact, else 0.
    ContinuousContact,
    /// 1 for a member whose P-w concordance exceeds its s-w one, else 0.
    PwDominant,
}

impl SteadyQuantity {
    /// Every steady quantity, in the order they are measured and recorded.
    pub const ALL: [SteadyQuantity; 5] = [
        SteadyQuantity::Pw,
        SteadyQuantity::Sw,
        SteadyQuantity::ContactFraction,
        SteadyQuantity::ContinuousContact,
        SteadyQuantity::PwDominant,
    ];

    /// Its part of the recorded name (`pw` of `standard.pw`).
    pub fn name(self) -> &'static str {
        match self {
            SteadyQuantity::Pw => "pw",
            SteadyQuantity::Sw => "sw",
            SteadyQuantity::ContactFraction => "contact_fraction",
            SteadyQuantity::ContinuousContact => "continuous_contact",
            SteadyQuantity::PwDominant => "pw_dominant",
        }
    }

    /// Its value in one member.
    pub fn of(self, m: &SteadyMember) -> f64 {
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        match self {
            SteadyQuantity::Pw => m.concordance.pressure_wear,
            SteadyQuantity::Sw => m.concordance.sliding_wear,
            SteadyQuantity::ContactFraction => m.motion.contact_fraction,
            SteadyQuantity::ContinuousContact => {
                flag(m.motion.contact_fraction >= CONTINUOUS_CONTACT_FRACTION)
            }
            SteadyQuantity::PwDominant => flag(m.concordance.dominant() == "P-w"),
        }
    }

    fn floor(self) -> f64 {
        match self {
            SteadyQuantity::Pw | SteadyQuantity::Sw => CONCORDANCE_FLOOR,
            _ => FRACTION_FLOOR,
        }
    }
}

/// A golden quantity: what is measured, on which case. [`Quantity::name`] is its key in
/// `data/golden/ensemble.toml`; code names a quantity by this type, so a misspelt one does
/// not compile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Quantity {
    /// A Table 3 measure of a case's steady ensemble.
    Steady(Case, SteadyQuantity),
    /// Signed offset (deg) from the paper's angle `claimed_deg` of the nearest of each
    /// member's three most prominent wear regions ([`crate::analysis::regions`]).
    RegionNearOffset {
        /// The wear case.
        case: Case,
        /// The paper's angle (deg).
        claimed_deg: f64,
    },
    /// Signed offset (deg) of each member's deepest wear region from the paper's.
    DeepestRegionOffset(Case),
    /// Deepest wear of each member (m).
    MaxDepth(Case),
}

impl Quantity {
    /// The recorded name, `case.quantity`, e.g. `standard.pw`.
    pub fn name(&self) -> String {
        match self {
            Quantity::Steady(c, q) => format!("{}.{}", c.scene, q.name()),
            Quantity::RegionNearOffset { case, claimed_deg } => {
                format!("{}.region_near_{claimed_deg:.0}_deg_offset", case.scene)
            }
            Quantity::DeepestRegionOffset(c) => format!("{}.deepest_region_deg_offset", c.scene),
            Quantity::MaxDepth(c) => format!("{}.max_depth_m", c.scene),
        }
    }

    /// Whether it is an angle (deg).
    pub fn is_angle(&self) -> bool {
        matches!(
            self,
            Quantity::RegionNearOffset { .. } | Quantity::DeepestRegionOffset(_)
        )
    }

    /// Whether it is a concordance (P-w or s-w).
    pub fn is_concordance(&self) -> bool {
        matches!(
            self,
            Quantity::Steady(_, SteadyQuantity::Pw | SteadyQuantity::Sw)
        )
    }
}

/// A golden quantity measured over an ensemble's members.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// What was measured.
    pub quantity: Quantity,
    /// Its distribution over the members.
    pub distribution: Distribution,
    /// Resolution floor of its bound (same unit).
    pub floor: f64,
}

/// Every golden quantity measured on `runs` (which must hold [`GOLDEN_NEEDS`]).
pub fn measure(runs: &Runs, golden: &Golden) -> Result<Vec<Measurement>> {
    let mut q = Vec::new();
    let mut add = |quantity, distribution, floor| {
        q.push(Measurement {
            quantity,
            distribution,
            floor,
        })
    };
    for case in CASES.list() {
        let e = runs.steady(case.scene)?;
        for sq in SteadyQuantity::ALL {
            add(
                Quantity::Steady(*case, sq),
                e.stat(|m| sq.of(m)),
                sq.floor(),
            );
        }
    }
    // signed offset of the deepest region from the claimed angle
    let deepest = |m: &WearMember, claimed: f64| {
        m.deepest_angle()
            .map_or(f64::NAN, |a| angle_offset(a, claimed))
    };
    let claim = &golden.standard_wear;
    let case = case_of_scene(&claim.scene)?;
    let w = runs.wear(case.scene)?;
    for &a in &claim.peak_angles_deg {
        // signed offset of the nearest of the three most prominent regions from the paper's angle
        let nearest = move |m: &WearMember| {
            m.region_angles()
                .into_iter()
                .map(|p| angle_offset(p, a))
                .min_by(|x, y| x.abs().total_cmp(&y.abs()))
                .unwrap_or(f64::NAN)
        };
        let quantity = Quantity::RegionNearOffset {
            case,
            claimed_deg: a,
        };
        add(quantity, w.stat(nearest), ANGLE_FLOOR);
    }
    add(
        Quantity::DeepestRegionOffset(case),
        w.stat(|m| deepest(m, claim.largest_peak_deg)),
        ANGLE_FLOOR,
    );
    add(
        Quantity::MaxDepth(case),
        w.stat(|m| m.max_depth()),
        DEPTH_FLOOR,
    );
    let low = &golden.low_speed_wear;
    let case = case_of_scene(&low.scene)?;
    let slow = runs.wear(case.scene)?;
    add(
        Quantity::DeepestRegionOffset(case),
        slow.stat(|m| deepest(m, low.largest_peak_deg)),
        ANGLE_FLOOR,
    );
    add(
        Quantity::MaxDepth(case),
        slow.stat(|m| m.max_depth()),
        DEPTH_FLOOR,
    );
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
pub fn compare(measured: &[Measurement], recorded: &EnsembleGolden) -> Vec<Violation> {
    let named: Vec<(String, &Distribution)> = measured
        .iter()
        .map(|m| (m.quantity.name(), &m.distribution))
        .collect();
    let mut out = Vec::new();
    for r in &recorded.quantity {
        let Some((_, d)) = named.iter().find(|(n, _)| *n == r.name) else {
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
    for (name, d) in &named {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The golden file with its Table 3 rows edited by `edit`.
    fn golden_with(edit: impl FnOnce(&mut Vec<toml::Value>)) -> Result<Golden> {
        let text = std::fs::read_to_string(golden_path()).unwrap();
        let mut value: toml::Table = toml::from_str(&text).unwrap();
        let rows = value["table3"].as_array_mut().unwrap();
        edit(rows);
        Golden::from_file(toml::Value::Table(value).try_into().unwrap())
    }

    #[test]
    fn table3_rows_are_looked_up_by_scene_whatever_their_order() {
        let golden = golden_with(|rows| rows.reverse()).unwrap();
        assert_eq!(golden.table3.standard.scene, "standard");
        assert_eq!(golden.table3.speed_30rpm.speed_rpm, 30.0);
        assert_eq!(golden.table3.clearance_0_5mm.clearance_mm, 0.5);
    }

    #[test]
    fn a_missing_or_wrong_row_is_an_error_naming_its_scene() {
        let missing = golden_with(|rows| {
            rows.retain(|r| r["scene"].as_str() != Some("speed_600rpm"));
        })
        .unwrap_err()
        .to_string();
        assert!(missing.contains("speed_600rpm"), "{missing}");
        let unknown = golden_with(|rows| {
            let row = rows[0].as_table_mut().unwrap();
            row.insert("scene".into(), toml::Value::from("speed_3Orpm"));
        })
        .unwrap_err()
        .to_string();
        assert!(unknown.contains("speed_3Orpm"), "{unknown}");
        let inconsistent = golden_with(|rows| {
            let row = rows[1].as_table_mut().unwrap();
            row.insert("speed_rpm".into(), toml::Value::from(700.0));
        })
        .unwrap_err()
        .to_string();
        assert!(inconsistent.contains("speed_600rpm"), "{inconsistent}");
    }

    /// A tolerance out of its range decided every verdict it judges (NaN failed them all, an
    /// angle's 400 deg passed any angle): it is refused, naming it.
    #[test]
    fn a_tolerance_or_angle_out_of_its_range_is_an_error_naming_it() {
        let edited = |key: &str, sub: Option<&str>, v: f64| {
            let text = std::fs::read_to_string(golden_path()).unwrap();
            let mut value: toml::Table = toml::from_str(&text).unwrap();
            let table = match sub {
                Some(t) => value[t].as_table_mut().unwrap(),
                None => &mut value,
            };
            table.insert(key.into(), toml::Value::from(v));
            let e = Golden::from_file(toml::Value::Table(value).try_into().unwrap());
            e.unwrap_err().to_string()
        };
        let e = edited("concordance_tolerance", None, f64::NAN);
        assert!(
            e.contains("concordance_tolerance") && e.contains("NaN"),
            "{e}"
        );
        let e = edited("angle_tolerance_deg", Some("standard_wear"), 400.0);
        assert!(e.contains("standard_wear.angle_tolerance_deg"), "{e}");
        let e = edited("largest_peak_deg", Some("low_speed_wear"), -5.0);
        assert!(
            e.contains("low_speed_wear") && e.contains("[0, 360)"),
            "{e}"
        );
    }
}
