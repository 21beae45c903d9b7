//! Axes of a panel: the range, the tick labels (with a common "×10ⁿ" factor for very small or
//! large values) and the room the labels need.

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
        let points = RangedCoordf64::from(lo..hi).key_points(ticks);
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
        }
    }

    /// The tick label of `v` (divided by the common factor; a true minus sign).
    pub(super) fn label(&self, v: f64) -> String {
        let s = format!("{:.*}", self.decimals, v / 10f64.powi(self.exp));
        match s.strip_prefix('-') {
            Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_owned(),
            Some(rest) => format!("\u{2212}{rest}"),
            None => s,
        }
    }

    /// Common factor shown at the end of the axis, e.g. "×10⁻⁹".
    pub(super) fn factor(&self) -> Option<String> {
        const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
        (self.exp != 0).then(|| {
            let digits = self.exp.to_string();
            let sup = digits
                .chars()
                .map(|c| c.to_digit(10).map_or('⁻', |d| SUP[d as usize]));
            "×10".chars().chain(sup).collect()
        })
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
