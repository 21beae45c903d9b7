//! Failure modes of the `jointwear` program: each fails with its exit code (2 bad input, 1 a
//! failure while running) and a message naming its cause, before any simulation where the
//! cause is knowable up front.

mod common;

use common::*;
use jointwear::scene::scene_path;
use std::fs;

/// A step limit that fails any simulation of two rotations within 100 steps (they need about
/// 10 000), yet passes validation (at the 1 ms largest step they need at least 60).
const FEW_STEPS: (&str, &str) = (
    "record_interval_s = 1e-5",
    "record_interval_s = 1e-5\nmax_steps = 100",
);

#[test]
fn a_missing_scene_file_is_bad_input() {
    let dir = temp_dir("guards", "missing");
    let absent = dir.join("absent.toml");
    for command in ["check", "run", "sweep", "longlife"] {
        let o = jointwear(&[command, s(&absent)]);
        assert_fails(&o, 2, &["absent.toml", "No such file"]);
    }
    let o = jointwear(&["sweep-merge", s(&absent), "--out", s(&dir.join("all.csv"))]);
    assert_fails(&o, 2, &["absent.toml", "No such file"]);
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
    // A simulation would fail at its 100th step (exit 1): exit 2 shows none was run.
    let scene = short_standard(&dir, "few-steps.toml", 2, &[FEW_STEPS]);
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
    assert_fails(&o, 1, &["step limit of 100 steps"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_recording_beyond_the_memory_budget_fails_at_validation() {
    let dir = temp_dir("guards", "budget");
    let tiny = (
        "record_interval_s = 1e-5",
        "record_interval_s = 1e-12\nmax_steps = 100",
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
    // A sweep checks every case's recording against the budget.
    let scene = short_standard(&dir, "few-steps.toml", 2, &[FEW_STEPS]);
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "run.record_interval_s=1e-5,1e-12",
        "--out",
        s(&dir.join("sweep.csv")),
    ]);
    let in_case = "`run.record_interval_s (in case 1: run.record_interval_s=1e-12)`: 1e-12 s";
    assert_fails(&o, 2, &[&[in_case], &needles[1..]].concat());
    assert!(!dir.join("out").exists() && !dir.join("sweep.csv").exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// The four-bar with a 145 mm coupler, which cannot close: its pin A is 70 mm from the
/// rocker pivot at crank angle 0, and the 70 mm rocker reaches at most 140 mm from it.
const OPEN_FOURBAR: (&str, &str) = (
    "points_mm = { A = [-45.0, 0.0], B = [45.0, 0.0] }",
    "points_mm = { A = [-45.0, 0.0], B = [100.0, 0.0] }",
);

#[test]
fn check_assembles_and_prints_the_pose_of_every_body() {
    let dir = temp_dir("guards", "branch");
    let out = dir.join("out");
    let o = jointwear(&["check", s(&scene_path("fourbar")), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for line in [
        "assembled pose at t = 0 (clearance joints centred):",
        "  crank        x    15.0000 mm, y     0.0000 mm, angle     0.000 deg",
        "  coupler      x    58.9286 mm, y    34.4694 mm, angle    49.995 deg",
        "  rocker       x    93.9286 mm, y    34.4694 mm, angle    99.990 deg",
    ] {
        assert!(text.contains(line), "lacks `{line}`: {text}");
    }
    assert!(!text.contains("note:"), "{text}");
    // A rocker guessed 100 deg off closes the loop elbow down, and check says so.
    let scene = dir.join("far.toml");
    let far = ("angle_deg = 100.0", "angle_deg = 200.0");
    fs::write(&scene, scene_with("fourbar", &[far])).unwrap();
    let text = stdout(&jointwear(&["check", s(&scene), "--out", s(&out)]));
    for line in [
        "  coupler      x    58.9286 mm, y   -34.4694 mm, angle   -49.995 deg",
        "    note: 60.0 deg from its guessed angle: the loop may have closed on another branch",
    ] {
        assert!(text.contains(line), "lacks `{line}`: {text}");
    }
    // A rocker guessed seven turns on assembles seven turns on, printed wrapped (was 2619.990).
    let turns = ("angle_deg = 100.0", "angle_deg = 2620.0");
    fs::write(&scene, scene_with("fourbar", &[turns])).unwrap();
    let text = stdout(&jointwear(&["check", s(&scene), "--out", s(&out)]));
    let line = "  rocker       x    93.9286 mm, y    34.4694 mm, angle    99.990 deg";
    assert!(text.contains(line), "lacks `{line}`: {text}");
    assert!(!text.contains("note:"), "{text}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_loop_that_cannot_close_is_bad_input_naming_its_joints_in_check_run_and_sweep() {
    let dir = temp_dir("guards", "open");
    let scene = dir.join("open.toml");
    fs::write(&scene, scene_with("fourbar", &[OPEN_FOURBAR])).unwrap();
    let needles = [
        "`joints (assembly)`: the loop cannot close",
        "revolute[2] (ground-rocker)",
        "clearance joint `coupler-rocker` (coupler-rocker, held ideal)",
    ];
    let out = dir.join("out");
    for args in [
        vec!["check", s(&scene)],
        vec!["run", s(&scene), "--out", s(&out)],
    ] {
        assert_fails(&jointwear(&args), 2, &needles);
    }
    // The sweep assembles every case before running any: the second case fails it.
    let scene = dir.join("sweep.toml");
    let text = scene_with(
        "fourbar",
        &[
            ("rotations = 20 ", "rotations = 2 "),
            ("wear_snapshots = [5, 10, 20]", "wear_snapshots = []"),
        ],
    );
    fs::write(&scene, text).unwrap();
    let csv = dir.join("sweep.csv");
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "bodies.1.points_mm.B=[45.0, 0.0],[100.0, 0.0]",
        "--out",
        s(&csv),
    ]);
    assert_fails(
        &o,
        2,
        &[
            "`joints (assembly) (in case 1: bodies.1.points_mm.B=[100.0, 0.0])`",
            needles[1],
        ],
    );
    assert!(!csv.exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// The revolute a clearance joint replaces, left beside it, is named with what to do rather than
/// reported as dependent constraints at assembly (which it was; the check would fail against
/// that message).
#[test]
fn a_revolute_left_beside_its_clearance_joint_is_named_to_be_removed() {
    let dir = temp_dir("guards", "replaced");
    let scene = dir.join("both.toml");
    let left = "[[translational]]";
    let both = "[[revolute]]\na = \"slider.C\"\nb = \"rod.B\"\n\n[[translational]]";
    fs::write(&scene, scene_with("standard", &[(left, both)])).unwrap();
    let out = dir.join("out");
    assert_fails(
        &jointwear(&["check", s(&scene), "--out", s(&out)]),
        2,
        &[
            "`revolute[2]`: slider.C - rod.B",
            "clearance joint `rod-slider`",
            "remove this [[revolute]]",
        ],
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_value_of_a_sweep_names_its_case_and_assignments() {
    let dir = temp_dir("guards", "sweep_case");
    let scene = short_standard(&dir, "one.toml", 1, &[]);
    let csv = dir.join("sweep.csv");
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "driver.speed_rpm=600,2000",
        "--set",
        "clearance.0.clearance_mm=0.1,-1",
        "--out",
        s(&csv),
    ]);
    assert_fails(
        &o,
        2,
        &["(in case 1: driver.speed_rpm=600, clearance.0.clearance_mm=-1)`: -1"],
    );
    assert!(!csv.exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// Fails on the code before: `run --set K=0.02 --set K=0.03` (or an alias of K) ran with the
/// last value, exit 0, where `sweep` refuses a key given twice.
#[test]
fn a_run_refuses_a_key_given_twice() {
    let dir = temp_dir("guards", "set_twice");
    let scene = short_standard(&dir, "few-steps.toml", 2, &[FEW_STEPS]);
    let run = |args: &[&str]| {
        let mut all = vec!["run", s(&scene), "--out", s(&dir)];
        all.extend_from_slice(args);
        jointwear(&all)
    };
    for extra in [&[][..], &["--ensemble", "2"]] {
        let mut args = vec![
            "--set",
            "clearance.0.clearance_mm=0.02",
            "--set",
            "clearance.00.clearance_mm=0.03",
        ];
        args.extend_from_slice(extra);
        let o = run(&args);
        assert_fails(
            &o,
            2,
            &[
                "`--set`: clearance.0.clearance_mm",
                "given twice",
                "`0.02` and as `0.03`",
            ],
        );
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// The check for a key given twice changes nothing else: a key given once is asked as
/// written, so a run's fingerprint (its checkpoint's) and recorded command line are those of
/// runs before the check and of Python's `set` of the same key. Failed with the keys made
/// canonical: `clearance.00.clearance_mm` ran as `clearance.0.clearance_mm`, another
/// fingerprint, and an older checkpoint of that command line could not be resumed.
#[test]
fn a_key_given_once_is_asked_as_written() {
    use jointwear::scene::variant::Variant;
    let dir = temp_dir("guards", "set_as_written");
    let scene = scene_path("standard");
    let sets = [
        ("clearance.00.clearance_mm", "0.03"),
        ("run.record_rotations", "0"),
    ];
    let mut args = vec!["run", s(&scene), "--rotations", "1", "--out", s(&dir)];
    let words: Vec<String> = sets.iter().map(|(k, v)| format!("{k}={v}")).collect();
    for w in &words {
        args.extend_from_slice(&["--set", w]);
    }
    let o = jointwear(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut variant = Variant::read(&scene).unwrap();
    for (k, v) in sets {
        variant
            .set(k, jointwear::sweep::parse_value(v), v, false)
            .unwrap();
    }
    variant.set("run.rotations", 1.into(), "1", true).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["scene"]["fingerprint"].as_str(),
        Some(variant.fingerprint().as_str()),
        "{}",
        summary["scene"]
    );
    let readme = fs::read_to_string(dir.join("README.txt")).unwrap();
    assert!(
        readme.contains("--set clearance.00.clearance_mm=0.03"),
        "{readme}"
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_rerun_replaces_the_previous_run_and_leaves_other_files_alone() {
    let dir = temp_dir("guards", "rerun");
    let scene = short_standard(&dir, "one.toml", 1, &[]);
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    // A previous run's manifest lists a profile this run does not write; notes.txt is the
    // user's.
    let manifest = out.join("jointwear-manifest.txt");
    fs::write(
        &manifest,
        "# jointwear run old.toml\nwear_old-joint.csv\ntimeseries.csv\n",
    )
    .unwrap();
    fs::write(out.join("wear_old-joint.csv"), "stale").unwrap();
    fs::write(out.join("timeseries.csv"), "stale").unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = jointwear(&["run", s(&scene), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let listed: Vec<String> = fs::read_to_string(&manifest)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_owned)
        .collect();
    let mut expected = [
        "timeseries.csv",
        "wear_rod-slider.csv",
        "wear.png",
        "trajectory.png",
        "normal_force.png",
        "summary.json",
        "README.txt",
    ];
    let mut sorted = listed.clone();
    sorted.sort();
    expected.sort();
    assert_eq!(sorted, expected);
    let mut present: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    present.sort();
    let mut wanted: Vec<String> = listed;
    wanted.extend(["jointwear-manifest.txt".into(), "notes.txt".into()]);
    wanted.sort();
    assert_eq!(present, wanted);
    assert_ne!(
        fs::read_to_string(out.join("timeseries.csv")).unwrap(),
        "stale"
    );
    fs::remove_dir_all(&dir).unwrap();
}

/// The file names a manifest lists (its comment lines left out).
fn manifest_names(dir: &std::path::Path) -> Vec<String> {
    jointwear::io::output::read_manifest(dir, |_| true).unwrap()
}

/// A manifest is not trusted: a title cannot add a line to it, and a line that names no
/// output of the program (the user's notes, a scene, a checkpoint, a file outside the folder)
/// is refused before the run, removing nothing. Fails on the code before: the title's line
/// break made `notes.txt` a listed file, and the rerun deleted the user's notes (exit 0), as
/// it deleted every name an edited manifest listed.
#[test]
fn a_manifest_names_only_outputs_and_no_title_adds_to_it() {
    let dir = temp_dir("guards", "manifest");
    let scene = short_standard(&dir, "one.toml", 1, &[]);
    let out = dir.join("out");
    let run = || jointwear(&["run", s(&scene), "--out", s(&out)]);
    let o = jointwear(&[
        "run",
        s(&scene),
        "--set",
        "title=A\nnotes.txt",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = fs::read_to_string(out.join("jointwear-manifest.txt")).unwrap();
    assert!(text.starts_with("# jointwear run "), "{text}");
    assert!(
        text.lines().next().unwrap().contains(r"title=A\nnotes.txt"),
        "{text}"
    );
    assert!(
        !manifest_names(&out).contains(&"notes.txt".to_string()),
        "{text}"
    );
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = run();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    let outputs = manifest_names(&out);
    for (foreign, content) in [
        ("notes.txt", None),
        ("myscene.toml", Some("title = \"mine\"")),
        ("checkpoint.json", Some("{}")),
        (".hidden.csv", Some("a")),
        ("../one.toml", None),
        ("wear_rod slider.csv", Some("a")),
    ] {
        if let Some(content) = content {
            fs::write(out.join(foreign), content).unwrap();
        }
        let before = file_names(&out);
        let manifest = format!("# edited\n{}\n{foreign}\n", outputs.join("\n"));
        fs::write(out.join("jointwear-manifest.txt"), &manifest).unwrap();
        let o = run();
        assert_fails(
            &o,
            2,
            &["jointwear-manifest.txt", foreign, "remove the line"],
        );
        assert_eq!(file_names(&out), before, "{foreign}");
        assert!(out.join(foreign).exists() && scene.exists(), "{foreign}");
        let left = fs::read_to_string(out.join("jointwear-manifest.txt")).unwrap();
        assert_eq!(left, manifest);
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// A rerun that stops while writing leaves a manifest, marked incomplete, that lists the
/// previous run's files and its own, and the next complete run removes those it does not
/// write. Fails on the code before: the rerun removed the manifest before writing, so the
/// previous run's snapshot files were listed nowhere and stayed beside the next run's outputs
/// (exit 0).
#[test]
fn a_rerun_that_stops_while_writing_loses_track_of_no_output() {
    let dir = temp_dir("guards", "stopped-write");
    let scene = short_standard(&dir, "two.toml", 2, &[]);
    let out = dir.join("out");
    let run = |snapshots: &str| {
        let set = format!("run.wear_snapshots={snapshots}");
        jointwear(&["run", s(&scene), "--set", &set, "--out", s(&out)])
    };
    let o = run("[1,2]");
    assert!(o.status.success(), "{}", stderr(&o));
    let first = manifest_names(&out);
    assert!(first.contains(&"wear_snapshots_rod-slider.csv".to_string()));
    // A directory where the rerun writes wear.png stops it after its first files, as a kill
    // would (deterministically).
    fs::remove_file(out.join("wear.png")).unwrap();
    fs::create_dir(out.join("wear.png")).unwrap();
    let o = run("[]");
    assert!(!o.status.success(), "{}", stderr(&o));
    let text = fs::read_to_string(out.join("jointwear-manifest.txt")).unwrap();
    assert!(
        text.lines().nth(1).unwrap().contains("INCOMPLETE"),
        "{text}"
    );
    let listed = manifest_names(&out);
    for name in first.iter().filter(|n| out.join(n).is_file()) {
        assert!(listed.contains(name), "{name} unlisted: {text}");
    }
    fs::remove_dir(out.join("wear.png")).unwrap();
    let o = run("[]");
    assert!(o.status.success(), "{}", stderr(&o));
    let mut expected = manifest_names(&out);
    assert!(
        !expected.iter().any(|n| n.contains("snapshots")),
        "{expected:?}"
    );
    expected.push("jointwear-manifest.txt".into());
    expected.sort();
    assert_eq!(file_names(&out), expected);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_interrupted_run_says_so_and_exits_130() {
    let dir = temp_dir("guards", "interrupt");
    // 5 000 rotations: still simulating when the signal comes (about 1.1e7 steps, tens of
    // seconds), and within run.max_steps, so that the crawl guard does not end the run first
    // (with 100 000 rotations it did, at 2e5 steps, once a run of them took under 0.5 s).
    // k/H a thousandth of the scene's: at its own the groove passes the gap's validity bound
    // within about 130-200 rotations, under 0.5 s, and the run stops there (exit 1) first.
    let scene = short_standard(
        &dir,
        "long.toml",
        5_000,
        &[("k_over_h_per_pa = 1e-12", "k_over_h_per_pa = 1e-15")],
    );
    let out = dir.join("out");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_jointwear"))
        .args(["run", s(&scene), "--out", s(&out)])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(kill.unwrap().success());
    let o = child.wait_with_output().unwrap();
    assert_fails(&o, 130, &["interrupted: no temporary outputs to remove"]);
    assert!(!out.exists());
    fs::remove_dir_all(&dir).unwrap();
}
