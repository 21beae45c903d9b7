//! `figures/work_precision.png`: error against work of the work-precision study, on log-log
//! axes, work as right-hand-side evaluations (wall time depends on the machine and its load;
//! it stays in the CSV), one line per method (and step cap, and step control) joining its settings from the
//! loosest to the tightest, the two ends of each line labelled with their tolerance (rtol, or
//! the step h of RK4; labelling every point made them overlap), the loosest on its left and the
//! tightest on its right, off the line. The three panels stand one
//! under another, so the figure is one panel wide and stays readable at a page's width. Settings
//! without a point (a failed run, a wear ensemble not measured) are named in a note of the
//! panel. The figure is drawn from the study's rows as it runs, or redrawn from
//! `data/work_precision.csv` ([`redraw_work_precision`]) without rerunning the study.

use super::work_precision::{
    EnsembleWearError, Errors, WorkRow, PROVENANCE, REFERENCE, SECOND_REFERENCE,
    WORK_PRECISION_FIGURE, WORK_PRECISION_FILE, WORK_PRECISION_HEADER, WP_ENSEMBLE_MAX_EVALUATIONS,
};
use crate::analysis::statistics::Distribution;
use crate::io::output::read_rows;
use crate::io::plot::{render_column, Axes, Series, Style};
use crate::paper::figures::output_path;
use crate::paper::format::count;
use crate::{Error, Result};

/// What the figure needs of one setting.
pub(super) struct Point {
    /// `dopri5`, `dop853` or `rk4`.
    method: String,
    /// The setting as the CSV writes it, e.g. `rtol=1e-7 max_step=1e-3` or `h=1e-5`.
    setting: String,
    /// Whether it is one of the two references (which define the errors and their floor).
    reference: bool,
    /// Right-hand-side evaluations of the 40-rotation run (0 when it failed).
    evaluations: f64,
    /// Errors against the reference, `None` when the run failed.
    errors: Option<Errors>,
    /// The ensemble wear error, where measured.
    ensemble: Option<EnsembleWearError>,
    /// Why the run failed, if it did.
    failure: Option<String>,
}

impl Point {
    /// The study's row as the figure needs it.
    pub(super) fn of(r: &WorkRow) -> Self {
        Point {
            method: r.integration.method_name().to_owned(),
            setting: r.integration.setting(),
            reference: r.integration == REFERENCE || r.integration == SECOND_REFERENCE,
            evaluations: if r.failure.is_some() {
                0.0
            } else {
                r.stats.evaluations as f64
            },
            errors: r.errors,
            ensemble: r.ensemble,
            failure: r.failure.clone(),
        }
    }

    /// The tolerance a point is labelled with: `1e-7` (rtol) or `1e-5 s` (the step of RK4).
    fn tolerance(&self) -> String {
        let value = |key: &str| self.field(key).unwrap_or("").to_owned();
        if self.method == "rk4" {
            format!("{} s", value("h="))
        } else {
            value("rtol=")
        }
    }

    /// The value of `key` (as `"rtol="`) in the setting, if it names one.
    fn field(&self, key: &str) -> Option<&str> {
        (self.setting.split(' ')).find_map(|part| part.strip_prefix(key))
    }

    /// The series a point belongs to: the method, its step cap when it is not the method's
    /// usual one (one DOP853 setting runs at 1e-3 s instead of 1e-4 s, the ode45-like Dopri5
    /// at the paper's 1e-5 s instead of 1e-3 s), and its step control when the setting names
    /// one (the scenes' PI.4.2 row): a line joins one method under one controller only.
    fn group(&self) -> String {
        let series = match (self.method.as_str(), self.field("max_step=")) {
            ("dop853", Some(cap)) if cap != "1e-4" => format!("dop853, max step {cap} s"),
            // the ode45-like setting at the paper's maximum step
            ("dopri5", Some(cap)) if cap != "1e-3" => format!("dopri5, max step {cap} s"),
            (m, _) => m.to_owned(),
        };
        match self.field("step_control=") {
            Some(control) => format!("{series}, step control {control}"),
            None => series,
        }
    }
}

/// The drawn settings of one series in one panel: evaluations, errors and point labels.
type Drawn = (Vec<f64>, Vec<f64>, Vec<String>);

/// Redraws `figures/work_precision.png` from `data/work_precision.csv` (the study's last
/// results), so the figure follows changes of its drawing without the study's two minutes;
/// refused ([`crate::Error::Stale`]) unless its record shows the CSV is this checkout's.
pub fn redraw_work_precision() -> Result<()> {
    crate::paper::provenance::check(&[&PROVENANCE])?;
    let path = output_path("data", WORK_PRECISION_FILE);
    let (header, rows) = read_rows(&path)?;
    if header != WORK_PRECISION_HEADER {
        return Err(Error::invalid(
            "data/work_precision.csv",
            header.join(","),
            "the columns of WORK_PRECISION_HEADER (rerun `cargo run --release --bin work_precision`)",
        ));
    }
    let num = |s: &str| s.parse::<f64>().ok();
    let points: Vec<Point> = rows
        .iter()
        .map(|r| {
            let errors = match (num(&r[6]), num(&r[7]), num(&r[8])) {
                (Some(orbit_um), Some(force_rel), Some(wear_rel)) => Some(Errors {
                    orbit_um,
                    force_rel,
                    wear_rel,
                }),
                _ => None,
            };
            let ensemble = match (num(&r[9]), num(&r[10])) {
                (Some(error), Some(sampling)) => Some(EnsembleWearError { error, sampling }),
                _ => None,
            };
            let role = r[1].find(" (");
            Point {
                method: r[0].clone(),
                setting: role.map_or(r[1].as_str(), |i| &r[1][..i]).to_owned(),
                reference: r[1].ends_with("reference)"),
                evaluations: if r[11].is_empty() {
                    num(&r[5]).unwrap_or(0.0)
                } else {
                    0.0
                },
                errors,
                ensemble,
                failure: (!r[11].is_empty()).then(|| r[11].clone()),
            }
        })
        .collect();
    let floor = rows
        .iter()
        .zip(&points)
        .find(|(r, _)| r[1].ends_with("(second reference)"))
        .and_then(|(_, p)| p.errors)
        .ok_or_else(|| {
            Error::invalid(
                "data/work_precision.csv",
                "no second reference",
                "a row of the second reference with its errors",
            )
        })?;
    plot_work_precision(&points, &floor)
}

/// Draws the three panels (orbit, peak force, ensemble wear) from the study's `points` with
/// the error `floor` of the second reference.
pub(super) fn plot_work_precision(points: &[Point], floor: &Errors) -> Result<()> {
    type Pick = fn(&Point) -> Option<f64>;
    let measures: [(&str, &str, Pick); 3] = [
        (
            "Journal orbit, first rotation",
            "max orbit error (µm)",
            |p| p.errors.map(|e| e.orbit_um),
        ),
        (
            "Peak contact force, first rotation",
            "relative peak-force error",
            |p| p.errors.map(|e| e.force_rel),
        ),
        (
            "Wear after 40 rotations, ensemble mean of 16",
            "RMS error of the mean profile / max depth",
            |p| p.ensemble.map(|e| e.error),
        ),
    ];
    let swept: Vec<&Point> = points.iter().filter(|p| !p.reference).collect();
    let mut groups: Vec<String> = Vec::new();
    for p in &swept {
        if !groups.contains(&p.group()) {
            groups.push(p.group());
        }
    }
    // [measure][group] = (wall times, errors, labels) of the drawn settings, in the study's
    // order (loosest tolerance first)
    let data: Vec<Vec<Drawn>> = measures
        .iter()
        .map(|(_, _, pick)| {
            groups
                .iter()
                .map(|g| {
                    let drawn: Vec<(f64, f64, String)> = swept
                        .iter()
                        .filter(|p| &p.group() == g)
                        .filter_map(|p| {
                            let e = pick(p).filter(|e| *e > 0.0 && p.evaluations > 0.0)?;
                            Some((p.evaluations, e, p.tolerance()))
                        })
                        .collect();
                    let mut out = (Vec::new(), Vec::new(), Vec::new());
                    for (t, e, label) in drawn {
                        out.0.push(t);
                        out.1.push(e);
                        out.2.push(label);
                    }
                    out
                })
                .collect()
        })
        .collect();
    let times: Vec<f64> = swept
        .iter()
        .map(|p| p.evaluations)
        .filter(|t| *t > 0.0)
        .collect();
    let span = [
        times.iter().copied().fold(f64::INFINITY, f64::min),
        times.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    ];
    // the floors: the second reference's error for one run, the sampling error for ensembles
    let sampling = Distribution::of(points.iter().filter_map(|p| p.ensemble.map(|e| e.sampling)));
    let floors = [
        ("error floor (the two references disagree)", floor.orbit_um),
        ("error floor (the two references disagree)", floor.force_rel),
        (
            "sampling error of the difference (median)",
            sampling.median(),
        ),
    ]
    .map(|(label, y)| (label, [y; 2]));
    // settings without a point in a panel, and why
    let missing = |pick: Pick| -> Option<String> {
        let lines: Vec<String> = swept
            .iter()
            .filter(|p| pick(p).is_none_or(|e| e <= 0.0) || p.evaluations <= 0.0)
            .map(|p| {
                let why = match (&p.failure, p.errors) {
                    (Some(_), _) | (None, None) => {
                        "the run failed (data/work_precision.csv)".to_owned()
                    }
                    _ => format!(
                        "no wear ensemble: its single run takes over {} evaluations",
                        count(WP_ENSEMBLE_MAX_EVALUATIONS)
                    ),
                };
                format!("not drawn: {} {}, {why}", p.method, p.tolerance())
            })
            .collect();
        (!lines.is_empty()).then(|| lines.join("\n"))
    };
    let panels: Vec<Axes> = measures
        .iter()
        .zip(&data)
        .zip(&floors)
        .map(|(((title, y, pick), per_group), (label, fl))| {
            let mut series: Vec<Series> = groups
                .iter()
                .zip(per_group)
                .map(|(g, (x, y, _))| Series::new(g.as_str(), x, y, Style::LinePoints))
                .collect();
            series.push(Series::new(*label, &span, fl, Style::Reference));
            // the loosest setting of each line labelled on its left (the line leaves it to the
            // right), the tightest on its right: no label lies on its own line
            let end = |(x, y, l): &Drawn, i: usize| (x[i], y[i], l[i].clone());
            let drawn = per_group.iter().filter(|(x, ..)| !x.is_empty());
            let point_labels_left = drawn.clone().map(|d| end(d, 0)).collect();
            let point_labels = (drawn.filter(|(x, ..)| x.len() > 1))
                .map(|d| end(d, d.0.len() - 1))
                .collect();
            Axes {
                x_log: true,
                y_log: true,
                point_labels,
                point_labels_left,
                note: missing(*pick),
                ..Axes::new(
                    *title,
                    "right-hand-side evaluations of one 40-rotation run (ends labelled rtol, or step of rk4)",
                    *y,
                    series,
                )
            }
        })
        .collect();
    render_column(&output_path("figures", WORK_PRECISION_FIGURE), &panels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ode::Method;
    use crate::paper::studies::work_precision::{ODE45_PAPER, SCENE};
    use crate::paper::studies::Integration;

    // Checked to fail with the step control left out of the key: the scenes' PI.4.2 row
    // joined the I controller's Dopri5 line.
    #[test]
    fn a_series_holds_one_method_under_one_controller() {
        let point = |int: &Integration| Point {
            method: int.method_name().into(),
            setting: int.setting(),
            reference: false,
            evaluations: 1.0,
            errors: None,
            ensemble: None,
            failure: None,
        };
        let groups = [
            &Integration::adaptive(Method::Dopri5, 1e-7),
            &SCENE,
            &ODE45_PAPER,
        ]
        .map(|int| point(int).group());
        assert_eq!(
            groups,
            [
                "dopri5",
                "dopri5, step control pi42",
                "dopri5, max step 1e-5 s"
            ]
        );
    }
}
