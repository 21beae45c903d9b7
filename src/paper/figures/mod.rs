//! The paper's figures and Table 3 as library functions, drawn from ensembles
//! ([`crate::paper::cases`]).
//!
//! Each [`Figure`] names the ensembles it needs, and draws `figures/<name>.png` and writes
//! `data/<name>.csv` atomically from them. Wear figures draw the ensemble mean with the band
//! that holds 90 % of the members (5 %–95 % quantiles, shaded); time-series figures draw the
//! first member (a trajectory cannot be averaged) and their summary lines give mean ± sd over
//! all members. The `src/bin/` programs only call [`figure_main`]; the report computes every
//! ensemble once and draws every figure from it.
//!
//! Owns: the list of figures ([`FIGURES`]), where outputs go ([`output_path`]), the cases a
//! figure compares ([`Varied`]) and the figure programs' `main`. The figures themselves:
//! [`time_series`] (figures 3, 4, 8, 9, 12, 13), [`wear_profiles`] (figures 5, 6, 10, 11, 14,
//! 15), [`wear_history`] (figure 7) and [`table3`] (Table 3).

pub mod table3;
pub mod time_series;
pub mod wear_history;
pub mod wear_profiles;

pub use table3::{table3_rows, Table3Row};
pub use wear_history::{share_for_90pct, staircase_shares};
pub use wear_profiles::mean_profile_regions;

use crate::error::exit_on_error;
use crate::paper::cases::{Case, Need, Runs, CASES};
use crate::paper::program;
use crate::simulation::ensemble::EnsembleSettings;
use crate::{Error, Result};
use std::path::PathBuf;

pub use crate::io::paper_claim::output_root;

/// Where generated outputs go: `figures/` and `data/` under [`output_root`].
pub fn output_path(dir: &str, file: &str) -> PathBuf {
    output_root().join(dir).join(file)
}

/// A figure of the paper (or Table 3): the ensembles it reads and how it draws them.
pub struct Figure {
    /// Program and file name, `fig06`.
    pub name: &'static str,
    /// What the paper says it shows.
    pub caption: &'static str,
    /// Whether it draws `figures/<name>.png` (Table 3 writes only its CSV).
    pub png: bool,
    /// The ensembles it reads.
    pub needs: &'static [Need],
    /// Draws the PNG and writes the CSV; returns the lines its program prints.
    pub draw: fn(&Runs) -> Result<Vec<String>>,
}

const STANDARD_STEADY: &[Need] = &[Need::Steady(CASES.standard.scene)];
const STANDARD_WEAR: &[Need] = &[Need::Wear(CASES.standard.scene)];
const CLEARANCE_STEADY: &[Need] = &[
    Need::Steady(CASES.clearance_0_2mm.scene),
    Need::Steady(CASES.clearance_0_5mm.scene),
];
const SPEED_STEADY: &[Need] = &[
    Need::Steady(CASES.speed_30rpm.scene),
    Need::Steady(CASES.speed_600rpm.scene),
];

/// Every figure of the paper, in order, then Table 3.
pub const FIGURES: [Figure; 14] = [
    Figure {
        name: "fig03",
        caption: "Slider acceleration versus wear rate (0.02 mm, 2000 r/min)",
        png: true,
        needs: STANDARD_STEADY,
        draw: time_series::fig03,
    },
    Figure {
        name: "fig04",
        caption: "Journal trajectory (0.02 mm, 2000 r/min)",
        png: true,
        needs: STANDARD_STEADY,
        draw: time_series::fig04,
    },
    Figure {
        name: "fig05",
        caption: "Variation of bearing radius for 40 cycles (caption: 0.002 mm; text: 0.02 mm, 2000 r/min)",
        png: true,
        needs: STANDARD_WEAR,
        draw: wear_profiles::fig05,
    },
    Figure {
        name: "fig06",
        caption: "Variation of bearing radius with crank rotation, 10-40 rotations (0.02 mm, 2000 r/min)",
        png: true,
        needs: STANDARD_WEAR,
        draw: wear_profiles::fig06,
    },
    Figure {
        name: "fig07",
        caption: "Variation of bearing radius in the three severe regions (0.02 mm, 2000 r/min)",
        png: true,
        needs: &[Need::WearHistory(CASES.standard.scene)],
        draw: wear_history::fig07,
    },
    Figure {
        name: "fig08",
        caption: "Journal trajectory for radial clearances 0.2 mm and 0.5 mm",
        png: true,
        needs: CLEARANCE_STEADY,
        draw: time_series::fig08,
    },
    Figure {
        name: "fig09",
        caption: "Slider acceleration versus wear rate for 0.2 mm and 0.5 mm",
        png: true,
        needs: CLEARANCE_STEADY,
        draw: time_series::fig09,
    },
    Figure {
        name: "fig10",
        caption: "Variation of bearing radius for 0.2 mm and 0.5 mm",
        png: true,
        needs: &[
            Need::Wear(CASES.clearance_0_2mm.scene),
            Need::Wear(CASES.clearance_0_5mm.scene),
        ],
        draw: wear_profiles::fig10,
    },
    Figure {
        name: "fig11",
        caption: "Wear depth accumulated for different clearance sizes",
        png: true,
        needs: &[
            Need::Wear(CASES.standard.scene),
            Need::Wear(CASES.clearance_0_2mm.scene),
            Need::Wear(CASES.clearance_0_5mm.scene),
        ],
        draw: wear_profiles::fig11,
    },
    Figure {
        name: "fig12",
        caption: "Journal trajectory at 30 and 600 r/min",
        png: true,
        needs: SPEED_STEADY,
        draw: time_series::fig12,
    },
    Figure {
        name: "fig13",
        caption: "Slider acceleration versus wear rate at 30 and 600 r/min",
        png: true,
        needs: SPEED_STEADY,
        draw: time_series::fig13,
    },
    Figure {
        name: "fig14",
        caption: "Variation of bearing radius at 30 and 600 r/min",
        png: true,
        needs: &[
            Need::Wear(CASES.speed_30rpm.scene),
            Need::Wear(CASES.speed_600rpm.scene),
        ],
        draw: wear_profiles::fig14,
    },
    Figure {
        name: "fig15",
        caption: "Wear depth accumulated for different crank speeds",
        png: true,
        needs: &[
            Need::Wear(CASES.speed_30rpm.scene),
            Need::Wear(CASES.speed_600rpm.scene),
            Need::Wear(CASES.standard.scene),
        ],
        draw: wear_profiles::fig15,
    },
    Figure {
        name: "table3",
        caption: "Table 3: motion state and concordance of the wear-rate drivers",
        png: false,
        needs: &[
            Need::Steady(CASES.speed_30rpm.scene),
            Need::Steady(CASES.speed_600rpm.scene),
            Need::Steady(CASES.standard.scene),
            Need::Steady(CASES.clearance_0_2mm.scene),
            Need::Steady(CASES.clearance_0_5mm.scene),
        ],
        draw: table3::table3,
    },
];

/// Every ensemble any figure needs.
pub fn all_needs() -> Vec<Need> {
    FIGURES
        .iter()
        .flat_map(|f| f.needs.iter().copied())
        .collect()
}

/// What a figure of several cases varies between them: the clearance at 2000 r/min
/// (figures 8-11) or the crank speed at 0.02 mm (figures 12-15).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Varied {
    /// 0.02, 0.2 and 0.5 mm.
    Clearance,
    /// 30, 600 and 2000 r/min.
    Speed,
}

/// One case a figure draws: what tells it apart from the figure's other cases, and its title.
pub(crate) struct CasePanel {
    /// The case.
    pub case: Case,
    /// What the figure varies, whose value of the case tells it apart in the CSV.
    pub varied: Varied,
    /// Title of its panel.
    pub title: String,
}

impl Varied {
    /// The three cases compared, in growing order.
    pub fn cases(self) -> [Case; 3] {
        match self {
            Varied::Clearance => CASES.by_clearance(),
            Varied::Speed => CASES.by_speed(),
        }
        .map(|c| *c)
    }

    /// The value of a case that is varied: clearance (mm) or speed (r/min).
    pub fn key(self, case: &Case) -> f64 {
        match self {
            Varied::Clearance => case.clearance_mm,
            Varied::Speed => case.speed_rpm,
        }
    }

    /// CSV column of the varied value, named with its unit: `clearance_mm` or `speed_rpm`.
    pub fn column(self) -> &'static str {
        match self {
            Varied::Clearance => "clearance_mm",
            Varied::Speed => "speed_rpm",
        }
    }

    /// Legend label of a case: `c = 0.2 mm` or `30 r/min`.
    pub fn label(self, case: &Case) -> String {
        match self {
            Varied::Clearance => format!("c = {} mm", case.clearance_mm),
            Varied::Speed => format!("{} r/min", case.speed_rpm),
        }
    }

    /// CSV column tag of a case: `c0.2mm` or `30rpm`.
    pub fn tag(self, case: &Case) -> String {
        match self {
            Varied::Clearance => format!("c{}mm", case.clearance_mm),
            Varied::Speed => format!("{}rpm", case.speed_rpm),
        }
    }

    /// The two cases other than the standard one, as panels titled `{what}, {label}`
    /// (figures 8-10 and 12-14).
    pub(crate) fn panels(self, what: &str) -> [CasePanel; 2] {
        let [a, b, c] = self.cases();
        let others = match self {
            Varied::Clearance => [b, c],
            Varied::Speed => [a, b],
        };
        others.map(|case| CasePanel {
            case,
            varied: self,
            title: format!("{what}, {}", self.label(&case)),
        })
    }
}

/// The standard case alone, as one panel (figures 3, 4 and 6).
pub(crate) fn standard_panel(title: &str) -> [CasePanel; 1] {
    [CasePanel {
        case: CASES.standard,
        varied: Varied::Clearance,
        title: title.to_string(),
    }]
}

/// `member 0 (0-based) of N` for titles of figures that draw the first member: numbered from
/// 0 as `ensemble_members.csv` and `jointwear run --member` number them.
pub(crate) fn first_of(n: usize) -> String {
    format!("member 0 (0-based) of {n}")
}

/// `main` of a figure program: refuses any argument but `--help`, runs the default ensembles
/// it needs, draws it, prints its summary lines.
pub fn figure_main(name: &str) {
    let Some(figure) = FIGURES.iter().find(|f| f.name == name) else {
        exit_on_error::<()>(Err(Error::invalid("figure", name, "a name of FIGURES")));
        return;
    };
    let png = if figure.png {
        format!("figures/{name}.png and ")
    } else {
        String::new()
    };
    let ensemble = EnsembleSettings::default();
    let about = format!(
        "{}: runs the {}-member ensembles (seed {}) it draws and writes {png}data/{name}.csv",
        figure.caption, ensemble.members, ensemble.seed
    );
    let _claim = program::flags(name, &about, &[]);
    let bar = crate::io::progress::progress_bar(0, "ensemble members");
    let runs = exit_on_error(Runs::compute(figure.needs, ensemble, &|_| {}, &bar));
    bar.finish_and_clear();
    let lines = exit_on_error((figure.draw)(&runs));
    println!(
        "{} from {} members (seed {}) in {:.1} s",
        program::in_root(&format!("wrote {png}data/{name}.csv")),
        ensemble.members,
        ensemble.seed,
        runs.seconds
    );
    for line in &lines {
        println!("{line}");
    }
}
