//! Tests of whether two ensembles differ: Welch's t test for means and Fisher's exact test for
//! shares (the differences the perturbation study reports, [`crate::paper::perturbation`]),
//! and the sign test's interval of a median (the default-tolerance rule's paired ratios,
//! [`crate::paper::studies::tolerance_rule`]).
//!
//! * **Welch** (unequal variances): `t = (m₁ − m₂) / √(s₁²/n₁ + s₂²/n₂)`, Welch–Satterthwaite
//!   degrees of freedom `ν = (s₁²/n₁ + s₂²/n₂)² / ((s₁²/n₁)²/(n₁−1) + (s₂²/n₂)²/(n₂−1))`, and the
//!   two-sided p value `I_{ν/(ν+t²)}(ν/2, 1/2)` of Student's t distribution (regularised
//!   incomplete beta function by Lentz's continued fraction, Numerical Recipes §6.4).
//! * **Fisher** (a 2×2 table of counts `k₁ of n₁` against `k₂ of n₂`): the hypergeometric
//!   probability of every table with the same margins, summed over those no more probable than
//!   the observed one (the two-sided rule of R's `fisher.test`).
//! * **Median interval** (the sign test's, distribution-free): of `n` sorted values, the order
//!   statistics `x₍ₖ₎` and `x₍ₙ₊₁₋ₖ₎` (1-based) hold any continuous distribution's median with
//!   probability exactly `1 − 2·P(B ≤ k − 1)`, `B ~ Binomial(n, ½)`; the largest `k` whose
//!   coverage reaches the asked confidence gives the narrowest such interval.
//! * **Holm's step-down adjustment** (Holm 1979, *Scand. J. Statist.* 6:65–70) of a family of
//!   `m` p values, for deciding many comparisons at once ([`holm`]): sorted ascending
//!   `p₍₁₎ ≤ … ≤ p₍ₘ₎`, the adjusted `p̃₍ᵢ₎ = min(1, maxⱼ≤ᵢ (m − j + 1)·p₍ⱼ₎)`. Rejecting where
//!   `p̃ < α` keeps the chance of any false rejection in the family at most `α` whatever the
//!   tests' dependence, and never rejects less than Bonferroni (`m·p < α`). The same values as
//!   R's `p.adjust(p, method = "holm")`.

use super::statistics::Distribution;

/// Welch's t test of two means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Welch {
    /// `t = (m₁ − m₂) / √(s₁²/n₁ + s₂²/n₂)`.
    pub t: f64,
    /// Welch–Satterthwaite degrees of freedom.
    pub dof: f64,
    /// Two-sided p value.
    pub p: f64,
}

impl Welch {
    /// The test of `a`'s mean against `b`'s; `None` when either has fewer than two values or
    /// both have no spread (the statistic is undefined, not infinite).
    pub fn of(a: &Distribution, b: &Distribution) -> Option<Welch> {
        if a.n < 2 || b.n < 2 {
            return None;
        }
        let (va, vb) = (a.sd * a.sd / a.n as f64, b.sd * b.sd / b.n as f64);
        if va + vb <= 0.0 {
            return None;
        }
        let t = (a.mean - b.mean) / (va + vb).sqrt();
        let dof = (va + vb).powi(2) / (va * va / (a.n - 1) as f64 + vb * vb / (b.n - 1) as f64);
        Some(Welch {
            t,
            dof,
            p: student_two_sided(t, dof),
        })
    }
}

/// Two-sided p value of Student's t distribution with `dof` degrees of freedom at `t`.
pub fn student_two_sided(t: f64, dof: f64) -> f64 {
    incomplete_beta(dof / (dof + t * t), 0.5 * dof, 0.5)
}

/// The `t` at which Student's two-sided p value with `dof` degrees of freedom is `p`
/// ([`student_two_sided`] inverted by bisection).
pub fn student_two_sided_quantile(p: f64, dof: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1e3);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if student_two_sided(mid, dof) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Fisher's exact two-sided p value of `k1` of `n1` against `k2` of `n2`.
pub fn fisher_two_sided(k1: usize, n1: usize, k2: usize, n2: usize) -> f64 {
    assert!(k1 <= n1 && k2 <= n2, "counts {k1} of {n1}, {k2} of {n2}");
    let (n, k) = (n1 + n2, k1 + k2);
    let ln_choose = |n: usize, k: usize| ln_factorial(n) - ln_factorial(k) - ln_factorial(n - k);
    // probability that the first group holds x of the k
    let ln_p = |x: usize| ln_choose(n1, x) + ln_choose(n2, k - x) - ln_choose(n, k);
    let observed = ln_p(k1);
    // tables as probable as the observed one up to rounding count as "no more probable"
    let tie = 1e-7;
    let p: f64 = (k.saturating_sub(n2)..=k.min(n1))
        .map(ln_p)
        .filter(|&l| l <= observed + tie)
        .map(f64::exp)
        .sum();
    p.min(1.0)
}

/// A distribution-free confidence interval of a median ([`median_interval`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MedianInterval {
    /// Lower end: the `k`-th smallest value.
    pub lower: f64,
    /// Upper end: the `k`-th largest value.
    pub upper: f64,
    /// Its exact coverage, `1 − 2·P(B ≤ k − 1)`: at least the confidence asked, usually more
    /// (order statistics come in steps).
    pub coverage: f64,
}

/// The narrowest order-statistic interval of the median of `values` whose exact coverage is at
/// least `confidence` (module documentation); `None` when even the smallest and largest value
/// do not reach it (fewer than 6 values for 0.95) or a value is not finite.
pub fn median_interval(values: &[f64], confidence: f64) -> Option<MedianInterval> {
    if values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let n = values.len();
    let ln_half_n = n as f64 * 0.5f64.ln();
    let ln_choose = |i: usize| ln_factorial(n) - ln_factorial(i) - ln_factorial(n - i);
    // coverage of the k-th order statistics: 1 − 2·P(B ≤ k − 1), shrinking as k grows
    let coverage = |k: usize| {
        1.0 - 2.0
            * (0..k)
                .map(|i| (ln_choose(i) + ln_half_n).exp())
                .sum::<f64>()
    };
    let k = (1..=n / 2)
        .take_while(|&k| coverage(k) >= confidence)
        .last()?;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    Some(MedianInterval {
        lower: sorted[k - 1],
        upper: sorted[n - k],
        coverage: coverage(k),
    })
}

/// Holm's step-down adjusted p values of one family of tests (module documentation), in the
/// order of `p`. A NaN is no test: it stays NaN and does not count in the family's size `m`
/// (as R's `p.adjust` drops `NA`), so a law that could not run or a statistic without spread
/// neither adds a comparison nor makes the others harder to reject. Empty in, empty out.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..p.len()).filter(|&i| !p[i].is_nan()).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let m = order.len();
    let mut adjusted = vec![f64::NAN; p.len()];
    // the running maximum makes the adjusted values monotone in the raw ones: a smaller p
    // is never harder to reject than a larger one
    let mut running = 0.0_f64;
    for (rank, &i) in order.iter().enumerate() {
        running = running.max((m - rank) as f64 * p[i]).min(1.0);
        adjusted[i] = running;
    }
    adjusted
}

/// A row that may carry one test of a family of comparisons decided together by [`holm`]
/// (the studies' CSV rows), so that every study adjusts and rechecks its rows the same way.
pub trait FamilyTest {
    /// What identifies the row's family (equal for the rows adjusted together).
    type Family: PartialEq;
    /// The row's family and raw p; `None` when it carries no test.
    fn family_test(&self) -> Option<(Self::Family, f64)>;
    /// The Holm-adjusted p the row holds (NaN without a test).
    fn adjusted_p(&self) -> f64;
    /// Sets the Holm-adjusted p.
    fn set_adjusted_p(&mut self, p: f64);
}

/// The Holm-adjusted p of every row within its family (NaN where the row carries no test), in
/// the rows' order.
fn holm_of_families<T: FamilyTest>(rows: &[T]) -> Vec<f64> {
    let tests: Vec<_> = rows.iter().map(FamilyTest::family_test).collect();
    let mut adjusted = vec![f64::NAN; rows.len()];
    let mut done = vec![false; rows.len()];
    for first in 0..tests.len() {
        let Some((family, _)) = &tests[first] else {
            continue;
        };
        if done[first] {
            continue;
        }
        let members: Vec<usize> = (first..tests.len())
            .filter(|&i| tests[i].as_ref().is_some_and(|(f, _)| f == family))
            .collect();
        let p: Vec<f64> = members
            .iter()
            .map(|&i| tests[i].as_ref().unwrap().1)
            .collect();
        for (&i, a) in members.iter().zip(holm(&p)) {
            (adjusted[i], done[i]) = (a, true);
        }
    }
    adjusted
}

/// Sets every row's adjusted p to its raw p Holm-adjusted within its family ([`FamilyTest`]):
/// a row without a test (a failed run, an undefined test, the reference itself) adds no
/// comparison and gets NaN.
pub fn adjust_within_families<T: FamilyTest>(rows: &mut [T]) {
    let adjusted = holm_of_families(rows);
    for (r, a) in rows.iter_mut().zip(adjusted) {
        r.set_adjusted_p(a);
    }
}

/// Whether every row's adjusted p is what [`adjust_within_families`] makes of the rows' raw
/// p, to the CSVs' seven significant digits: a file edited by hand, or whose adjusted column
/// is not its raw one's, would print calls its p values do not support.
pub fn holm_consistent<T: FamilyTest>(rows: &[T]) -> bool {
    rows.iter().zip(holm_of_families(rows)).all(|(r, a)| {
        let recorded = r.adjusted_p();
        (recorded.is_nan() && a.is_nan()) || (recorded - a).abs() <= 1e-5 * a.abs()
    })
}

/// ln n! (exact summation: the tables here have at most a few thousand members).
fn ln_factorial(n: usize) -> f64 {
    (2..=n).map(|i| (i as f64).ln()).sum()
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, nine coefficients: relative error below 1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // reflection: Γ(x) Γ(1 − x) = π / sin πx
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = G[1..]
        .iter()
        .enumerate()
        .fold(G[0], |s, (i, g)| s + g / (x + i as f64 + 1.0));
    0.5 * (std::f64::consts::TAU).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// Regularised incomplete beta function `I_x(a, b)`.
fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    // the continued fraction converges fast for x < (a + 1)/(a + b + 2); else use symmetry
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

/// The continued fraction of `I_x(a, b)` by the modified Lentz method.
fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let clamp = |v: f64| if v.abs() < TINY { TINY } else { v };
    let mut c = 1.0;
    let mut d = 1.0 / clamp(1.0 - (a + b) * x / (a + 1.0));
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let even = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
        d = 1.0 / clamp(1.0 + even * d);
        c = clamp(1.0 + even / c);
        h *= d * c;
        let odd = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
        d = 1.0 / clamp(1.0 + odd * d);
        c = clamp(1.0 + odd / c);
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // References computed independently: Fisher's by exact rational sums of hypergeometric
    // probabilities, Student's by Simpson integration of the t density (2·10⁵ intervals).
    // Tolerances: 1e-9 relative is far below any plausible slip (a one-sided p, a wrong
    // degrees-of-freedom formula or a pooled variance move these by percents) and above the
    // references' own error.

    // Hand-computed: of 16 values, P(B ≤ 3) = (1 + 16 + 120 + 560)/2¹⁶ = 697/65 536, so the
    // 4th smallest and largest cover 1 − 1 394/65 536 = 0.978 729 248 046 875; the 5th would
    // cover 1 − 2·2 517/65 536 = 0.923 < 0.95. Of 6 values only the extremes, 1 − 2/64; of 5,
    // 1 − 2/32 = 0.9375 < 0.95. Checked to fail with a one-sided coverage (1 − P(B ≤ k − 1)
    // takes the 5th values of 16: (5, 12)). Tolerance: 1e-14 relative, a few roundings of the
    // sum of exponentials.
    #[test]
    fn the_median_interval_takes_the_order_statistics_of_the_binomial() {
        let values: Vec<f64> = (1..=16).rev().map(f64::from).collect();
        let i = median_interval(&values, 0.95).unwrap();
        assert_eq!((i.lower, i.upper), (4.0, 13.0));
        assert_relative_eq!(i.coverage, 64_142.0 / 65_536.0, max_relative = 1e-14);
        let six = median_interval(&[6.0, 1.0, 5.0, 2.0, 4.0, 3.0], 0.95).unwrap();
        assert_eq!((six.lower, six.upper), (1.0, 6.0));
        assert_relative_eq!(six.coverage, 62.0 / 64.0, max_relative = 1e-14);
        assert_eq!(median_interval(&[1.0, 2.0, 3.0, 4.0, 5.0], 0.95), None);
        assert_eq!(
            median_interval(&[1.0, f64::NAN, 3.0, 4.0, 5.0, 6.0], 0.95),
            None
        );
    }

    // Holm by hand: sorted 0.01, 0.02, 0.03, 0.04, 0.05 times 5, 4, 3, 2, 1 give 0.05, 0.08,
    // 0.09, 0.08, 0.05; the running maximum makes them 0.05, 0.08, 0.09, 0.09, 0.09. R:
    // p.adjust(c(0.04, 0.01, 0.05, 0.03, 0.02), "holm") = 0.09 0.05 0.09 0.09 0.08.
    // Tolerance 1e-15 relative: one product and one comparison per value.
    #[test]
    fn holm_matches_the_hand_computed_step_down() {
        let adjusted = holm(&[0.04, 0.01, 0.05, 0.03, 0.02]);
        for (a, e) in adjusted.iter().zip([0.09, 0.05, 0.09, 0.09, 0.08]) {
            assert_relative_eq!(*a, e, max_relative = 1e-15);
        }
        // R: p.adjust(c(0.002, 0.2, 0.001, 0.5), "holm") = 0.006 0.4 0.004 0.5; capped at 1:
        // p.adjust(c(0.6, 0.3), "holm") = 0.6 0.6
        for (a, e) in holm(&[0.002, 0.2, 0.001, 0.5])
            .iter()
            .zip([0.006, 0.4, 0.004, 0.5])
        {
            assert_relative_eq!(*a, e, max_relative = 1e-15);
        }
        assert_eq!(holm(&[0.6, 0.3]), [0.6, 0.6]);
        assert_eq!(holm(&[0.9, 0.8]), [1.0, 1.0]);
    }

    // Eleven laws against one, as section 8's families: raw 0.0008 and 0.00095 with nine of
    // 0.5. Bonferroni multiplies all by 11: 0.0088 and 0.01045, one rejection at 0.01; Holm
    // multiplies the second smallest by 10 only: 0.0095, two. Checked to fail with m instead
    // of m − i + 1 (0.01045, one rejection).
    #[test]
    fn holm_rejects_where_bonferroni_does_not() {
        let mut p = vec![0.0008, 0.00095];
        p.extend([0.5; 9]);
        let adjusted = holm(&p);
        assert_relative_eq!(adjusted[0], 0.0088, max_relative = 1e-14);
        assert_relative_eq!(adjusted[1], 0.0095, max_relative = 1e-14);
        let bonferroni: Vec<f64> = p.iter().map(|p| (p * 11.0).min(1.0)).collect();
        let rejected = |v: &[f64]| v.iter().filter(|&&p| p < 0.01).count();
        assert_eq!((rejected(&adjusted), rejected(&bonferroni)), (2, 1));
        // the nine 0.5 are tied: each one's 0.5 × (number left) is below the running maximum
        // of the first of them, 9 × 0.5 capped at 1
        assert!(adjusted[2..].iter().all(|&a| a == 1.0));
    }

    // Ties take one adjusted value whatever their order. R: p.adjust(c(0.01, 0.03, 0.01, 0.03),
    // "holm") = 0.04 0.06 0.04 0.06 (4 × 0.01, then max(0.04, 3 × 0.01), then 2 × 0.03, then
    // max(0.06, 0.03)). Checked to fail without the running maximum (the second 0.01 gets
    // 0.03 and the second 0.03 gets 0.03).
    #[test]
    fn holm_gives_ties_one_value() {
        let adjusted = holm(&[0.01, 0.03, 0.01, 0.03]);
        for (a, e) in adjusted.iter().zip([0.04, 0.06, 0.04, 0.06]) {
            assert_relative_eq!(*a, e, max_relative = 1e-15);
        }
    }

    // A NaN is no test: R's p.adjust(c(NA, 0.01, NA, 0.02), "holm") = NA 0.02 NA 0.02 (m = 2,
    // not 4). An empty or all-NaN family adjusts nothing.
    #[test]
    fn holm_leaves_out_what_was_not_tested() {
        let adjusted = holm(&[f64::NAN, 0.01, f64::NAN, 0.02]);
        assert!(adjusted[0].is_nan() && adjusted[2].is_nan());
        assert_relative_eq!(adjusted[1], 0.02, max_relative = 1e-15);
        assert_relative_eq!(adjusted[3], 0.02, max_relative = 1e-15);
        assert!(holm(&[]).is_empty());
        assert!(holm(&[f64::NAN; 3]).iter().all(|p| p.is_nan()));
        assert_eq!(holm(&[0.003]), [0.003]);
    }

    // Identities over many pseudo-random families (a fixed uniform sequence, with ties and
    // NaNs mixed in): Holm is never below the raw p nor above Bonferroni's m·p (so it rejects
    // at most what the raw p does and at least what Bonferroni does), is at most 1, and keeps
    // the raw order (a smaller raw p never gets a larger adjusted one).
    #[test]
    fn holm_lies_between_the_raw_p_and_bonferroni_and_keeps_their_order() {
        let mut draw = crate::test_support::uniform(0x2545_f491_4f6c_dd1d);
        for family in 0..500 {
            let n = 1 + family % 13;
            let p: Vec<f64> = (0..n)
                .map(|_| match draw() {
                    u if u < 0.1 => f64::NAN,
                    // coarse values tie often
                    u if u < 0.3 => (draw() * 20.0).floor() / 1000.0,
                    _ => draw().powi(3),
                })
                .collect();
            let adjusted = holm(&p);
            let m = p.iter().filter(|p| !p.is_nan()).count() as f64;
            for (i, (&raw, &a)) in p.iter().zip(&adjusted).enumerate() {
                if raw.is_nan() {
                    assert!(a.is_nan());
                    continue;
                }
                assert!(a >= raw && a <= (m * raw).min(1.0), "{p:?} {adjusted:?}");
                for (&other, &b) in p.iter().zip(&adjusted).skip(i + 1) {
                    if raw < other {
                        assert!(a <= b, "{p:?} {adjusted:?}");
                    } else if raw == other {
                        assert_eq!(a, b, "{p:?} {adjusted:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn fisher_matches_exact_rational_sums() {
        // Fisher's lady tasting tea, 3 of 4 against 1 of 4: 34/70
        assert_relative_eq!(
            fisher_two_sided(3, 4, 1, 4),
            34.0 / 70.0,
            max_relative = 1e-9
        );
        // 1 of 10 against 11 of 14 (one-sided p would be 0.001346)
        assert_relative_eq!(
            fisher_two_sided(1, 10, 11, 14),
            0.002_759_456_185_220_083_6,
            max_relative = 1e-9
        );
        // issue 20's count: 10 of 64 members in the low state against 13 of 24
        assert_relative_eq!(
            fisher_two_sided(10, 64, 13, 24),
            0.000_672_598_186_262_007_9,
            max_relative = 1e-9
        );
        assert_relative_eq!(fisher_two_sided(5, 10, 5, 10), 1.0, max_relative = 1e-12);
        // symmetric in the groups
        assert_relative_eq!(
            fisher_two_sided(13, 24, 10, 64),
            fisher_two_sided(10, 64, 13, 24),
            max_relative = 1e-12
        );
    }

    #[test]
    fn student_matches_integrated_density() {
        assert_relative_eq!(
            student_two_sided(2.0, 10.0),
            0.073_388_034_770_741_3,
            max_relative = 1e-9
        );
        assert_relative_eq!(
            student_two_sided(-1.5, 3.3),
            0.222_503_196_719_291_28,
            max_relative = 1e-9
        );
        assert_relative_eq!(student_two_sided(0.0, 5.0), 1.0, max_relative = 1e-12);
    }

    #[test]
    fn welch_matches_the_worked_example() {
        // Welch's test's textbook example (two samples of 15 with unequal variances)
        let a = Distribution::of([
            27.5, 21.0, 19.0, 23.6, 17.0, 17.9, 16.9, 20.1, 21.9, 22.6, 23.1, 19.6, 19.0, 21.7,
            21.4,
        ]);
        let b = Distribution::of([
            27.1, 22.0, 20.8, 23.4, 23.4, 23.5, 25.8, 22.0, 24.8, 20.2, 21.9, 22.1, 22.9, 20.5,
            24.4,
        ]);
        let w = Welch::of(&a, &b).unwrap();
        assert_relative_eq!(w.t, -2.455_356_398_286_006, max_relative = 1e-9);
        assert_relative_eq!(w.dof, 24.988_529_290_231_42, max_relative = 1e-9);
        assert_relative_eq!(w.p, 0.021_378_001_462_866_04, max_relative = 1e-8);
        let one = Distribution::of([1.0]);
        assert_eq!(Welch::of(&a, &one), None);
        let flat = Distribution::of([2.0, 2.0]);
        assert_eq!(Welch::of(&flat, &flat), None);
    }
}
