//! Failure modes of the `jointwear` program: each fails with its exit code (2 bad input, 1 a
//! failure while running) and a message naming its cause, before any simulation where the
//! cause is knowable up front.

mod common;

use common::*;
use jointwear::scene::scene_path;
use std::fs;

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
