//! What the report reads back from `data/` instead of computing it ([`READ_BACK`]): the
//! check of every such study's record before the report computes or reads anything
//! ([`check_read_back`]; [`crate::paper::provenance`] says why it refuses rather than labels),
//! and the paragraph of `paper.md`'s header that lists them.

use super::markdown::md_table;
use crate::paper::provenance::{self, Study};
use crate::Result;
use std::path::Path;

/// Every study whose results the report reads back from `data/` instead of computing them, in
/// the order of `paper.md`'s sections; `report --all` reruns those marked
/// [`Study::rerun_by_all`].
pub const READ_BACK: [&Study; 11] = [
    &crate::paper::perturbation::PROVENANCE,
    &crate::paper::separation::PROVENANCE,
    &crate::paper::convergence::PROVENANCE,
    &crate::paper::calibration::PROVENANCE,
    &crate::paper::studies::work_precision::PROVENANCE,
    &crate::paper::studies::tolerance_rule::PROVENANCE,
    &crate::paper::studies::ensemble_tolerance::PROVENANCE,
    &crate::paper::studies::sector_resolution::PROVENANCE,
    &crate::paper::performance::PROVENANCE,
    &crate::paper::studies::contact_laws::PROVENANCE,
    &crate::paper::studies::contact_law_wear::PROVENANCE,
];

/// Refuses ([`crate::Error::Stale`]) results of [`READ_BACK`] under `data/` that are not this
/// checkout's, all of them named at once; when `rerun_all`, only of the studies `--all` does
/// not rerun. The report's first step, before the minutes it computes: [`super::write`] checks
/// them all again where it reads them.
pub fn check_read_back(rerun_all: bool) -> Result<()> {
    let kept: Vec<&Study> = (READ_BACK.iter().copied())
        .filter(|s| !(rerun_all && s.rerun_by_all))
        .collect();
    provenance::check(&kept)
}

/// The paragraph of `paper.md`'s header that lists the results read back from the data folder
/// `data` and says how they were checked.
pub(super) fn paragraph(rerun_all: bool, data: &Path) -> String {
    let rows: Vec<Vec<String>> = READ_BACK
        .iter()
        .map(|s| {
            let files: Vec<String> = s.files.iter().map(|f| format!("`data/{f}`")).collect();
            let this_run = if rerun_all && s.rerun_by_all {
                "rerun (`--all`)"
            } else if provenance::absent_in(s, data) {
                "missing (its section says so)"
            } else {
                "read back, record matches"
            };
            let figures: Vec<String> = (s.figures.iter())
                .map(|f| format!("`figures/{f}` (not checked)"))
                .collect();
            vec![
                files.join(", "),
                figures.join(", "),
                format!("`{}`", s.command),
                if s.rerun_by_all { "yes" } else { "no" }.into(),
                this_run.into(),
            ]
        })
        .collect();
    let mut md = format!(
        "**Results read back from `data/`.** The studies below are too slow to rerun with every \
         report; their results are read from where their last run left them. Each run leaves a \
         record beside its first CSV (`data/<name>.provenance.json`): the jointwear version and \
         arithmetic it ran under ({} and {} here), the fingerprints of the scenes, the paper's \
         values and the settings it read, and the length and fingerprint of each CSV it wrote. \
         The report is written only when every record matches this checkout (an edited scene or \
         CSV, another version or a missing record stops it, naming the study, what differs and \
         the command that remakes it), so none of these numbers comes from other scenes, paper \
         values, settings or program version than this checkout's; a change of the code that \
         moves them without changing those is not seen. A record covers its study's CSVs, not the \
         figure its run drew (second column): that figure is shown as the run left it, and one \
         edited or replaced since is not seen (every report draws `figures/{}`: from its \
         checked CSV, or by the study's rerun under `--all`). The benchmarks and the SciPy comparison of section 7 are timings from \
         whenever they were last run, carry no record and are not checked.\n\n",
        env!("CARGO_PKG_VERSION"),
        crate::simulation::checkpoint::ARITHMETIC,
        crate::paper::studies::work_precision::WORK_PRECISION_FIGURE
    );
    md_table(
        &mut md,
        &[
            "results",
            "figure",
            "made by",
            "rerun by `report --all`",
            "this run",
        ],
        &rows,
    );
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper::figures::{output_root, FIGURES};
    use crate::paper::studies::work_precision::WORK_PRECISION_FIGURE;
    use crate::Error;
    use std::path::PathBuf;

    /// The committed `data/` is this checkout's: a scene or setting changed without rerunning
    /// the studies that read it fails here, not only in the next report.
    #[test]
    fn the_committed_results_read_back_are_this_checkouts() {
        check_read_back(false).unwrap();
    }

    /// The records fingerprint their CSVs byte for byte, so git must check them out as
    /// committed: converted to CRLF (`core.autocrlf`, the default of git on Windows), every
    /// study was refused as "edited, cut short or replaced", and this test's neighbour failed,
    /// though the numbers were the committed ones. Skipped outside a git work tree.
    #[test]
    fn git_checks_out_the_csvs_read_back_byte_for_byte() {
        let files: Vec<String> = (READ_BACK.iter().flat_map(|s| s.files))
            .map(|f| format!("data/{f}"))
            .collect();
        let out = std::process::Command::new("git")
            .arg("-C")
            .arg(output_root())
            .args(["check-attr", "text", "--"])
            .args(&files)
            .output();
        let Some(out) = out.ok().filter(|o| o.status.success()) else {
            eprintln!(
                "skipped: {} is not a git work tree",
                output_root().display()
            );
            return;
        };
        let said = String::from_utf8_lossy(&out.stdout);
        assert_eq!(said.lines().count(), files.len(), "{said}");
        for line in said.lines() {
            assert!(
                line.ends_with(": text: unset"),
                "{line}: git may convert its line endings (.gitattributes: `data/*.csv -text`)"
            );
        }
    }

    /// A copy of `data/` with what the studies of [`READ_BACK`] read and wrote; removed when
    /// dropped.
    struct Copy(PathBuf);

    impl Copy {
        fn new(name: &str) -> Copy {
            let dir = std::env::temp_dir()
                .join(format!("jointwear-read-back-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            let data = output_root().join("data");
            let copy = |from: &Path, to: &Path| {
                std::fs::create_dir_all(to.parent().unwrap()).unwrap();
                std::fs::copy(from, to).unwrap();
            };
            for sub in ["scenes", "golden"] {
                for entry in std::fs::read_dir(data.join(sub)).unwrap() {
                    let path = entry.unwrap().path();
                    if path.is_file() {
                        copy(&path, &dir.join(sub).join(path.file_name().unwrap()));
                    }
                }
            }
            for study in READ_BACK {
                let stem = study.files[0].trim_end_matches(".csv");
                let record = format!("{stem}.provenance.json");
                for file in study.files.iter().copied().chain([record.as_str()]) {
                    copy(&data.join(file), &dir.join(file));
                }
            }
            Copy(dir)
        }

        /// Replaces the first `from` of `file` by `to`.
        fn edit(&self, file: &str, from: &str, to: &str) {
            crate::test_support::edit_file(&self.0.join(file), from, to);
        }

        /// The first file of each study the report refuses to read back.
        fn refused(&self) -> Vec<String> {
            match provenance::check_in(&READ_BACK, &self.0) {
                Ok(()) => Vec::new(),
                Err(Error::Stale { results }) => results
                    .iter()
                    .map(|r| r.split([':', ' ']).next().unwrap().to_string())
                    .collect(),
                Err(e) => panic!("{e}"),
            }
        }
    }

    impl Drop for Copy {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// A study none of whose CSVs is there passes the check, its section says it is missing,
    /// and so must the header's table: it said "read back, record matches" of results that
    /// were not there.
    #[test]
    fn the_header_says_a_missing_study_is_missing() {
        let copy = Copy::new("absent");
        for file in ["scaling.csv", "step_limit.csv"] {
            std::fs::remove_file(copy.0.join(file)).unwrap();
        }
        assert!(copy.refused().is_empty(), "{:?}", copy.refused());
        let md = paragraph(false, &copy.0);
        let row = |first: &str| {
            let row = md
                .lines()
                .find(|l| l.starts_with(&format!("| `data/{first}`")));
            row.unwrap_or_else(|| panic!("a row of {first} in {md}"))
                .to_string()
        };
        let scaling = row("scaling.csv");
        assert!(
            scaling.contains("missing") && !scaling.contains("record matches"),
            "{scaling}"
        );
        assert!(row("calibration.csv").contains("read back, record matches"));
        // rerun by `--all`, it is this run's whatever it was before
        std::fs::remove_file(copy.0.join("calibration.csv")).unwrap();
        let all = paragraph(true, &copy.0);
        assert!(
            all.contains("calibration` | yes | rerun (`--all`) |"),
            "{all}"
        );
    }

    /// Every figure `paper.md` shows is drawn by the report (the paper's figures; the
    /// work-precision figure, redrawn from its checked CSV) or one its study lists as not
    /// covered by its record, and the header names each of those as unchecked: it said every
    /// number was this checkout's while `figures/scaling.png` and four others were shown as
    /// whatever last wrote them.
    #[test]
    fn every_figure_shown_is_the_reports_own_or_said_unchecked() {
        let md = std::fs::read_to_string(output_root().join("paper.md")).unwrap();
        let unchecked: Vec<&str> = READ_BACK.iter().flat_map(|s| s.figures).copied().collect();
        let own = |file: &str| {
            file == WORK_PRECISION_FIGURE
                || (FIGURES.iter()).any(|f| f.png && file == format!("{}.png", f.name))
        };
        let shown: Vec<&str> = (md.split("](figures/").skip(1))
            .map(|rest| &rest[..rest.find(')').unwrap()])
            .collect();
        assert!(shown.len() > 13, "{shown:?}");
        for file in shown {
            assert!(
                own(file) || unchecked.contains(&file),
                "paper.md shows figures/{file}, neither drawn by the report nor said unchecked"
            );
        }
        let committed = &md[..md.find("**Results are ensemble statistics.**").unwrap()];
        let header = paragraph(false, &output_root().join("data"));
        for file in unchecked {
            let named = format!("`figures/{file}` (not checked)");
            assert!(header.contains(&named), "{named} in {header}");
            assert!(committed.contains(&named), "{named} in paper.md's header");
        }
    }

    // Fails with the check disabled (`provenance::check_in` returning Ok(()) at once): every
    // study below is read back as if it were current.

    #[test]
    fn a_changed_scene_stops_every_study_that_reads_it_and_only_those() {
        let copy = Copy::new("scene");
        assert!(copy.refused().is_empty(), "{:?}", copy.refused());
        // read by the Table 3 and wear studies, not by the standard scene's or the impact's
        copy.edit("scenes/clearance_0.5mm.toml", "_mm\" = 0.5", "_mm\" = 0.45");
        assert_eq!(
            copy.refused(),
            [
                "data/perturbation_sensitivity.csv",
                "data/member_separation.csv",
                "data/ensemble_convergence.csv",
                "data/calibration.csv",
                "data/ensemble_tolerance.csv",
                "data/sector_resolution.csv",
                "data/contact_law_wear.csv",
            ]
        );
    }

    #[test]
    fn an_edited_row_a_cut_csv_a_missing_or_foreign_record_are_each_refused() {
        let copy = Copy::new("files");
        // a digit of a row
        let text = std::fs::read_to_string(copy.0.join("calibration.csv")).unwrap();
        let row = text.lines().nth(3).unwrap();
        copy.edit("calibration.csv", row, &row.replacen("0.", "1.", 1));
        // the last rows of a file
        let path = copy.0.join("perturbation_sensitivity.csv");
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, &text[..text.len() / 2]).unwrap();
        // one of two files of a study
        std::fs::write(copy.0.join("step_limit.csv"), "t_s\n").unwrap();
        // a record gone
        std::fs::remove_file(copy.0.join("ensemble_convergence.provenance.json")).unwrap();
        // a record of another version
        let version = format!("\"jointwear\": \"{}\"", env!("CARGO_PKG_VERSION"));
        copy.edit(
            "contact_laws_restitution.provenance.json",
            &version,
            "\"jointwear\": \"0.0.1\"",
        );
        assert_eq!(
            copy.refused(),
            [
                "data/perturbation_sensitivity.csv",
                "data/ensemble_convergence.csv",
                "data/calibration.csv",
                "data/scaling.csv",
                "data/contact_laws_restitution.csv",
            ]
        );
    }
}
