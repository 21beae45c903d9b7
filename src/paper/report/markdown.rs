//! Markdown and environment helpers of the report: tables, the CSV tables of `data/`, and
//! what the report says about the machine it ran on.

use crate::io::output::read_rows;
use crate::paper::figures::output_path;
use crate::paper::format::{self, sci, sig};
use std::fmt::Write as _;

/// A p value for people: three significant digits, in scientific notation below 10⁻³.
pub(super) fn p_value(p: f64) -> String {
    if p < 1e-3 {
        sci(p)
    } else {
        sig(p)
    }
}

/// A tested p as the report's tables print it: the raw `p`, and beside it the Holm-adjusted
/// `p_holm` the significance call rests on, bold when `significant` (sections 2 and 8 alike).
pub(super) fn p_cell(p: f64, p_holm: f64, significant: bool) -> String {
    let holm = format!("Holm {}", p_value(p_holm));
    let holm = if significant {
        format!("**{holm}**")
    } else {
        holm
    };
    format!("p = {} ({holm})", p_value(p))
}

/// A markdown table, every header and cell as a person reads it ([`format::header`],
/// [`format::column`]: CSV column names with their units in words, no e-notation counts or
/// 15-digit times, no Rust names).
pub(super) fn md_table(out: &mut String, header: &[&str], rows: &[Vec<String>]) {
    let header: Vec<String> = header.iter().map(|h| format::header(h)).collect();
    let _ = writeln!(out, "| {} |", header.join(" | "));
    let _ = writeln!(out, "|{}", "---|".repeat(header.len()));
    let columns: Vec<Vec<String>> = (0..header.len())
        .map(|j| {
            let cells: Vec<&str> = rows
                .iter()
                .map(|r| r.get(j).map_or("", String::as_str))
                .collect();
            format::column(&cells)
        })
        .collect();
    for i in 0..rows.len() {
        // a `|` inside a cell (|slider acceleration|) would end the cell
        let cells: Vec<String> = columns.iter().map(|c| c[i].replace('|', "\\|")).collect();
        let _ = writeln!(out, "| {} |", cells.join(" | "));
    }
    out.push('\n');
}

/// A CSV of `data/` as a markdown table, or a note of the command that makes it.
pub(super) fn csv_table(out: &mut String, file: &str, command: &str) {
    match read_rows(&output_path("data", file)) {
        Ok((header, rows)) => {
            let header: Vec<&str> = header.iter().map(String::as_str).collect();
            md_table(out, &header, &rows);
        }
        Err(_) => {
            let _ = writeln!(out, "*`data/{file}` is missing: run `{command}`.*\n");
        }
    }
}
