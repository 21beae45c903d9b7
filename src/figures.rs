//! The paper's figures as library functions. Each loads its scene, runs only the simulation
//! it plots, writes `figures/<name>.png` and `data/<name>.csv` atomically, and returns a
//! printable summary; the `src/bin/` programs only call them.

use crate::analysis::{peaks, Peak};
use crate::output::write_csv;
use crate::plot::{render, Axes, Series, Style};
use crate::scene::{scene_path, SceneFile};
use crate::simulation::simulate;
use crate::Result;
use std::path::{Path, PathBuf};

/// Where generated outputs go: `figures/` and `data/` under the crate root.
pub fn output_path(dir: &str, file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(dir).join(file)
}

/// Minimum prominence of a reported wear peak, as a fraction of the deepest wear.
pub const PEAK_PROMINENCE: f64 = 0.05;

/// Sector centre angles (deg) of a profile with `n` sectors.
pub fn sector_angles_deg(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (i as f64 + 0.5) * 360.0 / n as f64)
        .collect()
}

/// Figure 6: wear depth against angle after 10, 20, 30 and 40 rotations of the standard
/// scene; returns the peaks of the final profile, deepest first.
pub fn fig06() -> Result<Vec<Peak>> {
    let mut file = SceneFile::read(scene_path("standard"))?;
    file.run.record_rotations = 0; // only the wear profile is plotted
    let out = simulate(&file.build()?)?;
    let angles = sector_angles_deg(out.final_wear[0].len());
    let mm: Vec<(String, Vec<f64>)> = out
        .wear_snapshots
        .iter()
        .map(|s| {
            (
                format!("rot{}", s.rotation),
                s.depths[0].iter().map(|d| d * 1e3).collect(),
            )
        })
        .collect();
    let mut header = vec!["angle_deg"];
    header.extend(mm.iter().map(|(h, _)| h.as_str()));
    let mut columns: Vec<&[f64]> = vec![&angles];
    columns.extend(mm.iter().map(|(_, c)| c.as_slice()));
    write_csv(&output_path("data", "fig06.csv"), &header, &columns)?;
    let um: Vec<Vec<f64>> = mm
        .iter()
        .map(|(_, c)| c.iter().map(|d| d * 1e3).collect())
        .collect();
    let series = out
        .wear_snapshots
        .iter()
        .zip(&um)
        .map(|(s, d)| Series::new(format!("{} rotations", s.rotation), &angles, d, Style::Line))
        .collect();
    render(
        &output_path("figures", "fig06.png"),
        &[Axes {
            x_range: Some((0.0, 360.0)),
            ..Axes::new(
                "Bearing wear with crank rotation (c = 0.02 mm, 2000 r/min)",
                "circumferential angle (deg)",
                "bearing radius increase = wear depth (µm)",
                series,
            )
        }],
    )?;
    Ok(peaks(&out.final_wear[0], PEAK_PROMINENCE))
}

/// Runs a figure's `main`: prints the error and exits non-zero on failure (2 for bad input).
pub fn exit_on_error<T>(result: Result<T>) -> T {
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        let code = match e {
            crate::Error::Invalid { .. } | crate::Error::Parse { .. } => 2,
            _ => 1,
        };
        std::process::exit(code)
    })
}
