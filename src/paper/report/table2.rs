//! Section 4 of `paper.md`: the reconstruction of the paper's lost Table 2, every value of
//! the standard scene with its source, and the calibration study
//! (`data/calibration.csv`, [`crate::paper::calibration`]) that settled the low-confidence
//! ones.

use super::markdown::md_table;
use crate::paper::calibration::{
    Params, StudyTable, FACTORIAL_GROUP, FAILURE_COLUMN, GROUP_COLUMN, SCORE_ANGLE_DEG,
    SCORE_COLUMN, SCORE_CONCORDANCE, SCORE_DEEPEST_MISPLACED,
};
use crate::paper::cases::CASES;
use crate::paper::format::{cell, friction_name, pressure_name, sci};
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
pub(super) fn table2_section(calibration: Option<&StudyTable>) -> String {
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
    match calibration {
        Some((header, rows)) => {
            let mut rows = rows.clone();
            let col = |name: &str| header.iter().position(|h| h == name);
            if let Some(score) = col(SCORE_COLUMN) {
                rows.sort_by(|a, b| {
                    let key = |r: &Vec<String>| r[score].parse::<f64>().unwrap_or(f64::INFINITY);
                    key(a).total_cmp(&key(b))
                });
            }
            // every column but the row index and the failure (listed below the tables)
            let keep: Vec<&str> = (header.iter().skip(1))
                .map(String::as_str)
                .filter(|h| *h != FAILURE_COLUMN)
                .collect();
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
            let failed: Vec<String> = col(FAILURE_COLUMN)
                .map(|f| {
                    let set = |r: &Vec<String>| {
                        let field = |name: &str| col(name).and_then(|i| r.get(i)).cloned();
                        let (g, i) = (field(GROUP_COLUMN), field("index"));
                        format!("set {} ({})", i.unwrap_or_default(), g.unwrap_or_default())
                    };
                    (rows.iter())
                        .filter(|r| r.get(f).is_some_and(|why| !why.is_empty()))
                        .map(|r| format!("- {}: {}", set(r), r[f]))
                        .collect()
                })
                .unwrap_or_default();
            if let Some(text) = scene_set_against_noise(header, &rows, scene.as_ref().ok()) {
                md.push_str(&text);
            }
            if !failed.is_empty() {
                let _ = write!(
                    md,
                    "Sets whose runs left the model, with no score (missing from the ranking, not last in \
                     it):\n\n{}\n\n",
                    failed.join("\n")
                );
            }
            md.push_str("![calibration](figures/calibration.png)\n\n");
        }
        None => md.push_str(
            "*`data/calibration.csv` is missing or not the study's whole table: run `cargo run --release --bin calibration`.*\n\n",
        ),
    }
    md
}

/// Where the scenes' own set stands in the calibration (`header`, `rows` of
/// `data/calibration.csv`; `scene`, the standard scene's file): its score against the best
/// admissible factorial set's, and the spread of the one-at-a-time rows, each one parameter
/// away from the scenes' set, which is the noise of one trajectory's score. `None` if a
/// column or the scenes' row is missing.
fn scene_set_against_noise(
    header: &[String],
    rows: &[Vec<String>],
    scene: Option<&SceneFile>,
) -> Option<String> {
    let col = |name: &str| header.iter().position(|h| h == name);
    let (group, score) = (col(GROUP_COLUMN)?, col(SCORE_COLUMN)?);
    let (rotation, mu, v_s, pressure, admissible) = (
        col("rotation")?,
        col("mu_d")?,
        col("v_s_m_s")?,
        col("pressure")?,
        col("admissible")?,
    );
    let p = Params::of_scene(scene?);
    let num = |r: &Vec<String>, i: usize| r.get(i)?.parse::<f64>().ok();
    let factorial = || {
        rows.iter()
            .filter(|r| r[group] == FACTORIAL_GROUP && r[admissible] == "true")
            .filter_map(|r| Some((r, num(r, score)?)))
    };
    let own = factorial().find(|(r, _)| {
        r[rotation] == p.rotation()
            && num(r, mu) == Some(p.mu_d)
            && num(r, v_s) == Some(p.v_s)
            && r[pressure] == format!("{:?}", p.pressure)
    })?;
    let (best, best_score) = factorial().min_by(|a, b| a.1.total_cmp(&b.1))?;
    let oat: Vec<f64> = (rows.iter())
        .filter(|r| r[group] != FACTORIAL_GROUP)
        .filter_map(|r| num(r, score))
        .collect();
    if oat.is_empty() {
        return None;
    }
    let (lo, hi) = (
        oat.iter().copied().fold(f64::INFINITY, f64::min),
        oat.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let spread = (hi.max(own.1) - lo.min(own.1)).max(0.0);
    let within = factorial()
        .filter(|(_, s)| *s <= best_score + spread)
        .count();
    let describe = |r: &Vec<String>| {
        format!(
            "{}, μ_d {}, v_s {} m/s, {}",
            r[rotation],
            r[mu],
            r[v_s],
            cell(&r[pressure])
        )
    };
    Some(format!(
        "**The scenes' set against the score's noise.** Each set is scored on one trajectory per case, and \
         the motion is chaotic. The scenes' set ({}) scores {:.3} in the calibration study's run (`data/calibration.csv`); the best admissible factorial \
         set ({}) {:.3}. The one-at-a-time rows, each one parameter away from the scenes' set (grazing floor, \
         k/H, length, sector count), score {:.3}-{:.3}: with the \
         scenes' own row, one trajectory's score moves by {:.2} units with no change that matters, and {} of \
         the admissible factorial sets lie within that of the best. The ranking within it is noise (it has \
         moved with rounding changes between runs of this study), so the scenes keep the set the study first \
         chose; ranking sets within that spread would need each scored over an ensemble.\n\n",
        describe(own.0),
        own.1,
        describe(best),
        best_score,
        lo,
        hi,
        spread,
        within,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scenes' row is found by its parameters, the noise is the spread of the
    /// one-at-a-time rows with it, and the sets within that of the best are counted. Fails with
    /// the scenes' own row left out of the spread (2.00 units and 1 set: tried).
    #[test]
    fn the_scenes_set_is_judged_against_the_one_at_a_time_spread() {
        let header: Vec<String> = [
            "group",
            "rotation",
            "mu_d",
            "v_s_m_s",
            "pressure",
            "admissible",
            "score",
        ]
        .map(String::from)
        .to_vec();
        let row = |g: &str, rot: &str, mu: &str, p: &str, ok: &str, score: &str| {
            [g, rot, mu, "0.0001", p, ok, score]
                .map(String::from)
                .to_vec()
        };
        let rows = vec![
            row("factorial", "cw", "0.01", "HertzLine", "true", "12"),
            row(
                "factorial",
                "cw",
                "0.01",
                "ElasticFoundation",
                "true",
                "8.5",
            ),
            row("factorial", "ccw", "0.01", "HertzLine", "true", "11.4"),
            row("factorial", "cw", "0", "HertzLine", "false", "1"),
            row("grazing", "cw", "0.01", "HertzLine", "true", "9"),
            row("sectors", "cw", "0.01", "HertzLine", "true", "11"),
        ];
        let scene = SceneFile::read(scene_path(CASES.standard.scene)).unwrap();
        let text = scene_set_against_noise(&header, &rows, Some(&scene)).unwrap();
        assert!(
            text.contains("Hertz line contact) scores 12.000")
                && text.contains("elastic foundation) 8.500")
                && text.contains("score 9.000-11.000")
                && text.contains("moves by 3.00 units")
                && text.contains("2 of the admissible factorial sets"),
            "{text}"
        );
        assert!(scene_set_against_noise(&header, &rows[1..], Some(&scene)).is_none());
    }
}
