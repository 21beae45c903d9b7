//! `x^(-1/q)` for the step-size controller without libm's `pow`: it is taken after every
//! attempted step, and `pow` cost 125 instructions a call (1.2 % of the standard run).

/// `x^(-1/q)` for an error norm `x` and the order `q` of the error estimate: Newton's method
/// for Dormand-Prince's `q = 5` and DOP853's `q = 8` on norms in `[1e-300, 1e300]`, within
/// 2 ulp of the exact root (the test below); libm's `powf` otherwise (0 gives +∞).
#[inline]
pub(super) fn inverse_root(x: f64, q: f64) -> f64 {
    // Wide enough for any norm that is not 0, narrow enough that x·y^q stays normal.
    if (1e-300..=1e300).contains(&x) {
        if q == 5.0 {
            return newton::<5>(x);
        }
        if q == 8.0 {
            return newton::<8>(x);
        }
    }
    x.powf(-1.0 / q)
}

/// Largest relative error of [`guess`] for `Q` ≤ 8 (measured over a period of its pattern in
/// the test below: 3.3e-2 at Q = 8, 3.2e-2 at Q = 5).
const GUESS_ERROR: f64 = 0.034;

/// Newton steps that take [`GUESS_ERROR`] below 2⁻⁵⁴ (half an ulp at worst): the relative
/// error ε of y ≈ x^(-1/Q) becomes −(Q + 1)/2·ε² to leading order. 4 for Q = 5, 5 for Q = 8.
const fn newton_steps(q: u64) -> u32 {
    let mut error = GUESS_ERROR;
    let mut steps = 0;
    while error > 1.0 / (1u64 << 54) as f64 {
        error = (q + 1) as f64 / 2.0 * error * error;
        steps += 1;
    }
    steps
}

/// x^(-1/Q) for a positive normal `x`, by Newton's method on y^-Q = x from [`guess`]:
/// y ← y + y (1 − x y^Q) / Q, which needs no division.
#[inline(always)]
fn newton<const Q: u64>(x: f64) -> f64 {
    let mut y = guess::<Q>(x);
    for _ in 0..const { newton_steps(Q) } {
        y += y * ((1.0 - x * y.powi(Q as i32)) * const { 1.0 / Q as f64 });
    }
    y
}

/// x^(-1/Q) within [`GUESS_ERROR`]: a double's bits, read as an integer, are about 2⁵² times
/// (its base-2 logarithm + 1023), so −log₂(x)/Q is a subtraction and a division of integers;
/// the shift (0.0586 in log₂ units) centres the error of that linear reading.
#[inline(always)]
fn guess<const Q: u64>(x: f64) -> f64 {
    const ONE: u64 = 1.0f64.to_bits();
    const SHIFT: u64 = 0xF000_0000_0000;
    f64::from_bits(ONE + ONE / Q - SHIFT - x.to_bits() / Q)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The relative difference of [`inverse_root`] from libm's `powf(x, -1/q)`, less what
    /// `powf` itself is off the exact root because its exponent is −1/q rounded (at 1e±12 and
    /// q = 5, 3.1e-16); the rest is our error against the exact root.
    fn error(x: f64, q: f64) -> f64 {
        let (ours, libm) = (inverse_root(x, q), x.powf(-1.0 / q));
        // q·fl(1/q) − 1, exact: the relative error of the rounded exponent.
        let exponent = (1.0 / q).mul_add(q, -1.0);
        let libm_off = x.ln().abs() * exponent.abs() / q;
        ((ours / libm - 1.0).abs() - libm_off).max(0.0)
    }

    // Fails with one Newton step fewer (2.5e-9 at q = 5), with SHIFT = 0 (the guess then errs
    // by 7.3 %; 2e-11) and with the step's 1/Q replaced by 1/(Q + 1) (4e-5): tried. The worst
    // error seen is 1.4 ε at q = 5 (2 ε from powf itself) and 1 ε at q = 8.
    #[test]
    fn inverse_root_is_the_exact_root_within_two_ulp() {
        let mut uniform = crate::test_support::uniform(0x2545_f491_4f6c_dd1d);
        for q in [5.0, 8.0] {
            let mut worst: f64 = 0.0;
            // Log-uniform over the error norms a run meets, [1e-12, 1e12].
            for _ in 0..500_000 {
                let x = 10f64.powf(24.0 * uniform() - 12.0);
                worst = worst.max(error(x, q));
            }
            // Two ulp: the last step's correction and its sum each round once.
            assert!(worst <= 2.0 * f64::EPSILON, "q = {q}: worst {worst:e}");
        }
        // Exact powers, the ends of Newton's range and powf's beyond them, 0 and +∞.
        assert_eq!(inverse_root(32.0, 5.0), 0.5);
        assert_eq!(inverse_root(1.0, 8.0), 1.0);
        for x in [1e-300, 1e300] {
            assert!(error(x, 5.0) <= 2.0 * f64::EPSILON, "{x:e}");
        }
        for x in [5e-324, 1e-310, 1e301, 0.0, f64::INFINITY] {
            assert_eq!(
                inverse_root(x, 5.0).to_bits(),
                x.powf(-0.2).to_bits(),
                "{x:e}"
            );
        }
        assert_eq!(inverse_root(3.0, 4.0), 3f64.powf(-0.25));
    }

    /// [`GUESS_ERROR`] bounds the guess: its relative error repeats with every Q-fold of x, so
    /// a fine grid of [1, 2^Q) covers every x.
    #[test]
    fn guess_error_is_bounded() {
        fn worst<const Q: u64>() -> f64 {
            let n = 200_000;
            (0..n)
                .map(|i| {
                    let x = 2f64.powf(Q as f64 * f64::from(i) / f64::from(n));
                    (guess::<Q>(x) / x.powf(-1.0 / Q as f64) - 1.0).abs()
                })
                .fold(0.0, f64::max)
        }
        assert!(worst::<5>() < GUESS_ERROR && worst::<8>() < GUESS_ERROR);
        assert_eq!((newton_steps(5), newton_steps(8)), (4, 5));
    }
}
