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

/// Replaces the first `from` in the file `path` by `to`, checking that it is there: a test's
/// edit of a file the code under test reads back.
pub(crate) fn edit_file(path: &std::path::Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{} holds `{from}`", path.display());
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}
