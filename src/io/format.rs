//! Numbers for people on the terminal: what the programs print (the figures' text and
//! `paper.md` use `jointwear::paper::format`, with grouped counts and ×10ⁿ). A
//! printed number has 3-4 significant digits and its unit, ordinary magnitudes without
//! e-notation, counts as integers and angles wrapped. Files keep full precision instead
//! ([`crate::io::output::number`]), and values a person gave (a scene's) are echoed with that.

/// `v` with `digits` significant digits (at least 1) and no trailing zeros after the point:
/// 20, 0.5, 0.000123, 1230000.
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

/// Magnitudes printed without e-notation: [10⁻³, 10⁶).
const PLAIN: std::ops::Range<f64> = 1e-3..1e6;

/// A number for the terminal: an integer as its digits (`598063`, `2`), a magnitude in
/// [10⁻³, 10⁶) with four significant digits (`185.1`, `0.6834`, `3222`), anything else in
/// e-notation with three (`1.02e-5`, `2.5e9`); `n/a` for NaN, `0` for ±0.
pub fn number(v: f64) -> String {
    if v.is_nan() {
        return "n/a".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    if v.fract() == 0.0 && v.abs() < 1e15 {
        return format!("{v:.0}");
    }
    if PLAIN.contains(&v.abs()) {
        return sig_n(v, 4);
    }
    let e = format!("{v:.2e}");
    // 2.50e9 → 2.5e9, 1.00e-7 → 1e-7: no trailing zeros, as in the plain form
    match e.split_once('e') {
        Some((m, exp)) if m.contains('.') => {
            format!("{}e{exp}", m.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => e,
    }
}

/// [`number`]`(v)` and its unit: `185.1 deg`, `0.6834 µm`; the number alone for an empty
/// unit.
pub fn quantity(v: f64, unit: &str) -> String {
    if unit.is_empty() {
        number(v)
    } else {
        format!("{} {unit}", number(v))
    }
}

/// A spread (a standard deviation, an error): three significant digits, for `mean ± sd`.
pub fn spread(v: f64) -> String {
    // a tenth of the plain range's floor: the spread of a mean just above it
    if (1e-4..PLAIN.end).contains(&v.abs()) {
        sig_n(v, 3)
    } else {
        number(v)
    }
}

/// `v` exactly, for echoing a value a person gave: the shortest digits that read back the
/// identical `f64`, plain for magnitudes in [10⁻⁴, 10¹⁶) (`1000`, `0.00025`), in e-notation
/// outside it (`1e-12`), as Python writes floats.
pub fn exact(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `v` × 10^`exp` computed on `v`'s shortest decimal digits, so that a value a person gave in
/// one unit reads the same in another: 0.02 (mm) gives 2e-5 (m), where 0.02 × 10⁻³ is
/// 2.0000000000000002e-5 and 0.02 / 1000 misses in a fifth of such values.
pub fn shift_decimal(v: f64, exp: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let text = format!("{v:e}");
    match text.split_once('e').map(|(m, e)| (m, e.parse::<i32>())) {
        Some((mantissa, Ok(e))) => format!("{mantissa}e{}", e + exp).parse().unwrap_or(v),
        _ => v,
    }
}

/// An angle (deg) wrapped to [0, 360): a direction, such as a bearing angle.
pub fn direction_deg(v: f64) -> f64 {
    let w = v.rem_euclid(360.0);
    // rem_euclid of a tiny negative angle rounds to 360 itself
    if w >= 360.0 {
        0.0
    } else {
        w
    }
}

/// An angle (deg) wrapped to (-180, 180]: a turn or a body's orientation, whose sign matters.
pub fn turn_deg(v: f64) -> f64 {
    let w = direction_deg(v);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// How a person reads a quantity named with its SI unit suffix (`max_wear_depth_m`,
/// `max_normal_force_recorded_n`): its name in words, the unit printed and the factor from
/// the SI value to it (lengths in µm, the scale of penetrations and wear).
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// The name in words, without the unit: `max wear depth`.
    pub label: String,
    /// The unit printed (empty for a ratio or a count per rotation).
    pub unit: &'static str,
    /// SI value × `scale` = the printed value.
    pub scale: f64,
}

impl Reading {
    /// The reading of the quantity `name` (suffixes `_m`, `_n`, `_deg`, `_s`, `_pa`; none: a
    /// plain number).
    pub fn of(name: &str) -> Reading {
        const SUFFIXES: [(&str, &str, f64); 5] = [
            ("_m", "µm", 1e6),
            ("_n", "N", 1.0),
            ("_deg", "deg", 1.0),
            ("_s", "s", 1.0),
            ("_pa", "Pa", 1.0),
        ];
        let (stem, unit, scale) = SUFFIXES
            .iter()
            .find_map(|&(s, u, k)| Some((name.strip_suffix(s)?, u, k)))
            .unwrap_or((name, "", 1.0));
        Reading {
            label: stem.replace('_', " "),
            unit,
            scale,
        }
    }

    /// `v` (SI) as [`quantity`] in this reading's unit.
    pub fn value(&self, v: f64) -> String {
        quantity(v * self.scale, self.unit)
    }

    /// `mean ± sd unit` of SI values.
    pub fn mean_sd(&self, mean: f64, sd: f64) -> String {
        let unit = if self.unit.is_empty() { "" } else { " " };
        format!(
            "{} ± {}{unit}{}",
            number(mean * self.scale),
            spread(sd * self.scale),
            self.unit
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each line is a case the issue met (`1.850625e2 ± 8.14e-1`, `6e5` among `598063`,
    /// -2466 deg) or a magnitude at a boundary of the plain range.
    #[test]
    fn people_read_these() {
        assert_eq!(number(185.0625), "185.1");
        assert_eq!(spread(0.814), "0.814");
        assert_eq!(number(600_000.0), "600000");
        assert_eq!(number(598_063.0), "598063");
        assert_eq!(number(0.683_41), "0.6834");
        assert_eq!(number(1.018307e-5), "1.02e-5");
        assert_eq!(number(2.5e9 + 0.5), "2.5e9");
        assert_eq!(number(1e-7 + 1e-23), "1e-7");
        assert_eq!(number(0.001), "0.001");
        assert_eq!(number(999_999.5), "1000000");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(f64::NAN), "n/a");
        assert_eq!(quantity(3222.304, "N"), "3222 N");
        assert_eq!(sig_n(0.15999999999, 3), "0.16");
        assert_eq!(exact(-2000.0), "-2000");
        assert_eq!(exact(0.00025), "0.00025");
        assert_eq!(exact(1e-12), "1e-12");
        assert_eq!(exact(-1999.9999999999998), "-1999.9999999999998");
        assert_eq!(shift_decimal(0.02, -3), 2e-5);
        assert_eq!(shift_decimal(-2000.0, 0), -2000.0);
        assert_eq!(shift_decimal(1.25e-300, -3), 1.25e-303);
        assert_eq!(direction_deg(-2466.0), 54.0);
        assert_eq!(direction_deg(-1e-20), 0.0);
        assert_eq!(turn_deg(-2466.0), 54.0);
        assert_eq!(turn_deg(190.0), -170.0);
        assert_eq!(turn_deg(-180.0), 180.0);
        let depth = Reading::of("max_wear_depth_m");
        assert_eq!(depth.label, "max wear depth");
        assert_eq!(depth.mean_sd(3.419926e-8, 7.36e-10), "0.0342 ± 0.000736 µm");
        assert_eq!(Reading::of("contact_fraction").value(0.9845), "0.9845");
        assert_eq!(
            Reading::of("max_wear_angle_deg").mean_sd(185.0625, 0.814),
            "185.1 ± 0.814 deg"
        );
    }
}
