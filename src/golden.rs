//! The paper's numbers (`data/golden/paper.toml`) and the deviations of this reproduction from
//! them. Where the model cannot match a paper value, the golden file records what we measure
//! instead, with the reason; the golden tests assert the recorded deviation, so a change of
//! behaviour in either direction is noticed.

use crate::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Path of the golden file.
pub fn golden_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/paper.toml")
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Golden {
    pub standard_wear: PeakClaim,
    pub low_speed_wear: PeakClaim,
    /// Tolerance on concordance values.
    pub concordance_tolerance: f64,
    /// Why that tolerance.
    pub concordance_tolerance_reason: String,
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
    /// What we measure where it differs from the paper.
    pub deviation: Option<PeakDeviation>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeakDeviation {
    pub peak_angles_deg: Vec<f64>,
    pub largest_peak_deg: f64,
    pub reason: String,
}

/// One row of Table 3.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table3Golden {
    pub clearance_mm: f64,
    pub speed_rpm: f64,
    /// "free flight and impact" or "continuous contact".
    pub motion: String,
    pub pw: f64,
    pub sw: f64,
    /// What we measure where it differs from the paper.
    pub deviation: Option<Table3Deviation>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table3Deviation {
    pub motion: String,
    pub pw: f64,
    pub sw: f64,
    pub reason: String,
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

impl Golden {
    /// Reads the golden file.
    pub fn load() -> Result<Golden> {
        let path = golden_path();
        let text = std::fs::read_to_string(&path).map_err(|source| Error::Io {
            path: path.clone(),
            source,
        })?;
        toml::from_str(&text).map_err(|e| Error::Parse {
            path,
            message: e.to_string(),
        })
    }
}

/// Smallest angular distance between two angles (deg).
pub fn angle_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}
