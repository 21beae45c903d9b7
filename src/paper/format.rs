//! Numbers formatted for people, used by the figures' text and by `paper.md`: significant
//! digits without trailing zeros, counts with thousands grouped, durations with a sensible
//! precision. (Data files keep full precision; these are for text a person reads.)

use crate::analysis::significance::{holm_consistent, FamilyTest};
pub use crate::io::format::sig_n;
use crate::io::plot::superscript;
use crate::laws::friction::FrictionModel;
use crate::laws::wear::PressureModel;

/// `v` with three significant digits and no trailing zeros: 20, 0.5, 0.000123, 1230000.
pub fn sig(v: f64) -> String {
    sig_n(v, 3)
}

/// A count with its thousands grouped by thin spaces from five digits on (SI style): 1692,
/// 20 000 000.
pub fn count(n: u64) -> String {
    let digits = n.to_string();
    if digits.len() < 5 {
        return digits;
    }
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
}

/// A duration in seconds for people: `0.062 s`, `4.1 s`, `62 s`, `2 min 05 s`.
pub fn seconds(t: f64) -> String {
    if !t.is_finite() || t < 0.0 {
        return format!("{t} s");
    }
    if t < 1.0 {
        format!("{t:.3} s")
    } else if t < 10.0 {
        format!("{t:.1} s")
    } else if t < 120.0 {
        format!("{t:.0} s")
    } else {
        let s = t.round() as u64;
        format!("{} min {:02} s", s / 60, s % 60)
    }
}

/// A statistic's CSV cell: seven significant digits in e-notation, empty where it is
/// undefined (a spread of one member, a test not made), so that readers see no number there.
pub fn csv_statistic(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e}")
    } else {
        String::new()
    }
}

/// A cell [`csv_statistic`] wrote: NaN for an empty one (undefined), `None` if it is neither
/// empty nor a number.
pub fn parse_statistic(cell: &str) -> Option<f64> {
    match cell {
        "" => Some(f64::NAN),
        s => s.parse::<f64>().ok(),
    }
}

/// A study's CSV table (its header and rows, as read) parsed row by row by `parse`: `None`
/// when the header is not `header` (a file of another layout, such as one written before its
/// adjusted p column, whose cells would shift), a row does not parse, or a row's adjusted p is
/// not the Holm adjustment of its family's raw p ([`holm_consistent`]).
pub fn parse_adjusted<T: FamilyTest>(
    (found, rows): (Vec<String>, Vec<Vec<String>>),
    header: &[&str],
    parse: impl Fn(&[String]) -> Option<T>,
) -> Option<Vec<T>> {
    if found != header {
        return None;
    }
    let rows: Vec<T> = rows.iter().map(|r| parse(r)).collect::<Option<_>>()?;
    holm_consistent(&rows).then_some(rows)
}

/// `v` in scientific notation for people: `4.24×10⁻⁴`, `3.00×10⁻⁴` (three significant digits),
/// `10⁻⁷` for a power of ten, `0` for 0.
pub fn sci(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let exp = v.abs().log10().floor() as i32;
    let mut mantissa = v / 10f64.powi(exp);
    let mut exp = exp;
    if (mantissa.abs() * 100.0).round() >= 1000.0 {
        mantissa /= 10.0;
        exp += 1;
    }
    let m = format!("{mantissa:.2}").replace('-', "\u{2212}");
    match exp {
        0 => sig_n(v, 3),
        _ if m == "1.00" => format!("10{}", superscript(exp)),
        _ if m == "\u{2212}1.00" => format!("\u{2212}10{}", superscript(exp)),
        _ => format!("{m}×10{}", superscript(exp)),
    }
}

/// A number for people: an integer as a grouped count, a value in [10⁻³, 10⁵) with four
/// significant digits, anything else in scientific notation.
pub fn number(v: f64) -> String {
    if v.is_nan() {
        return "n/a".into();
    }
    if v.fract() == 0.0 && v.abs() < 1e15 {
        let n = count(v.abs() as u64);
        return if v < 0.0 { format!("\u{2212}{n}") } else { n };
    }
    if (1e-3..1e5).contains(&v.abs()) {
        sig_n(v, 4)
    } else {
        sci(v)
    }
}

/// A table cell as a person should read it: numbers in e-notation or with more than six
/// significant digits through [`number`], plain integers of five digits or more grouped,
/// `true`/`false` as yes/no, `NaN` as n/a, the Rust names of the pressure models as words;
/// anything else unchanged (short decimals such as `0.7791` keep their digits).
pub fn cell(text: &str) -> String {
    let t = text.trim();
    match t {
        "true" => return "yes".into(),
        "false" => return "no".into(),
        "NaN" | "nan" => return "n/a".into(),
        _ => {}
    }
    for model in [PressureModel::HertzLine, PressureModel::ElasticFoundation] {
        if t == format!("{model:?}") {
            return pressure_name(model).into();
        }
    }
    let Ok(v) = t.parse::<f64>() else {
        return text.to_owned();
    };
    let digits = t
        .chars()
        .take_while(|c| *c != 'e' && *c != 'E')
        .filter(char::is_ascii_digit)
        .collect::<String>();
    let significant = digits.trim_start_matches('0').len();
    let exponent = t.contains(['e', 'E']);
    let plain_integer = !exponent && !t.contains('.');
    if exponent || significant > 6 || (plain_integer && digits.len() >= 5) {
        number(v)
    } else {
        text.to_owned()
    }
}

/// The cells of one table column as a person reads them: each through [`cell`], except that a
/// column where some number needs scientific notation shows all its fractional numbers in it,
/// so that the magnitudes of one column compare at a glance.
pub fn column(cells: &[&str]) -> Vec<String> {
    let formatted: Vec<String> = cells.iter().map(|c| cell(c)).collect();
    let superscript = |c: char| "⁰¹²³⁴⁵⁶⁷⁸⁹⁻".contains(c);
    let scientific = formatted.iter().any(|f| f.chars().any(superscript));
    cells
        .iter()
        .zip(formatted)
        .map(|(raw, f)| match raw.trim().parse::<f64>() {
            Ok(v) if scientific && v.is_finite() && v.fract() != 0.0 => sci(v),
            _ => f,
        })
        .collect()
}

/// A CSV column name as a table header: `wall_time_s` as `wall time (s)`, units in
/// parentheses; names with a dot (`standard.pw.se`) stay as they are.
pub fn header(name: &str) -> String {
    const SPECIAL: [(&str, &str); 3] = [
        ("k_over_h_per_pa", "k/H (1/Pa)"),
        ("mu_d", "μ_d"),
        ("v_s_m_s", "v_s (m/s)"),
    ];
    const UNITS: [(&str, &str); 12] = [
        ("_per_pa", "1/Pa"),
        ("_m_s2", "m/s²"),
        ("_m_s", "m/s"),
        ("_um", "µm"),
        ("_mm", "mm"),
        ("_ns", "ns"),
        ("_ms", "ms"),
        ("_s", "s"),
        ("_deg", "deg"),
        ("_rel", "relative"),
        ("_n", "N"),
        ("_m", "m"),
    ];
    if name.contains('.') {
        return name.to_owned();
    }
    if let Some((_, h)) = SPECIAL.iter().find(|(n, _)| *n == name) {
        return (*h).to_owned();
    }
    match UNITS
        .iter()
        .find_map(|(s, u)| Some((name.strip_suffix(s)?, u)))
    {
        Some((stem, unit)) => format!("{} ({unit})", stem.replace('_', " ")),
        None => name.replace('_', " "),
    }
}

/// A pressure model in words.
pub fn pressure_name(p: PressureModel) -> &'static str {
    match p {
        PressureModel::HertzLine => "Hertz line contact",
        PressureModel::ElasticFoundation => "elastic foundation",
    }
}

/// A friction law in words with its parameters.
pub fn friction_name(f: &FrictionModel) -> String {
    match *f {
        FrictionModel::None => "none (frictionless)".into(),
        FrictionModel::Coulomb { mu } => format!("Coulomb, μ = {}", sig(mu)),
        FrictionModel::Modified {
            mu_s,
            mu_d,
            v_s,
            v_d,
        } => format!(
            "modified Coulomb (eq. 4): μ_s = {}, μ_d = {}, v_s = {} m/s, v_d = {} m/s",
            sig(mu_s),
            sig(mu_d),
            sig(v_s),
            sig(v_d)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn people_read_these() {
        assert_eq!(sig(20.0), "20");
        assert_eq!(sig(0.5), "0.5");
        assert_eq!(sig(6.638e-5), "0.0000664");
        assert_eq!(sig(0.15999999999), "0.16");
        assert_eq!(count(20_000_000), "20\u{2009}000\u{2009}000");
        assert_eq!(count(999), "999");
        assert_eq!(seconds(62.83333333333), "63 s");
        assert_eq!(seconds(0.0625), "0.062 s");
        assert_eq!(seconds(125.4), "2 min 05 s");
        assert_eq!(sci(4.2438e1), "4.24×10¹");
        assert_eq!(sci(3.6064e-4), "3.61×10⁻⁴");
        assert_eq!(sci(1e-7), "10⁻⁷");
        assert_eq!(number(1.692e3), "1692");
        assert_eq!(number(61536490.0), "61\u{2009}536\u{2009}490");
        assert_eq!(cell("8.667902319474518e0"), "8.668");
        assert_eq!(cell("0.7791"), "0.7791");
        assert_eq!(cell("1.53385235075e9"), "1.53×10⁹");
        assert_eq!(sci(3e-4), "3.00×10⁻⁴");
        assert_eq!(cell("0.0000e0"), "0");
        assert_eq!(cell("HertzLine"), "Hertz line contact");
        assert_eq!(cell("true"), "yes");
        assert_eq!(header("wall_time_s"), "wall time (s)");
        assert_eq!(
            column(&["0.003441", "3.35e-4", "0e0"]),
            ["3.44×10⁻³", "3.35×10⁻⁴", "0"]
        );
        assert_eq!(column(&["10.50", "8.25"]), ["10.50", "8.25"]);
        assert_eq!(header("standard.pw.se"), "standard.pw.se");
    }
}
