//! The `jointwear` program end to end: outputs, exit codes, error messages, sweeps and shards.

use jointwear::io::output::{number, read_csv, read_rows};
use jointwear::scene::scene_path;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn jointwear(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_jointwear"))
        .args(args)
        .output()
        .expect("jointwear runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh, empty directory per test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("jointwear-cli-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// The standard scene cut to `rotations` rotations, written into `dir`.
fn short_standard(dir: &Path, rotations: u32) -> PathBuf {
    let text = fs::read_to_string(scene_path("standard"))
        .unwrap()
        .replace("rotations = 40", &format!("rotations = {rotations}"))
        .replace("record_rotations = 2", "record_rotations = 1")
        .replace("wear_snapshots = [10, 20, 30, 40]", "wear_snapshots = []");
    let path = dir.join("short.toml");
    fs::write(&path, text).unwrap();
    path
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn run_writes_series_wear_plots_and_summary() {
    let dir = temp_dir("run");
    let scene = short_standard(&dir, 2);
    let out = dir.join("out");
    let o = jointwear(&["run", s(&scene), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "steps",
        "wall time",
        "max normal force",
        "motion:",
        "wear region at",
    ] {
        assert!(text.contains(needle), "summary lacks {needle}: {text}");
    }
    let (header, columns) = read_csv(&out.join("timeseries.csv")).unwrap();
    assert_eq!(header[..2], ["time_s", "driver_angle_rad"]);
    for col in [
        "rod-slider.normal_force_n",
        "rod-slider.wear_rate_m_s",
        "slider.ax_m_s2",
    ] {
        assert!(header.iter().any(|h| h == col), "no column {col}");
    }
    assert!(columns[0].len() > 1000);
    let (header, columns) = read_csv(&out.join("wear_rod-slider.csv")).unwrap();
    assert_eq!(header, ["angle_deg", "depth_m"]);
    assert_eq!(columns[0].len(), 360);
    assert!(columns[1].iter().any(|&d| d > 0.0));
    for png in ["trajectory.png", "normal_force.png", "wear.png"] {
        let bytes = fs::read(out.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn check_describes_the_scene() {
    let dir = temp_dir("check");
    let o = jointwear(&["check", s(&scene_path("fourbar")), "--out", s(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    fs::remove_dir_all(&dir).unwrap();
    let text = stdout(&o);
    for needle in [
        "coupler-rocker",
        "rocker",
        "driver: crank at 1000 r/min",
        "degrees of freedom: 2",
        "20 rotations",
        // the scene's words and values, as its file writes them (was Rust's `Modified { .. }`,
        // `HertzLine`, `Dopri5`)
        "contact = { model = \"hybrid\", exponent = 1.5, grazing_velocity_m_s = 0.001, \
         restitution = 0.8 }",
        "friction = { model = \"modified\", mu_d = 0.08, mu_s = 0.12, v_d = 0.001, v_s = 0.0001 }",
        "wear = { k_over_h_per_pa = 1e-12, length_mm = 12, pressure = \"hertz-line\", \
         sectors = 360 }",
        "method \"dopri5\"",
    ] {
        assert!(text.contains(needle), "lacks {needle}: {text}");
    }
}

#[test]
fn bad_input_exits_2_naming_file_field_and_range() {
    let dir = temp_dir("bad");
    let scene = dir.join("bad.toml");
    let text = fs::read_to_string(scene_path("standard")).unwrap();
    fs::write(
        &scene,
        text.replace("restitution = 0.9", "restitution = 1.5"),
    )
    .unwrap();
    let o = jointwear(&["run", s(&scene), "--out", s(&dir.join("out"))]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("bad.toml")
            && err.contains("clearance[0].contact.restitution")
            && err.contains("[0.1, 1]"),
        "{err}"
    );
    assert!(!dir.join("out").exists(), "bad input wrote outputs");
    let o = jointwear(&["check", s(&dir.join("absent.toml"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("absent.toml"));
    let std = scene_path("standard");
    for args in [
        vec!["sweep", s(&std), "--set", "driver.speed_rpm"],
        vec!["sweep", s(&std), "--set", "driver.nope.x=1"],
        vec!["sweep", s(&std), "--set", "clearance.3.clearance_mm=1"],
        vec![
            "sweep",
            s(&std),
            "--set",
            "clearance.0.clearance_mm=0.02,12",
        ],
        vec!["sweep", s(&std), "--shard", "4/3"],
        vec!["longlife", s(&std), "--rotations", "1.5"],
        vec!["run"],
    ] {
        let o = jointwear(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
    // longlife's options are named as given: written into the scene first, --k-over-h was
    // reported as `clearance[0].wear.k_over_h_per_pa`, --max-change as `max_change`, and
    // --until NaN as "n/a mm".
    for (option, value, named) in [
        ("--k-over-h", "1e-3", "`--k-over-h`: 0.001"),
        ("--k-over-h", "NaN", "`--k-over-h`: NaN"),
        ("--max-change", "0", "`--max-change`: 0"),
        ("--until", "NaN", "`--until`: NaN for joint"),
        // Fails on the code before: 4e9 settling rotations ran into the step limit after 20 s,
        // exit 1, blamed on the run's length.
        (
            "--settle",
            "10001",
            "`--settle`: 10001 (expected an integer in [0, 10000]",
        ),
        // Fails on the code before: blocks of a depth change of 2e-305 m extrapolated
        // nothing, so the prediction simulated every rotation (exit 0 here after 189 of them;
        // at k/H 1e-15, 20 s into the step limit, exit 1).
        (
            "--max-change",
            "1e-300",
            "`--max-change`: 1e-300 (expected at least 5e-6",
        ),
    ] {
        let o = jointwear(&["longlife", s(&std), option, value]);
        assert_eq!(o.status.code(), Some(2), "{option}: {}", stderr(&o));
        assert!(stderr(&o).contains(named), "{named}: {}", stderr(&o));
    }
    // So is a wear coefficient for a joint without clearance, which its scene refuses.
    let zero = scene_path("standard").with_file_name("stability/zero_clearance.toml");
    let o = jointwear(&["longlife", s(&zero), "--k-over-h", "1e-12"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("`--k-over-h`: 1e-12 (expected 0 for this scene: its joint"),
        "{}",
        stderr(&o)
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn help_shows_examples() {
    let o = jointwear(&["--help"]);
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(
        text.contains("Examples:") && text.contains("--shard 2/4"),
        "{text}"
    );
}

#[test]
fn shards_merge_into_the_whole_sweep() {
    let dir = temp_dir("sweep");
    let scene = short_standard(&dir, 1);
    let sets = [
        "--set",
        "clearance.0.clearance_mm=0.02,0.1",
        "--set",
        "driver.speed_rpm=600,2000",
    ];
    let sweep = |extra: &[&str], out: &Path| {
        let mut args = vec!["sweep", s(&scene)];
        args.extend(sets);
        args.extend(extra);
        args.extend(["--out", s(out)]);
        let o = jointwear(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    let whole = dir.join("whole.csv");
    sweep(&[], &whole);
    let shards: Vec<PathBuf> = (1..=3).map(|i| dir.join(format!("s{i}.csv"))).collect();
    for (i, p) in shards.iter().enumerate() {
        sweep(&["--shard", &format!("{}/3", i + 1)], p);
    }
    let merged = dir.join("merged.csv");
    let mut args = vec!["sweep-merge"];
    args.extend(shards.iter().rev().map(|p| s(p)));
    args.extend(["--out", s(&merged)]);
    let o = jointwear(&args);
    assert!(o.status.success(), "{}", stderr(&o));

    let rows = |p: &Path| -> Vec<Vec<String>> {
        // The first line names the sweep, as a comment.
        // plain CSV: no comment lines to skip
        let mut r = csv::ReaderBuilder::new().from_path(p).unwrap();
        let mut v = vec![r.headers().unwrap().iter().map(str::to_owned).collect()];
        v.extend(
            r.records()
                .map(|rec| rec.unwrap().iter().map(str::to_owned).collect()),
        );
        v
    };
    let (w, m) = (rows(&whole), rows(&merged));
    assert_eq!(w.len(), 5);
    assert_eq!(w[0], m[0]);
    assert_eq!(
        w[0][..3],
        ["case", "clearance.0.clearance_mm", "driver.speed_rpm"]
    );
    for (a, b) in w[1..].iter().zip(&m[1..]) {
        // identical cases up to the wall time (before `error` and the sweep's id column)
        let strip = |r: &[String]| {
            let mut r = r.to_vec();
            let n = r.len();
            r.remove(n - 3);
            r
        };
        assert_eq!(strip(a), strip(b));
    }
    assert_eq!(w[1][..3], ["0", "0.02", "600"]);
    assert_eq!(w[4][..3], ["3", "0.1", "2000"]);
    let mode = w[0]
        .iter()
        .position(|h| h == "rod-slider.motion_mode")
        .unwrap();
    let modes = ["continuous contact", "free flight and impact"];
    assert!(w[1..].iter().all(|r| modes.contains(&r[mode].as_str())));

    // headers must agree, cases must be unique
    let other = dir.join("other.csv");
    fs::write(&other, "case,x\n7,1\n").unwrap();
    let o = jointwear(&["sweep-merge", s(&shards[0]), s(&other), "--out", s(&merged)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("header"), "{}", stderr(&o));
    let o = jointwear(&[
        "sweep-merge",
        s(&shards[0]),
        s(&shards[0]),
        "--out",
        s(&merged),
    ]);
    assert_eq!(o.status.code(), Some(2));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn longlife_writes_profiles_and_growth() {
    let dir = temp_dir("longlife");
    let out = dir.join("out");
    let standard = scene_path("standard");
    let longlife = |rotations: &str, out: &Path| {
        let scene = s(&standard);
        let args = [
            "longlife",
            scene,
            "--rotations",
            rotations,
            "--k-over-h",
            "1e-15",
        ];
        jointwear(&[&args[..], &["--out", s(out)]].concat())
    };
    let o = longlife("5e4", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("50000 rotations predicted"));
    let (header, columns) = read_csv(&out.join("longlife_growth.csv")).unwrap();
    assert_eq!(
        header,
        [
            "rotations",
            "rod-slider.max_depth_m",
            "rod-slider.clearance_m"
        ]
    );
    assert_eq!(*columns[0].last().unwrap(), 5e4);
    // counts as integers: the snapshot at 40 000 rotations was written 4e4
    let text = fs::read_to_string(out.join("longlife_growth.csv")).unwrap();
    let counts: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| &l[..l.find(',').unwrap()])
        .collect();
    assert!(counts.contains(&"40000"), "{counts:?}");
    assert!(
        counts.iter().all(|c| c.parse::<u64>().is_ok()),
        "{counts:?}"
    );
    // what each block was extrapolated from, and what the printout says of it
    let (header, blocks) = read_rows(&out.join("longlife_blocks.csv")).unwrap();
    assert_eq!(
        header[..3],
        [
            "sampled_rotations",
            "rotations",
            "rod-slider.wear_rate_m_per_rotation"
        ]
    );
    assert_eq!(blocks.len(), columns[0].len() - 1);
    assert!(
        stdout(&o).contains("extrapolated: the other")
            && stdout(&o).contains("within the validated regime throughout"),
        "{}",
        stdout(&o)
    );
    let (header, _) = read_csv(&out.join("longlife_profiles_rod-slider.csv")).unwrap();
    assert_eq!(
        header,
        [
            "angle_deg",
            "rot10000_m",
            "rot20000_m",
            "rot30000_m",
            "rot40000_m",
            "rot50000_m"
        ]
    );
    for png in ["longlife_growth.png", "longlife_profiles.png"] {
        assert!(out.join(png).exists(), "{png}");
    }
    // The folder explains itself: every file in README.txt, the numbers in summary.json.
    let readme = fs::read_to_string(out.join("README.txt")).unwrap();
    for file in [
        "longlife_growth.csv",
        "longlife_profiles_rod-slider.csv",
        "longlife_blocks.csv",
        "summary.json",
    ] {
        assert!(readme.contains(file), "README.txt lacks {file}");
    }
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["rotations_predicted"], 50000);
    assert_eq!(summary["validity_stop"], serde_json::Value::Null);
    let joint = &summary["joints"][0];
    let depth = joint["max_wear_depth_m"].as_f64().unwrap();
    assert_eq!(depth, *columns[1].last().unwrap());
    assert_eq!(
        joint["effective_clearance_m"].as_f64().unwrap(),
        *columns[2].last().unwrap()
    );
    assert_eq!(joint["validated_until_rotations"], serde_json::Value::Null);
    assert!(joint["changes"].is_array());

    // A million rotations outgrow the paper's gap: the prediction stops short, says so, and
    // keeps what it predicted up to there (exit 0).
    let out = dir.join("stopped");
    let o = longlife("1e6", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("of the 1000000 rotations asked for, where the model stops"),
        "{}",
        stdout(&o)
    );
    let summary = json(&out.join("summary.json"));
    let stop = summary["validity_stop"]
        .as_array()
        .expect("a validity stop");
    assert_eq!(stop[0], summary["rotations_predicted"]);
    assert_eq!(stop[1], "rod-slider");
    assert!(
        stop[2].as_str().unwrap().contains("|dh/dθ| / (c + h) = "),
        "{stop:?}"
    );
    assert!(summary["rotations_predicted"].as_u64().unwrap() < 1_000_000);
    // The stop is told at the rotation predicted, and the simulated rotation that found it
    // named as such: the message said "after simulated driver rotation 11" of a stop at
    // rotation 160990.
    let at = format!(
        " deg after rotation {} of the prediction, its simulated driver rotation {} (",
        stop[0], summary["rotations_simulated"]
    );
    assert!(stop[2].as_str().unwrap().contains(&at), "{at}: {stop:?}");
    assert!(stdout(&o).contains(&at), "{at}: {}", stdout(&o));
    assert!(!stdout(&o).contains("after simulated"), "{}", stdout(&o));
    fs::remove_dir_all(&dir).unwrap();
}

/// The JSON file at `path`.
fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap()
}

/// Every column of `timeseries.csv` is there (the contact angle too), explained in README.txt,
/// and every number is the shortest text that reads back to the same double. Would fail on a
/// dropped column, an undocumented one, or numbers in `{:e}` (`3.3e-1` for a time).
#[test]
fn run_outputs_are_documented_and_numbers_round_trip() {
    let dir = temp_dir("conventions");
    let scene = short_standard(&dir, 2);
    let out = dir.join("out");
    let o = jointwear(&["run", s(&scene), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = fs::read_to_string(out.join("timeseries.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let readme = fs::read_to_string(out.join("README.txt")).unwrap();
    for column in &header {
        // `J.ex_m` is explained as `J.ex_m`, a body's `B.ax_m_s2` as `B.ax_m_s2`.
        let generic = match column.split_once('.') {
            Some(("rod-slider", name)) => format!("J.{name}"),
            Some((_, name)) => format!("B.{name}"),
            None => column.to_string(),
        };
        assert!(readme.contains(&generic), "README.txt lacks {generic}");
    }
    for needle in [
        "UNWRAPPED",
        "GLOBAL frame",
        "BEARING frame",
        "POSITIVE in contact",
    ] {
        assert!(readme.contains(needle), "README.txt lacks {needle}");
    }
    let angle = header
        .iter()
        .position(|h| *h == "rod-slider.contact_angle_deg")
        .expect("contact angle column");
    let (ex, ey) = (angle - 2, angle - 1);
    assert_eq!(header[ex], "rod-slider.ex_m");
    let mut rows = 0;
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), header.len());
        for f in &fields {
            let x: f64 = f.parse().unwrap();
            assert_eq!(number(x), *f, "not the shortest round-trip text");
        }
        // The standard scene's bearing (the slider) does not turn: the contact angle is the
        // direction of (ex, ey) in the global frame.
        let v = |i: usize| fields[i].parse::<f64>().unwrap();
        let global = v(ey).atan2(v(ex)).to_degrees().rem_euclid(360.0);
        assert!((0.0..360.0).contains(&v(angle)));
        let diff = (global - v(angle) + 180.0).rem_euclid(360.0) - 180.0;
        assert!(diff.abs() < 1e-9, "{global} vs {}", v(angle));
        rows += 1;
    }
    assert!(rows > 1000);
    // A time of the recording grid is written plainly, not as e-notation.
    assert!(!text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .contains('e'));
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["counts"]["recorded_samples"], rows);
    assert_eq!(summary["settings"]["rotations"], 2);
    let joint = &summary["joints"][0];
    assert_eq!(joint["name"], "rod-slider");
    assert!(joint["max_normal_force_recorded_n"].as_f64().unwrap() > 0.0);
    assert!(joint["max_penetration_recorded_m"].as_f64().unwrap() > 0.0);
    assert!(joint["wear_regions"][0]["depth_m"].as_f64().unwrap() > 0.0);
    assert!(joint["motion"]["mode"].is_string());
    let manifest = fs::read_to_string(out.join("jointwear-manifest.txt")).unwrap();
    assert!(manifest.contains("summary.json") && manifest.contains("README.txt"));
    fs::remove_dir_all(&dir).unwrap();
}

/// `--set` and `--rotations` change the scene that runs (summary.json says so), snapshots come
/// out at the requested rotations, and the last snapshot is the final profile. Would fail if
/// `--set` were ignored, or on a snapshot column of another rotation.
#[test]
fn run_set_rotations_and_wear_snapshots() {
    let dir = temp_dir("set");
    let scene = short_standard(&dir, 2);
    let out = dir.join("out");
    let o = jointwear(&[
        "run",
        s(&scene),
        "--set",
        "clearance.0.clearance_mm=0.1",
        "--rotations",
        "4",
        "--set",
        "run.wear_snapshots=[1, 3, 4]",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("Standard"), "{}", stdout(&o));
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["settings"]["rotations"], 4);
    assert_eq!(summary["counts"]["rotations_simulated"], 4);
    assert_eq!(
        summary["settings"]["wear_snapshots"],
        serde_json::json!([1, 3, 4])
    );
    // Echoed as given, to the last digit (was 9.99999999999994e-5 here and
    // 1.9999999999999185e-5 for the file's 0.02 mm below; driver -1999.9999999999998).
    let c = summary["joints"][0]["radial_clearance_m"].as_f64().unwrap();
    assert_eq!(c, 1e-4);
    assert_eq!(
        summary["settings"]["driver_speed_rpm"].as_f64(),
        Some(-2000.0)
    );
    let changes = summary["scene"]["changes"].to_string();
    assert!(changes.contains("clearance.0.clearance_mm") && changes.contains("0.1"));
    let (header, columns) = read_csv(&out.join("wear_snapshots_rod-slider.csv")).unwrap();
    assert_eq!(header, ["angle_deg", "rot1_m", "rot3_m", "rot4_m"]);
    let (_, last) = read_csv(&out.join("wear_rod-slider.csv")).unwrap();
    assert_eq!(columns[0], last[0]);
    assert_eq!(
        columns[3], last[1],
        "the snapshot after 4 of 4 rotations is the final wear"
    );
    for ((a, b), c) in columns[1].iter().zip(&columns[2]).zip(&columns[3]) {
        assert!(a <= b && b <= c, "wear never shrinks");
    }
    assert!(columns[1].iter().any(|&d| d > 0.0));
    let png = fs::read(out.join("wear_evolution.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // The scene's own value without --set: the clearance of the file.
    let plain = dir.join("plain");
    let o = jointwear(&["run", s(&scene), "--rotations", "1", "--out", s(&plain)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = json(&plain.join("summary.json"));
    let c = summary["joints"][0]["radial_clearance_m"].as_f64().unwrap();
    assert_eq!(c, 2e-5);
    assert_eq!(summary["counts"]["rotations_simulated"], 1);
    // --rotations shorter than the scene's snapshots drops those past it, and says so (only
    // that: a --set run.rotations it overrides is no change of its own to report).
    let std = dir.join("std");
    let o = jointwear(&[
        "run",
        s(&scene_path("standard")),
        "--rotations",
        "3",
        "--set",
        "run.record_rotations=1",
        "--set",
        "run.rotations=5",
        "--out",
        s(&std),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("run.wear_snapshots = []"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("sets run.rotations"), "{}", stderr(&o));
    assert_eq!(json(&std.join("summary.json"))["settings"]["rotations"], 3);
    assert!(!std.join("wear_snapshots_rod-slider.csv").exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// A bad `--set` is bad input: exit code 2, the key, the value and the range named, nothing
/// written. Would fail if the value were applied without validation.
#[test]
fn run_bad_set_exits_2_naming_the_field() {
    let dir = temp_dir("badset");
    let scene = short_standard(&dir, 1);
    let out = dir.join("out");
    for (set, needles) in [
        (
            "clearance.0.contact.restitution=1.5",
            &["clearance[0].contact.restitution", "1.5", "[0.1, 1]"][..],
        ),
        ("clearance.0.clearance_mm=-1", &["clearance_mm", "-1"][..]),
        // The hybrid K is derived for n = 1.5: n = 2 penetrated 102 µm with exit 0.
        (
            "clearance.0.contact.exponent=2",
            &["clearance[0].contact.exponent", ": 2 ", "expected 1.5"][..],
        ),
        ("clearance.0.nope=1", &["nope", "clearance.0.nope=1"][..]),
        ("driver.nope.x=1", &["driver.nope.x", "speed_rpm"][..]),
        ("clearance.0.clearance_mm=abc", &["abc", "clearance_mm"][..]),
        ("clearance.0.clearance_mm=0.1,0.2", &["one value"][..]),
        ("run.rotations", &["KEY=VALUE"][..]),
        (
            "run.step_control=pi4",
            &["run.step_control", "pi4", "`i` or `pi42`"][..],
        ),
    ] {
        let o = jointwear(&["run", s(&scene), "--set", set, "--out", s(&out)]);
        assert_eq!(o.status.code(), Some(2), "{set}: {}", stderr(&o));
        let err = stderr(&o);
        for n in needles {
            assert!(err.contains(n), "{set}: lacks {n}: {err}");
        }
        assert!(!out.exists(), "{set}: bad input wrote outputs");
    }
    let o = jointwear(&["run", s(&scene), "--rotations", "0", "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("run.rotations") && stderr(&o).contains("--rotations 0"));
    fs::remove_dir_all(&dir).unwrap();
}

/// `run.step_control` chooses the integrator's step-size controller: the standard scene names
/// `pi42` (the same counts as setting it again), `i` takes another step sequence, a scene
/// without the key runs `i`, and summary.json names it. Failed before it was a run setting (an
/// unknown key, exit code 2), and without its name in summary.json.
#[test]
fn step_control_is_a_run_setting() {
    let dir = temp_dir("stepcontrol");
    let scene = short_standard(&dir, 1);
    let counts = |set: Option<&str>| {
        let out = dir.join(set.unwrap_or("default").replace(['.', '='], "_"));
        let mut args = vec!["run", s(&scene), "--set", "run.record_rotations=0"];
        args.extend(set.iter().flat_map(|v| ["--set", v]));
        args.extend(["--out", s(&out)]);
        let o = jointwear(&args);
        assert!(o.status.success(), "{set:?}: {}", stderr(&o));
        let summary = json(&out.join("summary.json"));
        let control = summary["settings"]["step_control"].clone();
        (summary["counts"].clone(), control)
    };
    let (default, control) = counts(None);
    // summary.json names the controller its counts came from
    assert_eq!(control, "pi42");
    assert!(
        default["rhs_evaluations"].as_u64().unwrap() > 0,
        "{default}"
    );
    assert_eq!(
        counts(Some("run.step_control=pi42")),
        (default.clone(), control)
    );
    let (i, control) = counts(Some("run.step_control=i"));
    assert_eq!(control, "i");
    assert_ne!(i["rhs_evaluations"], default["rhs_evaluations"], "{i}");
    // the four-bar's scene has no key: the I controller, the same counts as naming it
    let fourbar_scene = scene_path("fourbar");
    let fourbar = |set: &str| {
        let out = dir.join(format!("fourbar-{}", set.replace(['.', '='], "_")));
        let mut args = vec!["run", s(&fourbar_scene), "--rotations", "1"];
        args.extend(["--set", "run.record_rotations=0", "--set", set]);
        args.extend(["--out", s(&out)]);
        let o = jointwear(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let summary = json(&out.join("summary.json"));
        (
            summary["counts"].clone(),
            summary["settings"]["step_control"].clone(),
        )
    };
    let own = fourbar("run.rotations=1");
    assert_eq!(own.1, "i");
    assert_eq!(own, fourbar("run.step_control=i"));
    // rk4's fixed step has no controller: a filter would be named in summary.json and steer
    // nothing (accepted before, exit 0)
    let out = dir.join("rk4");
    let o = jointwear(&[
        "run",
        s(&scene),
        "--set",
        "run.method=rk4",
        "--set",
        "run.fixed_step_s=1e-5",
        "--set",
        "run.step_control=pi42",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("run.step_control") && stderr(&o).contains("rk4"));
    assert!(
        stderr(&o).contains("set run.step_control = \"i\" as well"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// Nothing recorded (`record_rotations = 0`): the summary says so instead of printing NaN,
/// summary.json has null, and timeseries.csv has its whole header over no rows. Failed before
/// the fix ("max normal force NaN N").
#[test]
fn run_without_recording_prints_no_nan() {
    let dir = temp_dir("norecord");
    let scene = short_standard(&dir, 1);
    let out = dir.join("out");
    let o = jointwear(&[
        "run",
        s(&scene),
        "--set",
        "run.record_rotations=0",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(!text.to_lowercase().contains("nan"), "{text}");
    assert!(
        text.contains("max normal force and penetration not recorded"),
        "{text}"
    );
    let summary = json(&out.join("summary.json"));
    let joint = &summary["joints"][0];
    assert!(joint["max_normal_force_recorded_n"].is_null());
    assert!(joint["max_penetration_recorded_m"].is_null());
    assert!(joint["motion"].is_null());
    assert!(joint["max_penetration_whole_run_m"].as_f64().unwrap() > 0.0);
    let (header, columns) = read_csv(&out.join("timeseries.csv")).unwrap();
    assert!(header.iter().any(|h| h == "rod-slider.contact_angle_deg"));
    assert!(header.iter().any(|h| h == "slider.alpha_rad_s2"));
    assert!(columns.iter().all(Vec::is_empty));
    fs::remove_dir_all(&dir).unwrap();
}

/// A slider-crank whose 40 mm rod cannot reach the slider's axis past 53.1 deg of crank
/// angle is refused before it simulates by every command that simulates, exit 2 naming the
/// lock as `check` does. Before, `run` simulated into the lock and failed there with exit 1.
#[test]
fn a_linkage_that_locks_is_refused_before_any_command_simulates_it() {
    let dir = temp_dir("locks");
    let standard = short_standard(&dir, 2);
    let text = fs::read_to_string(&standard).unwrap().replace(
        "A = [-60.0, 0.0], B = [60.0, 0.0]",
        "A = [-20.0, 0.0], B = [20.0, 0.0]",
    );
    let scene = dir.join("short_rod.toml");
    fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let (scene, o) = (s(&scene), s(&out));
    for args in [
        &["check", scene, "--out", o][..],
        &["run", scene, "--out", o],
        &["run", scene, "--ensemble", "2", "--out", o],
        &["run", scene, "--member", "3", "--out", o],
        &["animate", scene, "--rotations", "1", "--out", o],
        &["longlife", scene, "--rotations", "1e3", "--out", o],
    ] {
        let run = jointwear(args);
        let err = stderr(&run);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {err}");
        for needle in [
            "`joints (one driver rotation)`",
            "the driver cannot turn from 306.9 to 53.1 deg of driver angle",
            "revolute[1] (crank-rod)",
        ] {
            assert!(err.contains(needle), "{args:?}: lacks {needle}: {err}");
        }
        // A refused ensemble finished no member: it leaves no journal, which made the next
        // command into the folder (--member) refuse it as an unfinished ensemble.
        let journal = out.join("ensemble_journal");
        assert!(!journal.exists(), "{args:?} left {}", journal.display());
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// An ensemble of one member is refused, by `run` and by `sweep`, naming the flag and saying
/// how to run one run: its statistics printed "± 0" and "1 members", and wrote an sd of 0 into
/// its CSV and summary.json, a spread that one value does not have.
#[test]
fn an_ensemble_of_one_member_is_refused() {
    let dir = temp_dir("ensemble-one");
    let scene = short_standard(&dir, 1);
    let out = dir.join("out");
    let run = ["run", s(&scene), "--ensemble", "1", "--out", s(&out)];
    let sweep_file = dir.join("sweep.csv");
    let sweep = [
        "sweep",
        s(&scene),
        "--set",
        "driver.speed_rpm=-600,-2000",
        "--ensemble",
        "1",
        "--out",
        s(&sweep_file),
    ];
    for args in [&run[..], &sweep[..]] {
        let o = jointwear(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stdout(&o));
        let err = stderr(&o);
        for needle in ["`--ensemble`: 1", "[2, 10000]", "--member K"] {
            assert!(err.contains(needle), "{args:?}: lacks {needle}: {err}");
        }
    }
    assert!(!out.exists() && !sweep_file.exists());
    fs::remove_dir_all(&dir).unwrap();
}

/// `run --ensemble` writes README.txt and summary.json too, with `--set` applied.
#[test]
fn ensemble_outputs_are_documented() {
    let dir = temp_dir("ensemble-docs");
    let scene = short_standard(&dir, 1);
    let out = dir.join("out");
    let o = jointwear(&[
        "run",
        s(&scene),
        "--ensemble",
        "2",
        "--set",
        "driver.speed_rpm=1000",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The sd of two members scatters widely: the printout says over how many it is.
    assert!(
        stdout(&o).contains("joint rod-slider (mean ± sd over 2 members, [5 %, 95 %]):"),
        "{}",
        stdout(&o)
    );
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["members"], 2);
    assert!(summary["changes"].to_string().contains("driver.speed_rpm"));
    let quantities = &summary["joints"][0]["quantities"];
    assert_eq!(quantities[0][0], "max_normal_force_recorded_n");
    assert_eq!(quantities[0][1]["n"], 2);
    let readme = fs::read_to_string(out.join("README.txt")).unwrap();
    for needle in [
        "ensemble_members.csv",
        "offset_body_x_m",
        "q95",
        "Bearing frame",
    ] {
        assert!(readme.contains(needle), "README.txt lacks {needle}");
    }
    let (header, rows) =
        jointwear::io::output::read_rows(&out.join("ensemble_summary.csv")).unwrap();
    let mean = header.iter().position(|h| h == "mean").unwrap();
    let n = header.iter().position(|h| h == "n").unwrap();
    for r in &rows {
        // Empty where no member has a value: `settled` of a scene that does not settle.
        if r[n] == "0" {
            assert!(r[mean].is_empty() && r[1] == "settled", "{r:?}");
            continue;
        }
        let x: f64 = r[mean].parse().unwrap();
        assert_eq!(number(x), r[mean]);
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// A `--set` that turns the driver the other way than the scene file (calibrated in its own
/// sense) is noted on stderr, by `run` and by `sweep`; one in the file's sense is not. (Checked
/// to fail with the note's sign test inverted.)
#[test]
fn a_set_that_reverses_the_driver_is_noted() {
    let dir = temp_dir("reverse");
    let scene = short_standard(&dir, 1);
    let note =
        "note: driver.speed_rpm = 600 reverses the driver: the scene turns it at -2000 r/min";
    for (speed, noted) in [("600", true), ("-600", false)] {
        let set = format!("driver.speed_rpm={speed}");
        let out = dir.join(format!("run{speed}"));
        let o = jointwear(&["run", s(&scene), "--set", &set, "--out", s(&out)]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(stderr(&o).contains(note), noted, "{}", stderr(&o));
        assert_eq!(stderr(&o).contains("reverses"), noted, "{}", stderr(&o));
    }
    let out = dir.join("sweep.csv");
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "driver.speed_rpm=-600,600",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stderr(&o).matches("reverses the driver").count(),
        1,
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains(note), "{}", stderr(&o));
    fs::remove_dir_all(&dir).unwrap();
}

/// `longlife --member K --seed S` predicts member K's mechanism, as `tests/longlife.rs` does
/// for its medians: bit for bit the library's prediction from
/// `Perturbation::mechanism(scene, S, K)` with the command's snapshots, and not the scene's own.
#[test]
fn longlife_predicts_one_member_as_the_library_does() {
    use jointwear::io::progress::Silent;
    use jointwear::simulation::ensemble::Perturbation;
    use jointwear::simulation::longlife::{predict, LongLifeSettings};
    let dir = temp_dir("longlife_member");
    let run = |extra: &[&str], out: &Path| {
        let scene = scene_path("standard");
        let args = ["longlife", s(&scene), "--rotations", "80", "--out", s(out)];
        let o = jointwear(&[&args[..], extra].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        json(&out.join("summary.json"))
    };
    let member = run(&["--member", "3", "--seed", "2"], &dir.join("member"));
    let own = run(&[], &dir.join("own"));
    let depth = |summary: &serde_json::Value| summary["joints"][0]["max_wear_depth_m"].clone();
    assert_eq!(member["member"], serde_json::json!([3, 2]));
    assert_eq!(own["member"], serde_json::Value::Null);
    assert_ne!(depth(&member), depth(&own));
    let mut scene = jointwear::scene::SceneFile::read(scene_path("standard"))
        .unwrap()
        .build()
        .unwrap();
    scene.mechanism = Perturbation::default().mechanism(&scene, 2, 3);
    let settings = LongLifeSettings {
        rotations: 80,
        snapshots: vec![16, 32, 48, 64],
        ..LongLifeSettings::default()
    };
    let life = predict(&scene, &settings, &Silent).unwrap();
    let expected = life.snapshots.last().unwrap().max_depth(0);
    assert_eq!(depth(&member).as_f64().unwrap(), expected);
    // a member number beyond any ensemble is bad input
    let o = jointwear(&["longlife", s(&scene_path("standard")), "--member", "10000"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--member"), "{}", stderr(&o));
    fs::remove_dir_all(&dir).unwrap();
}

/// The command line a longlife folder records (manifest and README.txt) makes the same
/// prediction again: every option is in it, and summary.json gives the k/H and depth limit
/// used. Fails without them: `--until 0.0001 --max-change 0.01 --settle 1` stopped at 640
/// rotations while the folder named `… --rotations 10000 --k-over-h 1e-14`, which predicts
/// 10000, and summary.json held no k/H.
#[test]
fn longlife_records_the_command_that_makes_it_again() {
    let dir = temp_dir("longlife_command");
    let scene = scene_path("standard");
    let options = [
        "--rotations",
        "1e4",
        "--k-over-h",
        "1e-14",
        "--until",
        "0.0001",
        "--max-change",
        "0.01",
        "--settle",
        "1",
        "--member",
        "2",
        "--seed",
        "7",
    ];
    let longlife = |args: &[&str], out: &Path| {
        let o = jointwear(&[args, &["--out", s(out)]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
    };
    let first = dir.join("first");
    longlife(&[&["longlife", s(&scene)], &options[..]].concat(), &first);
    let manifest = fs::read_to_string(first.join("jointwear-manifest.txt")).unwrap();
    let command = manifest.lines().next().unwrap().strip_prefix("# ").unwrap();
    let readme = fs::read_to_string(first.join("README.txt")).unwrap();
    assert!(readme.contains(&format!("`{command}`")), "{readme}");
    let words: Vec<&str> = command.split(' ').collect();
    assert_eq!(words[..2], ["jointwear", "longlife"], "{command}");
    let again = dir.join("again");
    longlife(&words[1..], &again);
    let (a, b) = (
        json(&first.join("summary.json")),
        json(&again.join("summary.json")),
    );
    // Stopped at the depth asked for, far short of the rotations.
    assert!(a["rotations_predicted"].as_u64().unwrap() < 1000, "{a}");
    for key in [
        "rotations_predicted",
        "rotations_simulated",
        "member",
        "max_change",
        "settle_rotations",
        "joints",
    ] {
        assert_eq!(a[key], b[key], "{key}: `{command}`");
    }
    assert_eq!(a["k_over_h_per_pa"], 1e-14);
    assert_eq!(a["until_m"], 1e-7);
    assert_eq!(a["joints"][0]["k_over_h_per_pa"], 1e-14);
    assert_eq!(a["joints"][0]["wear_limit_m"], 1e-7);
    for key in ["k_over_h_per_pa", "until_m"] {
        assert!(readme.contains(key), "README.txt lacks {key}");
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// A number a person gave is echoed in the project's format: `longlife --rotations 1e300`
/// printed it with its 301 digits.
#[test]
fn a_huge_rotation_count_is_echoed_as_written() {
    let o = jointwear(&[
        "longlife",
        s(&scene_path("standard")),
        "--rotations",
        "1e300",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`--rotations`: 1e300 (") && !err.contains("0000000"),
        "{err}"
    );
}

/// Disc and axis offsets at or above a joint's clearance are refused before any member runs
/// (exit 2 naming --perturbation). Before, `--member 0 --perturbation disc_1000000nm` (1 mm
/// against 0.02 mm) started the journal pressed into its bearing and failed while running
/// (exit 1), blaming a material.
#[test]
fn offsets_beyond_the_clearance_are_refused_naming_the_perturbation() {
    let dir = temp_dir("offsets");
    let scene = short_standard(&dir, 1);
    let out = s(&dir.join("out")).to_string();
    for args in [
        vec!["--member", "0", "--perturbation", "disc_1000000nm"],
        vec!["--ensemble", "2", "--perturbation", "axis_20000nm"],
    ] {
        let mut all = vec!["run", s(&scene), "--out", &out];
        all.extend(args);
        let o = jointwear(&all);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("`--perturbation`") && err.contains("`rod-slider`: 20000 nm"),
            "{err}"
        );
    }
    // Member 0 under protocol `key`.
    let member = |key: &str| {
        jointwear(&[
            "run",
            s(&scene),
            "--out",
            &out,
            "--member",
            "0",
            "--perturbation",
            key,
        ])
    };
    // A velocity in m/s typed as µm/s: 1000 m/s failed while running, blamed on a speed or
    // load, and 10²⁴ m/s on dependent joints.
    for key in [
        "velocity_1000000000um_s",
        "velocity_1000000000000000000000000000000um_s",
    ] {
        let o = member(key);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("`--perturbation`") && err.contains("at most 1000000 µm/s"),
            "{err}"
        );
    }
    // Just inside the clearance, the member runs.
    let o = member("disc_19999nm");
    assert!(o.status.success(), "{}", stderr(&o));
    // The default's 10 nm is taken at any clearance, zero included (refused at first, with
    // advice about units for a protocol nobody had given); into a folder of its own, as the
    // member's outputs are not an ensemble's to replace.
    let o = jointwear(&[
        "run",
        s(&scene),
        "--out",
        s(&dir.join("ensemble")),
        "--ensemble",
        "2",
        "--set",
        "clearance.0.clearance_mm=0",
        "--set",
        "clearance.0.wear.pressure=\"elastic-foundation\"",
        "--set",
        "clearance.0.wear.k_over_h_per_pa=0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    fs::remove_dir_all(&dir).unwrap();
}

/// Fails on the code before: `run --ensemble` wrote its outputs beside a plain run's
/// unfinished checkpoint (exit 0; a later --resume would have replaced them), and `animate`,
/// which records every rotation, skipped the record budget and aborted on a failed allocation.
#[test]
fn an_ensemble_and_an_animation_refuse_what_a_run_refuses() {
    let dir = temp_dir("ensemble-animate");
    let scene = short_standard(&dir, 1);
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    fs::write(out.join("checkpoint.json"), "{}").unwrap();
    let o = jointwear(&["run", s(&scene), "--ensemble", "2", "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("there is one at"), "{}", stderr(&o));
    assert!(!out.join("summary.json").exists());
    let dense = dir.join("dense.toml");
    let text = fs::read_to_string(&scene).unwrap();
    let text = text.replace("record_interval_s = 1e-5", "record_interval_s = 1e-8");
    assert!(text.contains("record_interval_s = 1e-8"), "{text}");
    fs::write(&dense, text).unwrap();
    let o = jointwear(&["animate", s(&dense), "--rotations", "4", "--out", s(&dir)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("`run.record_interval_s`: 1e-8 s"),
        "{}",
        stderr(&o)
    );
    fs::remove_dir_all(&dir).unwrap();
}

/// Fails on the code before: a settling run that reached `steady_state.max_rotations` with its
/// orbit still changing was printed as "3 settling + 3 rotations" like a settled one, and the
/// motion's figures did not say they cover the recorded rotations only.
#[test]
fn a_run_that_did_not_settle_says_so_and_the_motion_names_its_window() {
    let dir = temp_dir("unsettled");
    let scene = short_standard(&dir, 3);
    let capped = [
        "--set",
        "run.settle=true",
        "--set",
        "run.steady_state.orbit_tolerance=1e-9",
        "--set",
        "run.steady_state.max_rotations=3",
    ];
    let out = dir.join("run");
    let o = jointwear(&[&["run", s(&scene), "--out", s(&out)], &capped[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("not settled: after 3 settling rotations"),
        "{text}"
    );
    assert!(
        text.contains("contact onsets per rotation; recorded rotations, samples every"),
        "{text}"
    );
    // A single run says that it is one draw of a chaotic system; an ensemble gives the spread.
    assert!(
        text.contains("one trajectory of a chaotic system: its numbers are one draw"),
        "{text}"
    );
    let out = dir.join("ensemble");
    let args = ["run", s(&scene), "--ensemble", "2", "--out", s(&out)];
    let o = jointwear(&[&args[..], &capped[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("not settled: 2 of 2 members"), "{text}");
    assert!(
        !text.contains("one trajectory of a chaotic system"),
        "{text}"
    );
    assert!(
        text.contains("contact onsets per rotation (recorded)"),
        "{text}"
    );
    assert!(
        text.contains("recorded rotations: the last 1, samples every"),
        "{text}"
    );
    fs::remove_dir_all(&dir).unwrap();
}

/// The column `settled` of a member's and a sweep case's row; `None` when it is missing.
fn settled_column(path: &Path) -> Option<Vec<String>> {
    let (header, rows) = jointwear::io::output::read_rows(path).unwrap();
    let i = header.iter().position(|h| h == "rod-slider.settled")?;
    Some(rows.iter().map(|r| r[i].clone()).collect())
}

/// Fails on the code before: the members' rows had no `settled` column, and a member that
/// stopped at `steady_state.max_rotations` unsettled had the same `rotations_simulated` as one
/// that settled in its last allowed rotation (seen: 8 and 8 at `max_rotations = 6`).
#[test]
fn member_and_sweep_rows_say_whether_the_run_settled() {
    let dir = temp_dir("settled-column");
    let scene = short_standard(&dir, 2);
    let settle = |tolerance: &str| {
        [
            "--set".to_string(),
            "run.settle=true".to_string(),
            "--set".to_string(),
            format!("run.steady_state.orbit_tolerance={tolerance}"),
            "--set".to_string(),
            "run.steady_state.max_rotations=3".to_string(),
        ]
    };
    let ensemble = |name: &str, extra: &[String]| {
        let out = dir.join(name);
        let args = ["run", s(&scene), "--ensemble", "2", "--out", s(&out)];
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let o = jointwear(&[&args[..], &extra[..]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        settled_column(&out.join("ensemble_members.csv"))
    };
    // An orbit that must not change by more than 1e-9 clearances cannot settle in 3 rotations;
    // one allowed to change by a whole clearance settles after its first.
    assert_eq!(
        ensemble("capped", &settle("1e-9")),
        Some(vec!["false".into(); 2])
    );
    assert_eq!(
        ensemble("loose", &settle("1")),
        Some(vec!["true".into(); 2])
    );
    assert_eq!(ensemble("plain", &[]), Some(vec![String::new(); 2]));
    let summary = fs::read_to_string(dir.join("capped/ensemble_summary.csv")).unwrap();
    assert!(
        summary
            .lines()
            .any(|l| l.starts_with("rod-slider,settled,2,0,")),
        "{summary}"
    );
    let file = dir.join("sweep.csv");
    let mut args = vec!["sweep", s(&scene), "--out", s(&file), "--set"];
    args.push("run.steady_state.orbit_tolerance=1e-9,1");
    let extra = [
        "--set",
        "run.settle=true",
        "--set",
        "run.steady_state.max_rotations=3",
    ];
    let o = jointwear(&[&args[..], &extra[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        settled_column(&file),
        Some(vec!["false".into(), "true".into()])
    );
    fs::remove_dir_all(&dir).unwrap();
}

/// A sweep needs recorded rotations (it refuses `run.record_rotations = 0`), so its refusal of
/// a coarse recording grid must not advise recording none (it did).
#[test]
fn a_sweeps_coarse_recording_grid_is_refused_without_advising_no_recording() {
    let dir = temp_dir("sweep-grid");
    let scene = short_standard(&dir, 1);
    let file = dir.join("sweep.csv");
    let o = jointwear(&[
        "sweep",
        s(&scene),
        "--out",
        s(&file),
        "--set",
        "run.record_rotations=1",
        "--set",
        "run.record_interval_s=1e-3",
        "--set",
        "driver.speed_rpm=-2000,-1000",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`run.record_interval_s")
            && err.contains("needs recorded rotations: recording none is no remedy")
            && !err.contains("record no rotations"),
        "{err}"
    );
    fs::remove_dir_all(&dir).unwrap();
}

// Fails without the quoting: the recorded `… --set title="it's mine"` typed into a shell lost
// its TOML quotes and with them the fingerprint of the changes (or did not parse at all), and
// the scene's path `… a b/short.toml` split into two words.
#[test]
fn the_recorded_command_reruns_the_run_in_a_shell() {
    use jointwear::scene::variant::shell_word;
    let dir = temp_dir("shell").join("a b");
    fs::create_dir_all(&dir).unwrap();
    let scene = short_standard(&dir, 1);
    let first = dir.join("first");
    let title = r#"title="it's mine""#;
    let snapshots = "run.wear_snapshots=[1]";
    let o = jointwear(&[
        "run",
        s(&scene),
        "--set",
        title,
        "--set",
        snapshots,
        "--out",
        s(&first),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let readme = fs::read_to_string(first.join("README.txt")).unwrap();
    let command = readme.split('`').nth(1).unwrap();
    let program = shell_word(env!("CARGO_BIN_EXE_jointwear"));
    let again = dir.join("again");
    let line = format!(
        "{} --out {}",
        command.replacen("jointwear", &program, 1),
        shell_word(s(&again))
    );
    let o = Command::new("sh").args(["-c", &line]).output().unwrap();
    assert!(o.status.success(), "{line}: {}", stderr(&o));
    let scene_of = |d: &Path| {
        let text = fs::read_to_string(d.join("summary.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["scene"].clone()
    };
    assert_eq!(scene_of(&again), scene_of(&first));
    for file in ["wear_rod-slider.csv", "timeseries.csv"] {
        assert_eq!(
            fs::read(again.join(file)).unwrap(),
            fs::read(first.join(file)).unwrap()
        );
    }
}

// Fails without naming the part: a key that is not in the scene read "invalid value for
// `nope.x (with --set nope.x=1)`: (at `nope`)", as if the value were wrong.
#[test]
fn a_set_key_outside_the_scene_names_the_part_that_is_not_there() {
    let (scene, out) = (scene_path("standard"), temp_dir("set-key").join("out"));
    for (set, needle) in [
        (
            "nope.x=1",
            "`nope` is no key there (expected one of the keys bodies,",
        ),
        (
            "clearance.3.clearance_mm=0.1",
            "`3` is no element there (expected an array index in [0, 1))",
        ),
        (
            "title.x=1",
            "`x` follows a value (expected a table or an array before it)",
        ),
    ] {
        let o = jointwear(&["run", s(&scene), "--set", set, "--out", s(&out)]);
        assert_eq!(o.status.code(), Some(2), "{set}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{set}: {}", stderr(&o));
    }
    assert!(!out.exists(), "refused before any output");
}

// Fails without the claim: `check … --out figures`, as the README runs it, redrew
// figures/mechanism_standard.png while a paper program held the outputs, and a sweep's `--out`
// in data/ could replace a paper program's CSV or be replaced by it, each exit 0. (Under a
// temporary output root: the checkout's lock, held here, refused a paper program or another
// test run meanwhile.)
#[test]
fn a_command_writing_among_the_paper_outputs_waits_for_no_paper_program() {
    let root = temp_dir("paper-outputs");
    fs::create_dir_all(root.join("figures")).unwrap();
    fs::create_dir_all(root.join("data")).unwrap();
    // This test's process holds the outputs, as a paper program would.
    let host = fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let held = format!(
        "pid={}\nhost={}\ncommand=fig06\n",
        std::process::id(),
        host.trim()
    );
    fs::write(root.join(".paper-outputs.lock"), held).unwrap();
    let jointwear = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_jointwear"))
            .env("JOINTWEAR_OUTPUT_ROOT", &root)
            .args(args)
            .output()
            .unwrap()
    };
    let scene = scene_path("standard");
    let check = jointwear(&["check", s(&scene), "--out", s(&root.join("figures"))]);
    // (A path into data/ by another way is data/ all the same.)
    let csv = root.join("data/../data/sweep-test.csv");
    let sweep = jointwear(&[
        "sweep",
        s(&scene),
        "--set",
        "run.rtol=1e-6",
        "--out",
        s(&csv),
    ]);
    for o in [&check, &sweep] {
        let err = stderr(o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("`--out`") && err.contains("paper.md") && err.contains("`fig06`"),
            "{err}"
        );
    }
    let written: Vec<_> = ["figures", "data"]
        .iter()
        .flat_map(|d| fs::read_dir(root.join(d)).unwrap())
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(written, Vec::<PathBuf>::new(), "written among the outputs");
    fs::remove_dir_all(&root).unwrap();
}
