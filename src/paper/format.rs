//! Numbers formatted for people, used by the figures' text and by `paper.md`: significant
//! digits without trailing zeros, counts with thousands grouped, durations with a sensible
//! precision. (Data files keep full precision; these are for text a person reads.)

/// `v` with three significant digits and no trailing zeros: 20, 0.5, 0.000123, 1230000.
pub fn sig(v: f64) -> String {
    sig_n(v, 3)
}

/// `v` with `digits` significant digits (at least 1) and no trailing zeros after the point.
pub fn sig_n(v: f64, digits: i32) -> String {
    if v == 0.0 || !v.is_finite() {
        return v.to_string();
    }
    let decimals = (digits.max(1) - 1 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// A count with its thousands grouped by thin spaces: 20 000 000.
pub fn count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
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
    }
}
