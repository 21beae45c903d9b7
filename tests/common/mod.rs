//! Helpers of the end-to-end tests that run the built `jointwear` program.

#![allow(dead_code)] // each test file uses a different subset

use jointwear::scene::scene_path;
use jointwear::simulation::RunOutput;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `jointwear` with `args` to completion.
pub fn jointwear(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_jointwear"))
        .args(args)
        .output()
        .expect("jointwear runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh, empty directory per test (`prefix` keeps test files apart).
pub fn temp_dir(prefix: &str, name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("jointwear-{prefix}-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// The text of shipped scene `name` with each `(from, to)` replaced (each `from` must occur).
pub fn scene_with(name: &str, replacements: &[(&str, &str)]) -> String {
    let mut text = fs::read_to_string(scene_path(name)).unwrap();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name}.toml lacks `{from}`");
        text = text.replace(from, to);
    }
    text
}

/// The standard scene cut to `rotations` rotations (the last one recorded), plus
/// `replacements`, written to `dir/name`.
pub fn short_standard(
    dir: &Path,
    name: &str,
    rotations: u32,
    replacements: &[(&str, &str)],
) -> PathBuf {
    let rotations = format!("rotations = {rotations}");
    let mut all = vec![
        ("rotations = 40", rotations.as_str()),
        ("record_rotations = 2", "record_rotations = 1"),
        ("wear_snapshots = [10, 20, 30, 40]", "wear_snapshots = []"),
    ];
    all.extend_from_slice(replacements);
    let path = dir.join(name);
    fs::write(&path, scene_with("standard", &all)).unwrap();
    path
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Asserts exit code `code` and that stderr contains every one of `needles`.
#[track_caller]
pub fn assert_fails(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr lacks `{n}`: {err}");
    }
}

/// Bitwise equality of two runs' final wear, state, counters and snapshots (the first must
/// have impacted, or the comparison would test nothing chaotic).
pub fn assert_same_run(a: &RunOutput, b: &RunOutput) {
    assert!(a.impacts[0] > 0, "the scene must impact to test anything");
    assert_eq!(a.final_wear, b.final_wear);
    assert_eq!(a.final_state, b.final_state);
    assert_eq!(a.stats, b.stats);
    assert_eq!(a.impacts, b.impacts);
    assert_eq!(a.wear_snapshots, b.wear_snapshots);
}

/// The names in `dir`, sorted (no temporary file may stay behind).
pub fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Makes a FIFO at `fifo` (unless there is one) with a writer of 2 kB waiting to open it, runs
/// `check`, which must refuse it without reading, then releases the writer: on Linux a FIFO
/// opened for reading and writing does not wait, and held open it is the reader the writer
/// waits for; 2 kB fit in the pipe's buffer.
pub fn with_waiting_writer(fifo: &Path, check: impl FnOnce()) {
    if !fifo.exists() {
        let made = Command::new("mkfifo").arg(fifo).status().unwrap();
        assert!(made.success());
    }
    let writer_path = fifo.to_path_buf();
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        let mut w = fs::OpenOptions::new().write(true).open(writer_path)?;
        w.write_all(&b"#\n".repeat(1000))
    });
    check();
    let reader = fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(fifo)
        .unwrap();
    writer.join().unwrap().unwrap();
    drop(reader);
}
