//! Statistics over the members of an ensemble: the distribution of a scalar result, a
//! per-sector band of a wear profile, and the fractions of categorical results.
//!
//! Quantiles interpolate linearly between order statistics (Hyndman and Fan's type 7, the
//! default of R and NumPy): `Q(p) = x₍ⱼ₎ + (h − j)(x₍ⱼ₊₁₎ − x₍ⱼ₎)` with `h = (n − 1) p`, for the
//! sorted values `x₍₀₎ ≤ … ≤ x₍ₙ₋₁₎`. The standard deviation is the sample one (n − 1), and the
//! standard error of the mean is `sd / √n`.

/// Quantiles reported for every distribution and band.
pub const QUANTILES: [f64; 5] = [0.05, 0.25, 0.5, 0.75, 0.95];

/// Names of a distribution's numbers ([`Distribution::values`]), as every output spells them:
/// mean, sd, min, the [`QUANTILES`] as `qNN` (percent), max.
pub const VALUE_KEYS: [&str; 9] = [
    "mean", "sd", "min", "q05", "q25", "q50", "q75", "q95", "max",
];

/// Distribution of one scalar over the members (non-finite values are not counted).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distribution {
    /// Finite values counted.
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// Sample standard deviation (0 for a single value).
    pub sd: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// The [`QUANTILES`], in order.
    pub quantiles: [f64; 5],
}

/// Type-7 quantile `p` (clamped to [0, 1]) of sorted values; NaN when there are none.
pub fn quantile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * p.clamp(0.0, 1.0);
    let j = h.floor() as usize;
    match sorted.get(j + 1) {
        Some(next) => sorted[j] + (h - j as f64) * (next - sorted[j]),
        None => sorted[j],
    }
}

impl Distribution {
    /// Its numbers in the order of [`VALUE_KEYS`] (the count `n` apart).
    pub fn values(&self) -> [f64; 9] {
        let q = self.quantiles;
        [
            self.mean, self.sd, self.min, q[0], q[1], q[2], q[3], q[4], self.max,
        ]
    }

    /// The distribution of the finite `values`; every statistic is NaN when there are none.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Distribution {
        let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        let n = v.len();
        if n == 0 {
            return Distribution {
                n,
                mean: f64::NAN,
                sd: f64::NAN,
                min: f64::NAN,
                max: f64::NAN,
                quantiles: [f64::NAN; 5],
            };
        }
        v.sort_by(f64::total_cmp);
        let mean = v.iter().sum::<f64>() / n as f64;
        let ss: f64 = v.iter().map(|x| (x - mean).powi(2)).sum();
        Distribution {
            n,
            mean,
            sd: if n > 1 {
                (ss / (n - 1) as f64).sqrt()
            } else {
                0.0
            },
            min: v[0],
            max: v[n - 1],
            quantiles: QUANTILES.map(|p| quantile(&v, p)),
        }
    }

    /// The distribution of angles in degrees, unwrapped around their circular mean (so 359° and
    /// 1° average to 0°, not 180°); the mean, extremes and quantiles are wrapped back into
    /// [0, 360), so a `min` above `max` says the range crosses 0°.
    pub fn of_angles_deg(values: impl IntoIterator<Item = f64>) -> Distribution {
        Distribution::of(unwrap_angles_deg(values)).wrapped_deg()
    }

    /// The distribution of angles unwrapped by [`unwrap_angles_deg`], its mean, extremes and
    /// quantiles wrapped back into [0, 360).
    pub fn wrapped_deg(mut self) -> Distribution {
        // (`rem_euclid` rounds a tiny negative angle up to 360 itself: 0 is that angle.)
        let wrap = |a: f64| match a.rem_euclid(360.0) {
            360.0 => 0.0,
            w => w,
        };
        self.mean = wrap(self.mean);
        self.min = wrap(self.min);
        self.max = wrap(self.max);
        self.quantiles = self.quantiles.map(wrap);
        self
    }

    /// Standard error of the mean, `sd / √n`; NaN for fewer than two values.
    pub fn standard_error(&self) -> f64 {
        if self.n < 2 {
            return f64::NAN;
        }
        self.sd / (self.n as f64).sqrt()
    }

    /// The median.
    pub fn median(&self) -> f64 {
        self.quantiles[2]
    }

    /// The 5 % and 95 % quantiles: the band that holds nine members in ten.
    pub fn band90(&self) -> (f64, f64) {
        (self.quantiles[0], self.quantiles[4])
    }

    /// `mean ± sd` with `digits` decimals, after multiplying by `scale`.
    pub fn mean_sd(&self, scale: f64, digits: usize) -> String {
        if self.n == 0 {
            return "n/a".into();
        }
        format!(
            "{:.digits$} ± {:.digits$}",
            self.mean * scale,
            self.sd * scale
        )
    }
}

/// Angles in degrees unwrapped around their circular mean, each within 180° of it (so 359° and
/// 1° become −1° and 1° about 0°); a non-finite value stays where it is, NaN, and does not
/// count towards the mean.
pub fn unwrap_angles_deg(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let v: Vec<f64> = values.into_iter().collect();
    let (s, c) = v
        .iter()
        .filter(|a| a.is_finite())
        .fold((0.0, 0.0), |(s, c), a| {
            let (sa, ca) = a.to_radians().sin_cos();
            (s + sa, c + ca)
        });
    let centre = f64::atan2(s, c).to_degrees();
    let unwrap = |a: f64| centre + (a - centre + 180.0).rem_euclid(360.0) - 180.0;
    v.iter()
        .map(|&a| if a.is_finite() { unwrap(a) } else { f64::NAN })
        .collect()
}

/// Per-sector distribution of the members' wear profiles.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// One distribution per sector.
    pub sectors: Vec<Distribution>,
}

impl Band {
    /// The band of equally long `profiles`.
    pub fn of<'a>(profiles: impl IntoIterator<Item = &'a [f64]> + Clone) -> Band {
        let len = profiles
            .clone()
            .into_iter()
            .map(<[f64]>::len)
            .max()
            .unwrap_or(0);
        Band {
            sectors: (0..len)
                .map(|i| {
                    Distribution::of(
                        profiles
                            .clone()
                            .into_iter()
                            .filter_map(|p| p.get(i).copied()),
                    )
                })
                .collect(),
        }
    }

    /// The per-sector means.
    pub fn mean(&self) -> Vec<f64> {
        self.sectors.iter().map(|d| d.mean).collect()
    }

    /// The per-sector quantile `QUANTILES[i]`.
    pub fn quantile(&self, i: usize) -> Vec<f64> {
        self.sectors.iter().map(|d| d.quantiles[i]).collect()
    }
}

/// How many of `labels` carry each distinct label, in order of first appearance.
pub fn fractions<T: PartialEq + Clone>(labels: impl IntoIterator<Item = T>) -> Vec<(T, usize)> {
    let mut counts: Vec<(T, usize)> = Vec::new();
    for l in labels {
        match counts.iter_mut().find(|(k, _)| *k == l) {
            Some((_, c)) => *c += 1,
            None => counts.push((l, 1)),
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn value_keys_name_the_quantiles_in_percent() {
        let named: Vec<String> = QUANTILES.map(|p| format!("q{:02.0}", 100.0 * p)).into();
        assert_eq!(&VALUE_KEYS[3..8], &named[..]);
        let d = Distribution::of([1.0, 2.0, 3.0]);
        let expected = [2.0, 1.0, 1.0, 1.1, 1.5, 2.0, 2.5, 2.9, 3.0];
        for (v, e) in d.values().iter().zip(expected) {
            assert_relative_eq!(*v, e, max_relative = 1e-15);
        }
    }

    #[test]
    fn distribution_matches_hand_computed_values() {
        let d = Distribution::of([4.0, 1.0, 3.0, 2.0, f64::NAN]);
        assert_eq!(d.n, 4);
        assert_relative_eq!(d.mean, 2.5);
        // sample variance of 1..4 is 5/3
        assert_relative_eq!(d.sd, (5.0f64 / 3.0).sqrt());
        assert_relative_eq!(d.standard_error(), (5.0f64 / 3.0).sqrt() / 2.0);
        // type 7: h = 3p; Q(0.05) = 1 + 0.15, Q(0.25) = 1.75, median 2.5
        assert_relative_eq!(d.quantiles[0], 1.15);
        assert_relative_eq!(d.quantiles[1], 1.75);
        assert_relative_eq!(d.median(), 2.5);
        assert_relative_eq!(d.quantiles[4], 3.85);
        assert_eq!((d.min, d.max), (1.0, 4.0));
        assert!(Distribution::of([]).mean.is_nan());
        let a = Distribution::of_angles_deg([359.0, 1.0, 3.0]);
        assert_relative_eq!(a.mean, 1.0, epsilon = 1e-9);
        assert_relative_eq!(a.sd, 2.0, epsilon = 1e-9);
        assert_relative_eq!(a.min, 359.0, epsilon = 1e-9);
        assert_eq!(Distribution::of([7.0]).sd, 0.0);
    }

    #[test]
    fn band_is_per_sector_and_fractions_count_labels() {
        let a = [0.0, 1.0, 2.0];
        let b = [2.0, 1.0, 0.0];
        let band = Band::of([&a[..], &b[..]]);
        assert_eq!(band.mean(), vec![1.0, 1.0, 1.0]);
        assert_eq!(band.sectors[0].max, 2.0);
        assert_eq!(fractions(["x", "y", "x"]), vec![("x", 2), ("y", 1)]);
    }
}
