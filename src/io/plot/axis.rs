//! Axes of a panel: the range, the tick labels (with a common "×10ⁿ" factor for very small or
//! large values, or decades "10ⁿ" on a logarithmic axis) and the room the labels need.
//!
//! A logarithmic axis holds log10 of the data: its range runs over whole decades and its tick
//! labels are the decades.

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

use super::theme::{DESC_PX, TICK_CHAR_PX};

/// An axis range with its tick-label format: labels show `v / 10^exp` with `decimals` digits.
pub(super) struct Axis {
    /// Lower end of the range.
    pub(super) lo: f64,
    /// Upper end of the range.
    pub(super) hi: f64,
    exp: i32,
    decimals: usize,
    ticks: usize,
    /// Whether the axis holds log10 of the data (ticks at whole decades).
    pub(super) log: bool,
}

/// `n` in superscript digits with a true minus sign: `⁻⁴` (axis factors here, and the
/// report's scientific notation).
pub fn superscript(n: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    n.to_string()
        .chars()
        .map(|c| c.to_digit(10).map_or('⁻', |d| SUP[d as usize]))
        .collect()
}

impl Axis {
    /// The axis over `(lo, hi)` with about `ticks` tick labels.
    pub(super) fn new((lo, hi): (f64, f64), ticks: usize) -> Self {
        let max_abs = lo.abs().max(hi.abs());
        let exp = if !(1e-3..1e5).contains(&max_abs) {
            max_abs.log10().floor() as i32
        } else {
            0
        };
        // plotters 0.3.7 finds no key point at all on some narrow ranges far from zero (170 ±
        // 0.04 for 3 or 4 ticks, an inset of a mechanism picture): ask for more until it does.
        let key_points = |n: usize| (n, RangedCoordf64::from(lo..hi).key_points(n));
        let (ticks, points) = (ticks..3 * ticks.max(1))
            .map(key_points)
            .find(|(_, p)| p.len() >= 2)
            .unwrap_or_else(|| key_points(ticks));
        let step = points
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(hi - lo, f64::min);
        let scaled = step / 10f64.powi(exp);
        let decimals = (-scaled.log10() - 1e-6).ceil().clamp(0.0, 12.0) as usize;
        Axis {
            lo,
            hi,
            exp,
            decimals,
            ticks,
            log: false,
        }
    }

    /// A logarithmic axis over log10 values `(lo, hi)`, widened to whole decades (at least one).
    pub(super) fn log((lo, hi): (f64, f64)) -> Self {
        let lo = (lo + 1e-9).floor();
        let hi = (hi - 1e-9).ceil().max(lo + 1.0);
        let decades = (hi - lo) as usize;
        Axis {
            lo,
            hi,
            exp: 0,
            decimals: 0,
            // one label per decade, or per second, third... decade on a long axis
            ticks: decades.div_ceil(decades.div_ceil(10)) + 1,
            log: true,
        }
    }

    /// How many tick labels to ask plotters for.
    pub(super) fn ticks(&self) -> usize {
        self.ticks
    }

    /// Positions of the minor grid lines of a logarithmic axis (log10 of 2..9 × 10ⁿ), when its
    /// decades are labelled one by one; empty for a linear axis.
    pub(super) fn minor(&self) -> Vec<f64> {
        if !self.log || self.hi - self.lo > 10.0 {
            return Vec::new();
        }
        let (first, last) = (self.lo as i32, self.hi as i32);
        (first..last)
            .flat_map(|n| (2..10).map(move |k| f64::from(n) + f64::from(k).log10()))
            .collect()
    }

    /// The tick label of `v` (divided by the common factor; a true minus sign).
    pub(super) fn label(&self, v: f64) -> String {
        if self.log {
            let n = v.round();
            return if (v - n).abs() < 1e-6 {
                format!("10{}", superscript(n as i32))
            } else {
                String::new()
            };
        }
        let s = format!("{:.*}", self.decimals, v / 10f64.powi(self.exp));
        match s.strip_prefix('-') {
            Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_owned(),
            Some(rest) => format!("\u{2212}{rest}"),
            None => s,
        }
    }

    /// Common factor shown at the end of the axis, e.g. "×10⁻⁹".
    pub(super) fn factor(&self) -> Option<String> {
        (self.exp != 0).then(|| format!("×10{}", superscript(self.exp)))
    }

    /// Width of the label area needed by the tick labels plus the rotated axis description.
    pub(super) fn label_area(&self) -> u32 {
        let widest = RangedCoordf64::from(self.lo..self.hi)
            .key_points(self.ticks)
            .into_iter()
            .map(|v| self.label(v).chars().count())
            .max()
            .unwrap_or(1) as u32;
        widest * TICK_CHAR_PX + DESC_PX + 22
    }

    /// Length of the range.
    pub(super) fn span(&self) -> f64 {
        self.hi - self.lo
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_narrow_range_far_from_zero_still_gets_ticks() {
        let axis = Axis::new((169.96, 170.04), 4);
        let n = RangedCoordf64::from(axis.lo..axis.hi)
            .key_points(axis.ticks())
            .len();
        assert!(n >= 2, "{n} ticks");
    }
}
