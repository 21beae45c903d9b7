//! Failure modes of the `jointwear` program: each fails with its exit code (2 bad input, 1 a
//! failure while running) and a message naming its cause, before any simulation where the
//! cause is knowable up front.

mod common;

use common::*;
use jointwear::scene::scene_path;
use std::fs;

/// A run setting that fails any simulation at its first accepted step.
const ONE_STEP: (&str, &str) = (
    "record_interval_s = 1e-5",
    "record_interval_s = 1e-5\nmax_steps = 1",
);

#[test]
fn a_missing_scene_file_is_bad_input() {
    let dir = temp_dir("guards", "missing");
    let absent = dir.join("absent.toml");
    for command in ["check", "run", "sweep", "longlife"] {
        let o = jointwear(&[command, s(&absent)]);
        assert_fails(&o, 2, &["absent.toml", "No such file"]);
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_missing_extends_target_names_the_scene_that_refers_to_it() {
    let dir = temp_dir("guards", "extends");
    let child = dir.join("child.toml");
    fs::write(&child, "extends = \"nope.toml\"\ntitle = \"child\"\n").unwrap();
    let o = jointwear(&["check", s(&child)]);
    assert_fails(
        &o,
        2,
        &["child.toml", "extends = \"nope.toml\"", "nope.toml"],
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_command_line_values_are_bad_input() {
    let std = scene_path("standard");
    for args in [
        vec!["longlife", s(&std), "--rotations", "many"],
        vec!["longlife", s(&std), "--rotations", "nan"],
        vec!["longlife", s(&std), "--max-change", "0"],
        vec!["longlife", s(&std), "--k-over-h", "-1"],
        vec!["longlife", s(&std), "--settle", "-3"],
        vec!["sweep", s(&std), "--shard", "x"],
        vec!["run", s(&std), "--no-such-option"],
        vec!["no-such-command"],
    ] {
        let o = jointwear(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn an_unusable_output_location_fails_before_simulating() {
    let dir = temp_dir("guards", "out");
    // One accepted step would fail the run (exit 1): exit 2 shows nothing was simulated.
    let scene = short_standard(&dir, "one-step.toml", 2, &[ONE_STEP]);
    let file = dir.join("a-file");
    fs::write(&file, "keep me").unwrap();
    let below_file = file.join("sub");
    for out in [&file, &below_file] {
        for command in ["run", "longlife"] {
            let o = jointwear(&[command, s(&scene), "--out", s(out)]);
            assert_fails(&o, 2, &["`--out`", s(out), "is an existing file"]);
        }
        let o = jointwear(&["sweep", s(&scene), "--out", s(&out.join("sweep.csv"))]);
        assert_fails(&o, 2, &["`--out`", "is an existing file"]);
    }
    let o = jointwear(&["sweep", s(&scene), "--out", s(&dir)]);
    assert_fails(&o, 2, &["`--out`", "it is a directory"]);
    assert_eq!(fs::read_to_string(&file).unwrap(), "keep me");
    // The control: with a usable --out the same scene is simulated and stops at its step.
    let o = jointwear(&["run", s(&scene), "--out", s(&dir.join("ok"))]);
    assert_fails(&o, 1, &["step limit of 1 steps"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_recording_beyond_the_memory_budget_fails_at_validation() {
    let dir = temp_dir("guards", "budget");
    let tiny = (
        "record_interval_s = 1e-5",
        "record_interval_s = 1e-12\nmax_steps = 1",
    );
    let scene = short_standard(&dir, "tiny-interval.toml", 2, &[tiny]);
    let needles = [
        "`run.record_interval_s`: 1e-12 s",
        "record budget of 2 GiB",
        "rows x 29 columns",
        "wrong unit",
    ];
    let out = dir.join("out");
    for args in [
        vec!["check", s(&scene)],
        vec!["run", s(&scene), "--out", s(&out)],
    ] {
        assert_fails(&jointwear(&args), 2, &needles);
    }
    // A sweep records at least one rotation of every case, even of a scene that records none.
    let scene = short_standard(
        &dir,
        "no-record.toml",
        2,
        &[ONE_STEP, ("record_rotations = 1", "record_rotations = 0")],
    );
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "run.record_interval_s=1e-5,1e-12",
        "--out",
        s(&dir.join("sweep.csv")),
    ]);
    assert_fails(&o, 2, &needles);
    assert!(!dir.join("out").exists() && !dir.join("sweep.csv").exists());
    fs::remove_dir_all(&dir).unwrap();
}
