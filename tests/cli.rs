//! The `jointwear` program end to end: outputs, exit codes, error messages, sweeps and shards.

use jointwear::io::output::read_csv;
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
        "wear peak",
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
    let o = jointwear(&["check", s(&scene_path("fourbar"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "coupler-rocker",
        "rocker",
        "driver: crank at 1000 r/min",
        "degrees of freedom: 2",
        "20 rotations",
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
            && err.contains("(0e0, 1e0]"),
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
        let mut r = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_path(p)
            .unwrap();
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
        // identical cases up to the wall time
        let strip = |r: &[String]| {
            let mut r = r.to_vec();
            let n = r.len();
            r.remove(n - 2);
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
    let o = jointwear(&[
        "longlife",
        s(&scene_path("standard")),
        "--rotations",
        "2e5",
        "--k-over-h",
        "1e-15",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("200000 rotations predicted"));
    let (header, columns) = read_csv(&out.join("longlife_growth.csv")).unwrap();
    assert_eq!(
        header,
        [
            "rotations",
            "rod-slider.max_depth_m",
            "rod-slider.clearance_m"
        ]
    );
    assert_eq!(*columns[0].last().unwrap(), 2e5);
    let (header, _) = read_csv(&out.join("longlife_profiles_rod-slider.csv")).unwrap();
    assert_eq!(
        header,
        [
            "angle_deg",
            "rot40000_m",
            "rot80000_m",
            "rot120000_m",
            "rot160000_m",
            "rot200000_m"
        ]
    );
    for png in ["longlife_growth.png", "longlife_profiles.png"] {
        assert!(out.join(png).exists(), "{png}");
    }
    fs::remove_dir_all(&dir).unwrap();
}
