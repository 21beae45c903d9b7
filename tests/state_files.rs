//! State files read back are checked, field by field: an edited or damaged checkpoint or sweep
//! file gives a bad-input error naming the file and the field, never a panic, a wrong result
//! or a run without end. Each case below failed on the code before these checks (exit 101,
//! a wrong exit 0 or no end), as listed in issue 21.

mod common;

use common::*;
use jointwear::io::output::fnv1a;
use jointwear::io::progress::Silent;
use jointwear::simulation::checkpoint::{read_checkpoint, write_checkpoint};
use jointwear::simulation::{Scene, Simulation};
use jointwear::sweep::file::{label_check, SweepFile, SweepId};
use jointwear::Error;
use serde_json::Value;
use std::fs;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// A checkpoint after rotation 1 of a 2-rotation run of the standard scene (energy accounted,
/// wear history on), as JSON, and the scene.
fn real_checkpoint(dir: &Path) -> (Scene, Value) {
    let extra = [
        (
            "baumgarte_per_s = 100.0",
            "baumgarte_per_s = 100.0\nenergy_accounting = true\nprofile_history_per_rotation = 4",
        ),
        ("record_interval_s = 1e-5", "record_interval_s = 1e-4"),
    ];
    let scene = Scene::load(short_standard(dir, "scene.toml", 2, &extra)).unwrap();
    let mut sim = Simulation::start(&scene).unwrap();
    sim.advance_rotation().unwrap();
    let path = dir.join("real.json");
    write_checkpoint(&path, "fp", sim.checkpoint()).unwrap();
    let json = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    (scene, json)
}

/// Writes `file` with its checksum recomputed (the documented FNV-1a 64 of the scene's
/// fingerprint, U+001F and the compact, key-sorted JSON of `checkpoint`), as an edit that
/// knows the format would.
fn reseal(path: &Path, mut file: Value) {
    let scene = file["scene_fingerprint"].as_str().unwrap();
    let sum = fnv1a(format!("{scene}\u{1f}{}", file["checkpoint"]).as_bytes());
    file["checksum"] = Value::String(format!("{sum:016x}"));
    fs::write(path, file.to_string()).unwrap();
}

/// Reads and resumes the checkpoint at `path`; an accepted one is run to its end.
fn resume(scene: &Scene, path: &Path) -> jointwear::Result<u32> {
    let mut sim = Simulation::resume(scene, read_checkpoint(path, "fp")?)?;
    sim.run_to_end(&Silent)?;
    let done = sim.rotations_done();
    let out = sim.finish();
    assert_eq!(out.impacts.len(), out.final_wear.len());
    Ok(done)
}

/// An edit of a checkpoint's fields.
type Edit = fn(&mut Value);

/// Resumes `real` (a checkpoint file of `scene`) after each of `edits`, resealed at `path`:
/// each must be refused naming `checkpoint.<field>`.
fn refused_after_each(scene: &Scene, real: &Value, edits: &[(&str, Edit)], path: &Path) {
    for (field, edit) in edits {
        let mut file = real.clone();
        edit(file.pointer_mut("/checkpoint").unwrap());
        reseal(path, file);
        match resume(scene, path) {
            Err(Error::Invalid { field: f, .. }) => {
                assert_eq!(f, format!("checkpoint.{field}"), "edit of {field}")
            }
            other => panic!("edit of {field}: {:?}", other.map_err(|e| e.to_string())),
        }
    }
}

#[test]
fn edited_checkpoints_are_refused_naming_the_field() {
    let dir = temp_dir("state", "edits");
    let (scene, real) = real_checkpoint(&dir);
    let path = dir.join("edited.json");
    let ptr = |v: &mut Value, p: &str| v.pointer_mut(&format!("/checkpoint{p}")).unwrap().take();
    let edits: [(&str, Edit); 15] = [
        ("sampler.dy", |v| {
            v["sampler"]["dy"].as_array_mut().unwrap().pop();
        }),
        ("out.impacts", |v| {
            v["out"]["impacts"] = Value::Array(vec![])
        }),
        ("out.max_penetration_whole_run", |v| {
            v["out"]["max_penetration_whole_run"] = Value::Array(vec![])
        }),
        ("rotation", |v| v["rotation"] = 999.into()),
        ("sampler.interval", |v| {
            v["sampler"]["interval"] = 0.0.into()
        }),
        ("sampler", |v| v["sampler"] = Value::Null),
        ("sampler.start", |v| v["sampler"]["start"] = 0.0.into()),
        ("end_rotation", |v| v["end_rotation"] = 4294967295u32.into()),
        ("end_rotation", |v| v["end_rotation"] = Value::Null),
        ("energy_start", |v| v["energy_start"] = Value::Null),
        ("next_history", |v| v["next_history"] = 1e300.into()),
        ("gap_rates", |v| v["gap_rates"] = Value::Array(vec![])),
        // as an earlier version wrote it
        ("gap_rates", |v| {
            v.as_object_mut().unwrap().remove("gap_rates");
        }),
        // written under other arithmetic, or before the version was written
        ("arithmetic", |v| v["arithmetic"] = 1.into()),
        ("arithmetic", |v| {
            v.as_object_mut().unwrap().remove("arithmetic");
        }),
    ];
    refused_after_each(&scene, &real, &edits, &path);
    // Unsealed, any edit is caught by the checksum.
    let refused_as_edited = |file: Value| {
        fs::write(&path, file.to_string()).unwrap();
        let e = resume(&scene, &path).unwrap_err().to_string();
        assert!(
            e.contains("checksum") && e.contains("edited or damaged"),
            "{e}"
        );
    };
    let mut file = real.clone();
    let _ = ptr(&mut file, "/rotation");
    file["checkpoint"]["rotation"] = 2.into();
    refused_as_edited(file);
    // So is the scene's fingerprint: one of another scene's checkpoint edited to this scene's
    // (which the refusal of the other's names) was resumed as this scene's run, exit 0.
    let mut file = real.clone();
    file["scene_fingerprint"] = "another scene".into();
    reseal(&path, file);
    let mut file: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    file["scene_fingerprint"] = "fp".into();
    refused_as_edited(file);
    // A checkpoint of an earlier version, whose checksum covered the checkpoint alone, is
    // refused saying so and what to do (it was refused as edited or damaged).
    let mut file = real.clone();
    let sum = fnv1a(file["checkpoint"].to_string().as_bytes());
    file["checksum"] = Value::String(format!("{sum:016x}"));
    fs::write(&path, file.to_string()).unwrap();
    let e = resume(&scene, &path).unwrap_err().to_string();
    assert!(
        e.contains("written by an earlier version (before 2026-11-28)")
            && e.contains("--discard-checkpoint")
            && !e.contains("edited or damaged"),
        "{e}"
    );
    // The real one resumes to the end.
    reseal(&path, real);
    assert_eq!(resume(&scene, &path).unwrap(), 2);
    fs::remove_dir_all(&dir).unwrap();
}

/// Drops the first `k` numbers of every series of a checkpoint's recording (`time`, the driver
/// angle, every body's and joint's).
fn drop_samples(v: &mut Value, k: usize) {
    match v {
        Value::Array(items) if items.iter().all(Value::is_number) => {
            items.drain(..k.min(items.len()));
        }
        Value::Array(items) => items.iter_mut().for_each(|x| drop_samples(x, k)),
        Value::Object(map) => map.values_mut().for_each(|x| drop_samples(x, k)),
        _ => {}
    }
}

/// A checkpoint that lacks an output its run had made by then, or holds one it cannot have
/// made, is refused naming the field, not resumed to a result without it: before, (a) a
/// missing first snapshot gave a profile file without its column, (b) 1000 dropped samples a
/// time series 1000 rows short, and the other edits below resumed too (all exit 0).
#[test]
fn checkpoints_short_of_an_output_of_their_run_are_refused() {
    let dir = temp_dir("state", "outputs");
    // Rotation 2 of 3 with the last 2 recorded: samples, snapshots and history points made.
    let extra = [
        (
            "baumgarte_per_s = 100.0",
            "baumgarte_per_s = 100.0\nprofile_history_per_rotation = 4",
        ),
        ("record_interval_s = 1e-5", "record_interval_s = 1e-4"),
        ("record_rotations = 1", "record_rotations = 2"),
        ("wear_snapshots = []", "wear_snapshots = [1, 2, 3]"),
    ];
    let scene = Scene::load(short_standard(&dir, "scene.toml", 3, &extra)).unwrap();
    let mut sim = Simulation::start(&scene).unwrap();
    sim.advance_rotation().unwrap();
    sim.advance_rotation().unwrap();
    let path = dir.join("real.json");
    write_checkpoint(&path, "fp", sim.checkpoint()).unwrap();
    let real: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    let times = real["checkpoint"]["out"]["recording"]["time"]
        .as_array()
        .unwrap();
    assert!(times.len() > 10, "{} samples", times.len());
    let edits: [(&str, Edit); 10] = [
        ("out.wear_snapshots", |v| {
            v["out"]["wear_snapshots"].as_array_mut().unwrap().remove(0);
        }),
        // the snapshot of the rotation just completed is not the profile held
        ("out.wear_snapshots", |v| {
            v["out"]["wear_snapshots"][1]["depths"][0][0] = 1e-9.into()
        }),
        ("out.recording", |v| {
            drop_samples(&mut v["out"]["recording"], 10)
        }),
        ("out.recording", |v| {
            let t = v["out"]["recording"]["time"][3].as_f64().unwrap();
            v["out"]["recording"]["time"][3] = (t * (1.0 + 1e-15)).into();
        }),
        ("sampler.next", |v| {
            let next = v["sampler"]["next"].as_u64().unwrap();
            v["sampler"]["next"] = (next - 1).into();
        }),
        ("out.profile_history", |v| {
            v["out"]["profile_history"]
                .as_array_mut()
                .unwrap()
                .remove(0);
        }),
        ("next_history", |v| {
            let h = v["next_history"].as_f64().unwrap();
            v["next_history"] = (h * (1.0 - 1e-9)).into();
        }),
        ("out", |v| {
            v["out"]["final_wear"] = serde_json::json!([[0.0]])
        }),
        ("out", |v| v["out"]["stats"]["steps"] = 1.into()),
        ("out.max_penetration_whole_run[0]", |v| {
            v["out"]["max_penetration_whole_run"][0] = (-1.0).into()
        }),
    ];
    let edited = dir.join("edited.json");
    refused_after_each(&scene, &real, &edits, &edited);
    reseal(&edited, real);
    assert_eq!(resume(&scene, &edited).unwrap(), 3);
    fs::remove_dir_all(&dir).unwrap();
}

/// Every number, array and option of a real checkpoint replaced in turn (at most `MUTANTS`
/// mutations, taken evenly over its leaves) and resealed: each is refused or resumes to the
/// run's end, never a panic.
#[test]
fn mutated_checkpoints_never_panic_nor_run_without_end() {
    const MUTANTS: usize = 400;
    let dir = temp_dir("state", "fuzz");
    let (scene, real) = real_checkpoint(&dir);
    let path = dir.join("mutant.json");
    let mut pointers = Vec::new();
    collect(&real["checkpoint"], String::new(), &mut pointers);
    let replacements = [
        Value::Null,
        0.into(),
        (-1).into(),
        1e300.into(),
        4294967295u32.into(),
        Value::Array(vec![]),
    ];
    let stride = (pointers.len() * replacements.len())
        .div_ceil(MUTANTS)
        .max(1);
    let (mut refused, mut resumed) = (0, 0);
    for (i, (pointer, replacement)) in (pointers.iter())
        .flat_map(|p| replacements.iter().map(move |r| (p, r)))
        .enumerate()
        .filter(|(i, _)| i % stride == 0)
    {
        let mut file = real.clone();
        *file.pointer_mut(&format!("/checkpoint{pointer}")).unwrap() = replacement.clone();
        reseal(&path, file);
        let result = catch_unwind(AssertUnwindSafe(|| resume(&scene, &path)));
        match result {
            Err(_) => panic!("mutant {i}: {pointer} = {replacement} panicked"),
            Ok(Ok(done)) => {
                assert_eq!(done, 2, "mutant {i}: {pointer} = {replacement}");
                resumed += 1;
            }
            Ok(Err(_)) => refused += 1,
        }
    }
    // Most fields are checked; the state vector and counters can take many values.
    assert!(refused > resumed, "{refused} refused, {resumed} resumed");
    fs::remove_dir_all(&dir).unwrap();
}

/// JSON pointers of every leaf and array of `v` (array elements beyond the second skipped:
/// their siblings are alike).
fn collect(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(map) => {
            for (k, x) in map {
                collect(x, format!("{at}/{k}"), out);
            }
        }
        Value::Array(items) => {
            out.push(at.clone());
            for (k, x) in items.iter().enumerate().take(2) {
                collect(x, format!("{at}/{k}"), out);
            }
        }
        _ => out.push(at),
    }
}

/// The lines of a 2-case sweep's file: its header (the sweep named by the last column's
/// name), then a row per case.
fn shard_file(dir: &Path) -> (String, Vec<String>) {
    let scene = short_standard(dir, "scene.toml", 1, &[]);
    let out = dir.join("whole.csv");
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "driver.speed_rpm=-2000,-1000",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = fs::read_to_string(&out).unwrap();
    let lines: Vec<String> = text.lines().map(str::to_owned).collect();
    (s(&scene).to_string(), lines)
}

#[test]
fn edited_sweep_files_are_refused_before_any_number_read_is_used() {
    let dir = temp_dir("state", "sweep");
    let (scene, lines) = shard_file(&dir);
    // The header's last column names the sweep: `jointwear sweep fingerprint=… shard=…`.
    let (columns, genuine) = lines[0].rsplit_once(',').unwrap();
    let fingerprint = genuine.split_whitespace().nth(2).unwrap().to_string();
    let id = |rest: &str| format!("jointwear sweep {fingerprint} {rest}");
    let edited = dir.join("edited.csv");
    let merged = dir.join("merged.csv");
    let write = |first: &str, rows: &[&String]| {
        let mut text = format!("{columns},{first}\n");
        for r in rows {
            text.push_str(r);
            text.push('\n');
        }
        fs::write(&edited, text).unwrap();
    };
    let merge = || jointwear(&["sweep-merge", s(&edited), "--out", s(&merged)]);
    // A shard count of 2^64 - 1 panicked, one of 4e9 allocated 64 GB.
    for count in ["18446744073709551615", "4000000000"] {
        write(
            &id(&format!("shard=1/{count} cases=1 total=2")),
            &[&lines[1]],
        );
        assert_fails(&merge(), 2, &[&format!("no shard 2/{count}")]);
    }
    // Numbers that do not add up.
    for (bad, why) in [
        (
            "shard=1/1 cases=3 total=2",
            "cases=3: shard 1/1 of 2 cases owns 2",
        ),
        (
            "shard=1/1 cases=2000000 total=2000000",
            "at most 1000000 cases",
        ),
    ] {
        write(&id(bad), &[&lines[1], &lines[2]]);
        assert_fails(&merge(), 2, &[s(&edited), why]);
    }
    // A case outside the sweep, or twice, in merge and in --resume.
    let outside = lines[2].replacen("1,", "7,", 1);
    let twice = lines[1].clone();
    for row in [&outside, &twice] {
        write(genuine, &[&lines[1], row]);
        assert_fails(&merge(), 2, &["is not a case of shard 1/1"]);
        let resumed = jointwear(&[
            "sweep",
            &scene,
            "--set",
            "driver.speed_rpm=-2000,-1000",
            "--out",
            s(&edited),
            "--resume",
        ]);
        assert_fails(&resumed, 2, &["is not a case of shard 1/1"]);
    }
    // A row deleted: partial.
    write(genuine, &[&lines[1]]);
    assert_fails(&merge(), 2, &["1 of its 2 cases", "--allow-partial"]);
    let file = SweepFile::read(&edited).unwrap();
    assert_eq!((file.rows.len(), file.id.cases), (1, 2));
    fs::remove_dir_all(&dir).unwrap();
}

/// Every cell of a row is checked as the sweep writes it, in `sweep-merge` and in `sweep
/// --resume`: the error names the file, the row, the column and the value. Before, only the
/// case numbers were checked: a `nan` was merged (exit 0) and a resumed sweep kept it as a
/// finished case.
#[test]
fn edited_cells_of_sweep_files_are_refused_naming_row_column_and_value() {
    let dir = temp_dir("state", "cells");
    let (scene, lines) = shard_file(&dir);
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|c| c.ends_with(name)).unwrap();
    let edited = dir.join("edited.csv");
    let merged = dir.join("merged.csv");
    let sets = "driver.speed_rpm=-2000,-1000";
    let resume = || {
        let args = [
            "sweep",
            &scene,
            "--set",
            sets,
            "--out",
            s(&edited),
            "--resume",
        ];
        jointwear(&args)
    };
    // (column, new value, what the message says is written there)
    for (at, value, expected) in [
        (
            column("max_penetration_whole_run_m"),
            "nan",
            "a finite number",
        ),
        (
            column("max_wear_depth_m"),
            "inf",
            "a finite number >= 0, or an empty",
        ),
        (
            column("contact_fraction"),
            "1e999",
            "a number in [0, 1], or an empty",
        ),
        (column("motion_mode"), "flying", "`continuous contact`"),
        (column("wall_time_s"), "", "a finite number"),
        (column("driver.speed_rpm"), "", "a set value"),
        (column("error"), "boom", "the row of a failed case"),
        (
            header.len() - 1,
            "x",
            "the label check of its case, set values and results",
        ),
    ] {
        let mut cells: Vec<&str> = lines[2].split(',').collect();
        let name = header[at];
        cells[at] = value;
        fs::write(
            &edited,
            format!("{}\n{}\n{}\n", lines[0], lines[1], cells.join(",")),
        )
        .unwrap();
        let shown = if at == column("error") {
            // the error makes the first cell after the set values (the recorded window's) the
            // misfit
            "record_rotations"
        } else {
            name
        };
        let needles = [
            s(&edited),
            "row 2 (case 1)",
            &format!("column `{shown}`"),
            expected,
        ];
        let merge = jointwear(&["sweep-merge", s(&edited), "--out", s(&merged)]);
        assert_fails(&merge, 2, &needles);
        let resumed = resume();
        assert_fails(&resumed, 2, &needles);
        if at != column("error") {
            assert!(
                stderr(&merge).contains(&format!("`{value}`")),
                "{}",
                stderr(&merge)
            );
        }
    }
    // A set value changed to another valid value, or a row given another case, or a result
    // changed to another valid value: its label check no longer matches, which merge and
    // resume both tell (before the check, merge filed the results under the new label; and
    // before it covered the results, a wear depth edited, or rounded by a spreadsheet that
    // saved the file, was merged and resumed as the sweep's, exit 0).
    let mut result: Vec<&str> = lines[2].split(',').collect();
    let depth = format!(
        "{}",
        result[column("max_wear_depth_m")].parse::<f64>().unwrap() * 2.0
    );
    result[column("max_wear_depth_m")] = &depth;
    for relabelled in [
        lines[2].replacen("-1000", "-2000", 1),
        lines[2].replacen("1,", "0,", 1),
        result.join(","),
    ] {
        let row = if relabelled.starts_with("0,") {
            format!("{relabelled}\n")
        } else {
            format!("{}\n{relabelled}\n", lines[1])
        };
        fs::write(&edited, format!("{}\n{row}", lines[0])).unwrap();
        let needles = [
            "the label check of its case, set values and results",
            "a set value or a result) is not the one the sweep wrote",
        ];
        let merge = jointwear(&["sweep-merge", s(&edited), "--out", s(&merged)]);
        assert_fails(&merge, 2, &needles);
        assert_fails(&resume(), 2, &needles);
    }
    // A row with a cell too few (a complete line, not one cut by a kill) is refused; it was
    // dropped without a word, and `sweep-merge --allow-partial` merged without its case.
    let short = lines[2].replacen(",", "", 1);
    fs::write(&edited, format!("{}\n{}\n{short}\n", lines[0], lines[1])).unwrap();
    let merge = jointwear(&[
        "sweep-merge",
        s(&edited),
        "--out",
        s(&merged),
        "--allow-partial",
    ]);
    assert_fails(
        &merge,
        2,
        &[s(&edited), "row 2 has", "cells where the header has"],
    );
    // A joint's column renamed: its group no longer parses, so the header is not a sweep's.
    let renamed = lines[0].replacen(".motion_mode", ".motion", 1);
    fs::write(&edited, format!("{renamed}\n{}\n{}\n", lines[1], lines[2])).unwrap();
    let merge = jointwear(&["sweep-merge", s(&edited), "--out", s(&merged)]);
    assert_fails(&merge, 2, &[s(&edited), "is not a sweep's"]);
    // A failed case's row as the writer writes it is read back.
    let columns = header.len() - 3;
    let failed = format!("1,-1000{},some error", ",".repeat(columns - 1));
    let cells: Vec<String> = failed.split(',').map(String::from).collect();
    let id = SweepId::parse(header[header.len() - 1]).unwrap();
    let check = label_check(&id.fingerprint, &cells, column("wall_time_s"));
    fs::write(
        &edited,
        format!("{}\n{}\n{failed},{check}\n", lines[0], lines[1]),
    )
    .unwrap();
    assert_eq!(SweepFile::read(&edited).unwrap().rows.len(), 2);
    fs::remove_dir_all(&dir).unwrap();
}

/// A sweep file is a regular file read with a bound: a device or a FIFO is refused before it
/// is opened. Before, `sweep-merge /dev/zero` read until the memory ran out and a FIFO waited
/// for a writer (here one writes 2 kB, and the old code failed with "not a sweep file").
#[test]
fn sweep_files_that_are_devices_or_fifos_are_refused_without_reading_them() {
    let dir = temp_dir("state", "fifo");
    let scene = short_standard(&dir, "scene.toml", 1, &[]);
    let merged = dir.join("merged.csv");
    let o = jointwear(&["sweep-merge", "/dev/null", "--out", s(&merged)]);
    assert_fails(&o, 2, &["/dev/null", "not a regular file"]);
    let fifo = dir.join("sweep.fifo");
    for args in [
        vec!["sweep-merge", s(&fifo), "--out", s(&merged)],
        vec!["sweep", s(&scene), "--out", s(&fifo), "--resume"],
    ] {
        with_waiting_writer(&fifo, || {
            assert_fails(&jointwear(&args), 2, &["sweep.fifo", "not a regular file"])
        });
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// An output folder's manifest is a regular file read with a bound: a device or a FIFO in its
/// place is refused before it is opened. Before, a manifest linked to /dev/zero was read until
/// the memory ran out, and a FIFO made `run` wait for a writer (here one writes 2 kB of
/// comments, and the old code ran, exit 0; /dev/null read as an empty manifest).
#[test]
fn manifests_that_are_devices_or_fifos_are_refused_without_reading_them() {
    let dir = temp_dir("state", "manifest-fifo");
    let scene = short_standard(&dir, "scene.toml", 1, &[]);
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    let manifest = out.join("jointwear-manifest.txt");
    let refused = || {
        let o = jointwear(&["run", s(&scene), "--out", s(&out)]);
        assert_fails(&o, 2, &[s(&manifest), "not a regular file"]);
    };
    std::os::unix::fs::symlink("/dev/null", &manifest).unwrap();
    refused();
    fs::remove_file(&manifest).unwrap();
    with_waiting_writer(&manifest, refused);
    assert_eq!(file_names(&out), ["jointwear-manifest.txt"]);
    fs::remove_dir_all(&dir).unwrap();
}

/// A lock file is a regular file read with a bound: a FIFO in its place (an output folder's
/// lock, or a `.<name>.lock` of a file's claim in it) is refused or passed over, never opened.
/// Before, `run` waited for a writer of the FIFO (here one writes 2 kB of `#` lines, which the
/// old code read and refused as a lock cut short, the folder's as the run's own lock: exit 2
/// without naming the FIFO; the file claim's as a sweep's).
#[test]
fn locks_that_are_fifos_are_never_opened() {
    let dir = temp_dir("state", "lock-fifo");
    let scene = short_standard(&dir, "scene.toml", 1, &[]);
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    let run = || jointwear(&["run", s(&scene), "--out", s(&out)]);
    let lock = out.join(".jointwear.lock");
    with_waiting_writer(&lock, || {
        assert_fails(&run(), 2, &[s(&lock), "not a regular file"])
    });
    fs::remove_file(&lock).unwrap();
    // Not a sweep's claim, which the run looks for: it goes on without reading it.
    with_waiting_writer(&out.join(".sweep.csv.lock"), || {
        let o = run();
        assert!(o.status.success(), "{}", stderr(&o));
    });
    fs::remove_dir_all(&dir).unwrap();
}
