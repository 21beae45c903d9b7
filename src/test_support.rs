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

/// Checks a study's reader against its committed CSV `text` (a `#` line first or not, then
/// `header`, whose `p_holm` column follows the raw p): `read` accepts the file as committed,
/// and refuses the layout before `p_holm` (the column dropped from the header and every row),
/// those rows under the new header (a header mended by hand), and one row's adjusted p replaced
/// by its raw p: a stale or edited file is never read with shifted or unsupported calls.
pub(crate) fn assert_refuses_stale_adjusted<T>(
    study: &str,
    text: &str,
    header: &[&str],
    read: impl Fn(&std::path::Path) -> Option<T>,
) {
    let holm = header.iter().position(|&c| c == "p_holm").unwrap();
    let dir = std::env::temp_dir().join(format!("jointwear-{study}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (comment, body) = match text.strip_prefix('#') {
        Some(_) => text
            .split_once('\n')
            .map(|(c, b)| (format!("{c}\n"), b))
            .unwrap(),
        None => (String::new(), text),
    };
    let lines: Vec<Vec<&str>> = body.lines().map(|l| l.split(',').collect()).collect();
    let readable = |name: &str, lines: &[Vec<&str>]| {
        let path = dir.join(name);
        let rows: Vec<String> = lines.iter().map(|cells| cells.join(",")).collect();
        std::fs::write(&path, format!("{comment}{}\n", rows.join("\n"))).unwrap();
        read(&path).is_some()
    };
    assert!(readable("kept.csv", &lines));
    let mut old = lines.clone();
    for cells in &mut old {
        cells.remove(holm);
    }
    assert!(!readable("stale.csv", &old));
    old[0] = header.to_vec();
    assert!(!readable("mended.csv", &old));
    // a tested row whose adjustment moved its p (a family of one keeps it)
    let edited = (1..lines.len())
        .find(|&i| !lines[i][holm].is_empty() && lines[i][holm] != lines[i][holm - 1])
        .unwrap();
    let mut copied = lines.clone();
    copied[edited][holm] = lines[edited][holm - 1];
    assert!(!readable("edited.csv", &copied));
    std::fs::remove_dir_all(&dir).unwrap();
}
