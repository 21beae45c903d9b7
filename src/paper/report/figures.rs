//! Section 3 of `paper.md`, the figures, and the table of contents of the whole report.
//!
//! A figure's program prints summary lines per case (mean ± sd over the members); figures that
//! draw the same ensemble print the same lines, so the report lists a case's lines under the
//! first figure that draws it and points back there from the later ones.

use super::DrawnFigure;
use std::collections::HashMap;
use std::fmt::Write as _;

/// The heading of a figure: `Figure 3: caption`.
fn heading(name: &str, caption: &str) -> String {
    let number = name.trim_start_matches("fig").trim_start_matches('0');
    format!("Figure {number}: {caption}")
}

/// The GitHub anchor of a markdown heading: lower case, punctuation other than `-` and `_`
/// dropped, spaces as hyphens.
pub(super) fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The case a summary line is about: the text before its first " (" or ":".
fn case_of(line: &str) -> &str {
    let end = [line.find(" ("), line.find(':')]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(line.len());
    &line[..end]
}

/// Section 3: every drawn figure with its command, its summary lines (a case's lines once,
/// under the first figure that draws it) and its picture.
pub(super) fn figures_section(md: &mut String, n: usize, drawn: &[DrawnFigure]) {
    md.push_str("## 3. Figures\n\n");
    let _ = writeln!(
        md,
        "Wear figures draw the mean of the {n} members with the 5-95 % band shaded; time-series and \
         trajectory figures draw the first member (a trajectory cannot be averaged) and name its steady \
         state and how many members share it, and their lines give mean ± sd over all members. Each program computes only the ensembles it draws; a case's \
         statistics are listed under the first figure that draws it.\n"
    );
    // line -> heading of the figure that listed it first
    let mut listed: HashMap<&str, String> = HashMap::new();
    for DrawnFigure { figure, lines } in drawn.iter().filter(|d| d.figure.png) {
        let (name, title) = (figure.name, heading(figure.name, figure.caption));
        let _ = writeln!(md, "### {title}\n");
        let _ = writeln!(
            md,
            "`cargo run --release --bin {name}` → `figures/{name}.png`, `data/{name}.csv`\n"
        );
        let mut pointed: Vec<&str> = Vec::new();
        for line in lines {
            match listed.get(line.as_str()) {
                Some(first) => {
                    let case = case_of(line);
                    if !pointed.contains(&case) {
                        pointed.push(case);
                        let short = first.split(':').next().unwrap_or(first);
                        let _ = writeln!(
                            md,
                            "- {case}: the same ensemble as [{short}](#{})",
                            anchor(first)
                        );
                    }
                }
                None => {
                    listed.insert(line, title.clone());
                    let _ = writeln!(md, "- {line}");
                }
            }
        }
        let _ = writeln!(md, "\n![{name}](figures/{name}.png)\n");
    }
}

/// A table of contents of the `##` and `###` headings of `md`, linked to their anchors.
pub(super) fn table_of_contents(md: &str) -> String {
    let mut toc = String::from("## Contents\n\n");
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut in_code = false;
    for line in md.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
        }
        let (depth, text) = match line {
            _ if in_code => continue,
            l if l.starts_with("### ") => (1, &l[4..]),
            l if l.starts_with("## ") => (0, &l[3..]),
            _ => continue,
        };
        let base = anchor(text);
        let k = seen.entry(base.clone()).or_insert(0);
        let link = if *k == 0 { base } else { format!("{base}-{k}") };
        *k += 1;
        let _ = writeln!(toc, "{}- [{text}](#{link})", "  ".repeat(depth));
    }
    toc.push('\n');
    toc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anchors_follow_github() {
        assert_eq!(
            anchor("Figure 8: Journal trajectory for radial clearances 0.2 mm and 0.5 mm"),
            "figure-8-journal-trajectory-for-radial-clearances-02-mm-and-05-mm"
        );
        assert_eq!(anchor("2. Table 3: concordance"), "2-table-3-concordance");
    }

    #[test]
    fn contents_list_both_levels() {
        let toc = table_of_contents("# T\n\n## 1. A\n\n### B b\n\n```\n## not\n```\n");
        assert_eq!(toc, "## Contents\n\n- [1. A](#1-a)\n  - [B b](#b-b)\n\n");
    }
}
