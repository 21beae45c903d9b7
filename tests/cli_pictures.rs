//! Pictures of the mechanism: `jointwear check` draws the assembled pose as a PNG and names
//! its branch, `jointwear animate` writes a looping GIF of several frames, and bad options of
//! `animate` are bad input.

mod common;

use common::{assert_fails, file_names, jointwear, s, scene_with, stderr, stdout, temp_dir};
use jointwear::scene::scene_path;
use std::fs;
use std::path::Path;

/// The PNG signature and the width and height of its IHDR chunk (bytes 16-23, big-endian).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = fs::read(path).unwrap();
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is no PNG",
        path.display()
    );
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn check_draws_the_assembled_pose_on_the_guessed_branch() {
    let dir = temp_dir("pictures", "check");
    let o = jointwear(&["check", s(&scene_path("fourbar")), "--out", s(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = dir.join("mechanism_fourbar.png");
    let text = stdout(&o);
    assert!(
        text.contains(&format!("drew {}: ", png.display()))
            && text.contains("assembled on the guessed branch"),
        "{text}"
    );
    assert_eq!(png_size(&png), (1200, 800));
    assert_eq!(file_names(&dir), ["mechanism_fourbar.png"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn check_names_another_branch_in_the_picture() {
    let dir = temp_dir("pictures", "branch");
    let scene = dir.join("far.toml");
    // the rocker guessed 100 deg off: the loop closes elbow down
    let far = ("angle_deg = 100.0", "angle_deg = 200.0");
    fs::write(&scene, scene_with("fourbar", &[far])).unwrap();
    let o = jointwear(&["check", s(&scene), "--out", s(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let drew = text.lines().find(|l| l.starts_with("drew ")).unwrap_or("");
    let needle = "coupler assembled 100°, rocker 60° from their guesses: other branch";
    assert!(drew.contains(needle), "lacks `{needle}`: {text}");
    assert_eq!(png_size(&dir.join("mechanism_far.png")), (1200, 800));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn animate_writes_a_looping_gif_of_several_frames() {
    let dir = temp_dir("pictures", "animate");
    let args = ["--out", s(&dir), "--frames", "6"];
    let o = jointwear(&[&["animate", s(&scene_path("fourbar"))], &args[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let gif = dir.join("mechanism_fourbar.gif");
    assert!(stdout(&o).contains(&format!("wrote {} (6 frames", gif.display())));
    assert_eq!(file_names(&dir), ["mechanism_fourbar.gif"]);
    let bytes = fs::read(&gif).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options.read_info(bytes.as_slice()).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (1200, 800));
    let mut frames = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        frames.push(frame.buffer.to_vec());
    }
    assert_eq!(frames.len(), 6);
    // the mechanism moves: no two successive frames are alike
    assert!(frames.windows(2).all(|w| w[0] != w[1]));
    fs::remove_dir_all(&dir).unwrap();
}

/// Fails on the code before: the shipped zero-clearance scene simulated, then failed to draw
/// (exit 1, "inset x range (170, 170) must be finite and increasing"): the inset magnified a
/// clearance circle of radius 0. Its journal moves by its penetration, which the inset shows.
#[test]
fn animate_draws_a_joint_without_clearance() {
    let dir = temp_dir("pictures", "zero");
    let scene = scene_path("standard").with_file_name("stability/zero_clearance.toml");
    let o = jointwear(&["animate", s(&scene), "--out", s(&dir), "--frames", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(file_names(&dir), ["mechanism_zero_clearance.gif"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn animate_refuses_bad_options_with_exit_code_2_and_writes_nothing() {
    let dir = temp_dir("pictures", "bad");
    let out = dir.join("out");
    let scene = scene_path("fourbar");
    let cases: [(&[&str], &[&str]); 5] = [
        (
            &["--rotations", "0"],
            &["run.rotations (with --rotations 0)", "[1, 1000000]"],
        ),
        (&["--frames", "1"], &["--frames", "2 to 1000 frames"]),
        (&["--frames", "-3"], &["unexpected argument '-3'"]),
        (&["--nope"], &["--nope"]),
        (&["--rotations", "x"], &["--rotations", "invalid digit"]),
    ];
    for (extra, needles) in cases {
        let args = [&["animate", s(&scene), "--out", s(&out)], extra].concat();
        assert_fails(&jointwear(&args), 2, needles);
    }
    let absent = dir.join("absent.toml");
    let o = jointwear(&["animate", s(&absent), "--out", s(&out)]);
    assert_fails(&o, 2, &["absent.toml", "No such file"]);
    assert!(!out.exists(), "bad input wrote outputs");
    fs::remove_dir_all(&dir).unwrap();
}
