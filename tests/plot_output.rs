//! Figures and CSV outputs: valid PNGs of the right size, atomic writes, CSV round trip.

use std::f64::consts::PI;
use std::fs;
use std::path::{Path, PathBuf};

use jointwear::io::output::{read_csv, write_atomic, write_csv};
use jointwear::io::plot::{render, render_column, render_polar, Axes, Series, Style};
use jointwear::Error;

/// A fresh, empty directory per test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("jointwear-test-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Asserts a PNG signature, a non-trivial size and the given pixel dimensions.
fn assert_png(path: &Path, width: u32, height: u32) {
    let bytes = fs::read(path).unwrap();
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert!(
        bytes.len() > 10_000,
        "{} is suspiciously small",
        path.display()
    );
    let dim = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!((dim(16), dim(20)), (width, height));
}

/// Only `expected` (no hidden temporary files) is left in `dir`.
fn assert_only(dir: &Path, expected: &[&str]) {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, expected);
}

fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
        .collect()
}

#[test]
fn one_panel_with_gaps_and_points() {
    let dir = temp_dir("one");
    let t = linspace(0.0, 0.12, 400);
    let mut y1: Vec<f64> = t
        .iter()
        .map(|t| 0.3 * (2.0 * PI * 25.0 * t).sin())
        .collect();
    y1[100] = f64::NAN; // breaks the line, must not crash
    y1[101] = f64::INFINITY;
    let y2: Vec<f64> = t
        .iter()
        .map(|t| 0.25 * (2.0 * PI * 25.0 * t).cos())
        .collect();
    let (tp, yp): (Vec<f64>, Vec<f64>) = t
        .iter()
        .zip(&y2)
        .step_by(20)
        .map(|(a, b)| (*a, b + 0.02))
        .unzip();
    let axes = Axes::new(
        "Slider velocity",
        "time (s)",
        "velocity (m/s)",
        vec![
            Series::new("clearance joint", &t, &y1, Style::Line),
            Series::new("ideal joint", &t, &y2, Style::Reference),
            Series::new("measured", &tp, &yp, Style::Points),
        ],
    );
    let path = dir.join("one.png");
    render(&path, &[axes]).unwrap();
    assert_png(&path, 1200, 800);
    assert_only(&dir, &["one.png"]);
}

#[test]
fn two_panels_with_secondary_axis() {
    let dir = temp_dir("two");
    let angle = linspace(0.0, 720.0, 721);
    let accel: Vec<f64> = angle
        .iter()
        .map(|a| 180.0 * a.to_radians().cos() + 40.0 * (3.0 * a.to_radians()).sin())
        .collect();
    let rate: Vec<f64> = angle
        .iter()
        .map(|a| 2.5e-9 * (1.0 + a.to_radians().sin()).powi(2))
        .collect();
    let depth: Vec<f64> = angle.iter().map(|a| 3.2e-6 * a / 720.0).collect();
    let left = Axes {
        y2_label: Some("wear rate (m/s)".into()),
        ..Axes::new(
            "Acceleration and wear rate",
            "crank angle (deg)",
            "slider acceleration (m/s²)",
            vec![
                Series::new("acceleration", &angle, &accel, Style::Line),
                Series::new("wear rate", &angle, &rate, Style::LineOnSecondaryAxis),
            ],
        )
    };
    let right = Axes::new(
        "Maximum wear depth",
        "crank angle (deg)",
        "wear depth (m)",
        vec![Series::new("wear depth", &angle, &depth, Style::Line)],
    );
    let path = dir.join("two.png");
    render(&path, &[left, right]).unwrap();
    assert_png(&path, 2400, 800);
}

#[test]
fn trajectory_with_clearance_circle() {
    let dir = temp_dir("trajectory");
    let c = 0.25; // radial clearance, mm
    let s = linspace(0.0, 6.0 * PI, 3000);
    let x: Vec<f64> = s
        .iter()
        .map(|s| c * (0.97 * s.cos() + 0.02 * (7.0 * s).sin()))
        .collect();
    let y: Vec<f64> = s
        .iter()
        .map(|s| c * (0.6 * s.sin() + 0.35 * (2.0 * s).sin()))
        .collect();
    let axes = Axes {
        equal_aspect: true,
        circles: vec![(0.0, 0.0, c)],
        ..Axes::new(
            "Journal centre trajectory",
            "x (mm)",
            "y (mm)",
            vec![Series::new("journal centre", &x, &y, Style::Line)],
        )
    };
    let path = dir.join("trajectory.png");
    render(&path, &[axes]).unwrap();
    assert_png(&path, 1200, 800);
}

#[test]
fn four_panels_as_two_by_two() {
    let dir = temp_dir("four");
    let x = linspace(0.0, 1.0, 50);
    let ys: Vec<Vec<f64>> = (1..=4)
        .map(|k| x.iter().map(|x| x.powi(k) * 1e4).collect())
        .collect();
    let panels: Vec<Axes> = ys
        .iter()
        .enumerate()
        .map(|(k, y)| {
            Axes::new(
                format!("x^{}", k + 1),
                "x (-)",
                "force (N)",
                vec![Series::new("f", &x, y, Style::Line)],
            )
        })
        .collect();
    let path = dir.join("four.png");
    render(&path, &panels).unwrap();
    assert_png(&path, 2400, 1600);
}

#[test]
fn polar_profile() {
    let dir = temp_dir("polar");
    let theta = linspace(0.0, 359.0, 360);
    let r_ref = 10.0; // mm
    let worn = |depth: f64, centre: f64| -> Vec<f64> {
        theta
            .iter()
            .map(|t| r_ref + depth * (-((t - centre) / 25.0).powi(2)).exp())
            .collect()
    };
    let profiles = vec![
        (
            "after 10 cycles".to_owned(),
            worn(0.004, 250.0),
            Style::Line,
        ),
        (
            "after 20 cycles".to_owned(),
            worn(0.008, 250.0),
            Style::Dashed,
        ),
    ];
    let path = dir.join("polar.png");
    let scale = [(0.004, "4 µm".to_owned()), (0.008, "8 µm".to_owned())];
    render_polar(
        &path,
        "Bearing profile",
        &theta,
        &profiles,
        (r_ref, 200.0),
        &scale,
    )
    .unwrap();
    assert_png(&path, 1200, 800);
    // a column of three panels is one panel wide
    let x = [0.0, 1.0, 2.0];
    let panel = |t: &str| Axes::new(t, "x", "y", vec![Series::new("a", &x, &x, Style::Line)]);
    let path = dir.join("column.png");
    render_column(&path, &[panel("a"), panel("b"), panel("c")]).unwrap();
    assert_png(&path, 1200, 2400);
}

#[test]
fn bad_input_is_an_error_and_writes_nothing() {
    let dir = temp_dir("bad");
    let path = dir.join("bad.png");
    let plot_err =
        |r: jointwear::Result<()>| assert!(matches!(r, Err(Error::Plot { .. })), "{r:?}");

    plot_err(render(&path, &[Axes::new("empty", "x", "y", vec![])]));
    plot_err(render(&path, &[]));
    let nan = [f64::NAN; 4];
    let x = [0.0, 1.0, 2.0, 3.0];
    plot_err(render(
        &path,
        &[Axes::new(
            "nan",
            "x",
            "y",
            vec![Series::new("a", &x, &nan, Style::Line)],
        )],
    ));
    plot_err(render(
        &path,
        &[Axes::new(
            "len",
            "x",
            "y",
            vec![Series::new("a", &x, &x[..3], Style::Line)],
        )],
    ));
    plot_err(render(
        &path,
        &[Axes::new(
            "y2",
            "x",
            "y",
            vec![Series::new("a", &x, &x, Style::LineOnSecondaryAxis)],
        )],
    ));
    let band = Axes {
        shades: vec![jointwear::io::plot::Shade {
            series: 0,
            lo: &x[..3],
            hi: &x,
        }],
        ..Axes::new(
            "band",
            "x",
            "y",
            vec![Series::new("a", &x, &x, Style::Line)],
        )
    };
    plot_err(render(&path, &[band]));
    plot_err(render_polar(
        &path,
        "p",
        &x,
        &[("a".into(), vec![1.0; 3], Style::Line)],
        (1.0, 10.0),
        &[],
    ));
    assert_only(&dir, &[]);
}

#[test]
fn failed_write_leaves_neither_target_nor_temporary() {
    let dir = temp_dir("atomic");
    let target = dir.join("sub").join("out.csv");
    let result = write_atomic(&target, |tmp| {
        fs::write(tmp, "half written").unwrap();
        Err(Error::Plot {
            path: tmp.to_path_buf(),
            message: "simulated failure".into(),
        })
    });
    assert!(result.is_err());
    assert_only(&dir.join("sub"), &[]);

    // A successful write replaces an existing target.
    fs::write(&target, "old").unwrap();
    write_atomic(&target, |tmp| {
        fs::write(tmp, "new").map_err(|e| Error::Io {
            path: tmp.into(),
            source: e,
        })
    })
    .unwrap();
    assert_eq!(fs::read_to_string(&target).unwrap(), "new");
    assert_only(&dir.join("sub"), &["out.csv"]);
}

#[test]
fn csv_round_trip_is_exact() {
    let dir = temp_dir("csv");
    let path = dir.join("table.csv");
    let t = [0.0, 1.0 / 3.0, 1e-300, -2.5e7];
    let w = [f64::NAN, f64::INFINITY, -0.0, 1.234_567_890_123_456_7e-9];
    write_csv(&path, &["t (s)", "wear depth (m)"], &[&t, &w]).unwrap();
    let (header, columns) = read_csv(&path).unwrap();
    assert_eq!(header, ["t (s)", "wear depth (m)"]);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&columns[0]), bits(&t));
    assert!(columns[1][0].is_nan());
    assert_eq!(bits(&columns[1][1..]), bits(&w[1..]));
    assert_only(&dir, &["table.csv"]);
}

#[test]
fn csv_rejects_mismatched_columns() {
    let dir = temp_dir("csv-bad");
    let path = dir.join("bad.csv");
    let r = write_csv(&path, &["a", "b"], &[&[1.0, 2.0], &[1.0]]);
    assert!(matches!(r, Err(Error::Invalid { .. })), "{r:?}");
    let r = write_csv(&path, &["a"], &[&[1.0], &[1.0]]);
    assert!(matches!(r, Err(Error::Invalid { .. })), "{r:?}");
    assert_only(&dir, &[]);
}
