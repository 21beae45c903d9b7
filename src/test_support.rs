//! Helpers shared by the unit tests.

/// A reproducible uniform generator on [0, 1) (xorshift64 from `seed`, 53 bits): for tests
/// that sweep a function over many points without a random-number crate.
pub(crate) fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}
