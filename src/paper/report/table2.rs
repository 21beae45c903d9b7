//! Section 4 of `paper.md`: the reconstruction of the paper's lost Table 2, every value of
//! the standard scene with its source, and the calibration study
//! (`data/calibration.csv`, [`crate::paper::calibration`]) that settled the low-confidence
//! ones.

use super::markdown::md_table;
use crate::io::output::read_rows;
use crate::paper::calibration::{
    FACTORIAL_GROUP, GROUP_COLUMN, SCORE_ANGLE_DEG, SCORE_COLUMN, SCORE_CONCORDANCE,
    SCORE_DEEPEST_MISPLACED,
};
use crate::paper::cases::CASES;
use crate::paper::figures::output_path;
use crate::paper::format::{friction_name, pressure_name, sci};
use crate::scene::{scene_path, MethodSpec, SceneFile};
use std::fmt::Write as _;

/// An integration method in words.
fn method_name(m: MethodSpec) -> &'static str {
    match m {
        MethodSpec::Dopri5 => "Dormand-Prince 5(4), adaptive",
        MethodSpec::Dop853 => "DOP853, adaptive",
        MethodSpec::Rk4 => "classical Runge-Kutta, fixed step",
    }
}

/// The reconstruction of Table 2: every value, its source, and how much results move with it.
pub(super) fn table2_section() -> String {
    let mut md = String::from("## 4. Table 2 reconstructed\n\n");
    md.push_str(
        "Table 2 of the paper is lost. The values used (`data/scenes/standard.toml`, inherited by every case scene) \
         and where each comes from:\n\n",
    );
    let scene = SceneFile::read(scene_path(CASES.standard.scene));
    let rows: Vec<Vec<String>> = match &scene {
        Ok(s) => {
            let c = &s.clearance[0];
            let m = s.materials.get(&c.bearing_material);
            let w = c.wear.as_ref();
            let friction = friction_name(&c.friction);
            vec![
                vec![
                    "bearing radius R_i".into(),
                    format!("{} mm", c.bearing_radius_mm),
                    "reproduction notes (medium)".into(),
                ],
                vec![
                    "radial clearance c".into(),
                    format!("{} mm", c.clearance_mm),
                    "paper text (Fig. 5's 0.002 mm is a misprint)".into(),
                ],
                vec![
                    "E, ν (journal and bearing)".into(),
                    m.map_or("?".into(), |m| {
                        format!("{} GPa, {}", m.youngs_modulus_gpa, m.poisson_ratio)
                    }),
                    "notes (medium-high); E* = E / (2(1 − ν²))".into(),
                ],
                vec![
                    "restitution c_e, exponent n".into(),
                    format!(
                        "{}, {}",
                        c.contact.restitution,
                        c.contact.exponent.map_or("none".into(), |n| n.to_string())
                    ),
                    "notes (medium-high)".into(),
                ],
                vec![
                    "friction".into(),
                    friction,
                    "calibration study (low confidence)".into(),
                ],
                vec![
                    "grazing floor of δ̇⁻".into(),
                    format!("{} m/s", c.contact.grazing_velocity_m_s),
                    "calibration study (not in the paper)".into(),
                ],
                vec![
                    "wear k/H, pressure model, length L, sectors".into(),
                    w.map_or("none".into(), |w| {
                        format!(
                            "{} 1/Pa, {}, {} mm, {} sectors",
                            sci(w.k_over_h_per_pa),
                            pressure_name(w.pressure),
                            w.length_mm,
                            w.sectors
                        )
                    }),
                    "calibration study (low confidence; k accelerated as the paper says)".into(),
                ],
                vec![
                    "sense of crank rotation".into(),
                    if s.driver.speed_rpm > 0.0 {
                        "counter-clockwise"
                    } else {
                        "clockwise"
                    }
                    .into(),
                    "calibration study".into(),
                ],
                vec![
                    "integrator".into(),
                    format!(
                        "{}, rtol {}, atol {}, max step {} s",
                        method_name(s.run.method),
                        sci(s.run.rtol),
                        sci(s.run.atol),
                        sci(s.run.max_step_s)
                    ),
                    "work-precision study (section 5)".into(),
                ],
            ]
        }
        Err(e) => vec![vec![
            "scene".into(),
            format!("cannot read: {e}"),
            String::new(),
        ]],
    };
    md_table(&mut md, &["parameter", "value", "source"], &rows);
    let _ = write!(
        md,
        "**Calibration** (`cargo run --release --bin calibration`, `src/paper/calibration.rs`): each candidate set is applied to \
         every case and scored on the paper's claims (peak angles, deepest region, Table 3 modes, dominance and values, \
         the 30 r/min wear location); one unit of score is one missed qualitative claim, {SCORE_ANGLE_DEG} deg of angle or \
         {SCORE_CONCORDANCE} of concordance, and a deepest region away from 180 deg costs {SCORE_DEEPEST_MISPLACED}. Only sets \
         with friction are admissible (the paper's method includes eq. 4); frictionless sets are \
         run as a diagnostic. The best sets:\n\n",
    );
    match read_rows(&output_path("data", "calibration.csv")) {
        Ok((header, mut rows)) => {
            let col = |name: &str| header.iter().position(|h| h == name);
            if let Some(score) = col(SCORE_COLUMN) {
                rows.sort_by(|a, b| {
                    let key = |r: &Vec<String>| r[score].parse::<f64>().unwrap_or(f64::INFINITY);
                    key(a).total_cmp(&key(b))
                });
            }
            // every column but the row index
            let keep: Vec<&str> = header.iter().skip(1).map(String::as_str).collect();
            let idx: Vec<Option<usize>> = keep.iter().map(|k| col(k)).collect();
            let pick = |r: &Vec<String>| {
                idx.iter()
                    .map(|i| i.and_then(|i| r.get(i).cloned()).unwrap_or_default())
                    .collect()
            };
            let top: Vec<Vec<String>> = rows.iter().take(10).map(pick).collect();
            md_table(&mut md, &keep, &top);
            md.push_str("How much the results move when each one-at-a-time parameter moves (around the chosen set):\n\n");
            let oat: Vec<Vec<String>> = rows
                .iter()
                .filter(|r| col(GROUP_COLUMN).is_some_and(|g| r[g] != FACTORIAL_GROUP))
                .map(pick)
                .collect();
            md_table(&mut md, &keep, &oat);
            md.push_str("![calibration](figures/calibration.png)\n\n");
        }
        Err(_) => md.push_str(
            "*`data/calibration.csv` is missing: run `cargo run --release --bin calibration`.*\n\n",
        ),
    }
    md
}
