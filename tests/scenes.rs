//! Bad scenes give a clear error naming the field, the value and the valid range.

use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::Scene;
use std::path::Path;

fn standard_text() -> String {
    std::fs::read_to_string(scene_path("standard")).unwrap()
}

/// Parses and builds modified scene text, returning the error message.
fn error_of(text: &str) -> String {
    match SceneFile::parse(text, Path::new("test.toml")).and_then(|f| f.build()) {
        Ok(_) => panic!("scene was accepted"),
        Err(e) => e.to_string(),
    }
}

fn replaced(from: &str, to: &str) -> String {
    let text = standard_text();
    assert!(text.contains(from), "standard scene lacks {from:?}");
    text.replacen(from, to, 1)
}

#[test]
fn shipped_scenes_load() {
    for entry in std::fs::read_dir(scene_path("standard").parent().unwrap()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
    }
}

#[test]
fn missing_field() {
    let msg = error_of(&replaced("mass_kg = 0.30\n", ""));
    assert!(msg.contains("missing field `mass_kg`"), "{msg}");
}

#[test]
fn unknown_key() {
    let msg = error_of(&replaced(
        "mass_kg = 0.30\n",
        "mass_kg = 0.30\ncolour = \"red\"\n",
    ));
    assert!(msg.contains("unknown field `colour`"), "{msg}");
    let msg = error_of(&replaced("mu_s = 0.015", "mu_s = 0.015, mu_x = 1.0"));
    assert!(msg.contains("mu_x"), "{msg}");
}

#[test]
fn negative_radius() {
    let msg = error_of(&replaced(
        "bearing_radius_mm = 10.0",
        "bearing_radius_mm = -10.0",
    ));
    assert!(
        msg.contains("clearance[0].bearing_radius_mm") && msg.contains("-10"),
        "{msg}"
    );
}

#[test]
fn journal_larger_than_bearing() {
    for bad in ["clearance_mm = 12.0", "clearance_mm = -0.01"] {
        let msg = error_of(&replaced("clearance_mm = 0.02", bad));
        assert!(
            msg.contains("clearance[0].clearance_mm") && msg.contains("the journal must fit"),
            "{msg}"
        );
    }
}

#[test]
fn restitution_outside_its_range() {
    for bad in ["restitution = 0.0", "restitution = 1.5"] {
        let msg = error_of(&replaced("restitution = 0.9", bad));
        assert!(
            msg.contains("clearance[0].contact.restitution") && msg.contains("[0.1, 1]"),
            "{msg}"
        );
    }
}

/// The journal radius R − c is at least the bearing radius's own minimum, and c/R at most a
/// tenth. Before, 9.9 mm in a 10 mm bearing passed validation and failed while running (exit
/// 1), and 9999 mm in a 10 m one ran with the linkage disconnected (exit 0).
#[test]
fn clearance_leaves_a_conforming_journal() {
    let scene = |radius: &str, clearance: &str| {
        replaced(
            "bearing_radius_mm = 10.0",
            &format!("bearing_radius_mm = {radius}"),
        )
        .replacen(
            "clearance_mm = 0.02",
            &format!("clearance_mm = {clearance}"),
            1,
        )
        // elastic-foundation pressure: the Hertz bound on small c/R is not the one tested
        .replacen("\"hertz-line\"", "\"elastic-foundation\"", 1)
    };
    for (radius, clearance, needles) in [
        (
            "10.0",
            "9.9",
            &["at most 0.1 x the bearing radius", "1 mm"][..],
        ),
        (
            "10000.0",
            "9999.0",
            &["at most 0.1 x the bearing radius", "1000 mm"][..],
        ),
        (
            "0.1",
            "0.005",
            &["a journal radius", "0.095 mm", "at least 0.1 mm"][..],
        ),
    ] {
        let msg = error_of(&scene(radius, clearance));
        for n in [
            &[
                "clearance[0].clearance_mm",
                "clearance[0].bearing_radius_mm",
            ][..],
            needles,
        ]
        .concat()
        {
            assert!(msg.contains(n), "lacks `{n}`: {msg}");
        }
    }
    // At the bounds: a tenth of the radius (0.14 / 1.4 rounds above 0.1), a 0.1 mm journal
    // (whose R − c rounds below it).
    for (radius, clearance) in [("10.0", "1.0"), ("1.4", "0.14"), ("0.105", "0.005")] {
        let text = scene(radius, clearance);
        let file = SceneFile::parse(&text, Path::new("test.toml")).unwrap();
        file.build().unwrap();
    }
}

/// Values inside the old ranges that failed only while running, with a message blaming
/// something else, are refused at load naming their own field. Before: atol 1e-200 stopped at
/// t = 0 with "step size underflow (h = 0e0)", a grazing floor of 1e-100 m/s and (with a 1/c_e
/// damping law) a restitution of 1e-300 with "penetrates inf mm" blaming the linkage, and a
/// speed of -1e-300 r/min was refused naming `run.record_interval_s`.
#[test]
fn values_that_failed_while_running_are_refused_naming_their_field() {
    let flores = "contact = { stiffness = \"hybrid\", dissipation = \"flores\", \
                  restitution = 1e-300, exponent = 1.5, grazing_velocity_m_s = 1e-3 }";
    let contact = "contact = { model = \"hybrid\", restitution = 0.9, exponent = 1.5, \
                   grazing_velocity_m_s = 1e-3 }";
    for (from, to, field, bound) in [
        ("atol = 2.5e-10", "atol = 1e-200", "run.atol", "[1e-20, 1]"),
        (
            "grazing_velocity_m_s = 1e-3",
            "grazing_velocity_m_s = 1e-100",
            "clearance[0].contact.grazing_velocity_m_s",
            "[1e-9, 10]",
        ),
        (
            contact,
            flores,
            "clearance[0].contact.restitution",
            "[0.1, 1]",
        ),
        (
            "speed_rpm = -2000.0",
            "speed_rpm = -1e-300",
            "driver.speed_rpm",
            "[6e-9, 100000] r/min",
        ),
    ] {
        let msg = error_of(&replaced(from, to));
        for n in [field, bound] {
            assert!(msg.contains(n), "lacks `{n}`: {msg}");
        }
        assert!(!msg.contains("record_interval"), "{msg}");
    }
    // Each bound itself is valid.
    for (from, to) in [
        ("atol = 2.5e-10", "atol = 1e-20"),
        ("grazing_velocity_m_s = 1e-3", "grazing_velocity_m_s = 1e-9"),
        ("restitution = 0.9", "restitution = 0.1"),
    ] {
        let file = SceneFile::parse(&replaced(from, to), Path::new("test.toml")).unwrap();
        file.build().unwrap();
    }
}

/// Values are echoed as written, never in `Display`'s plain digits: before, a k/H of -1e-12
/// showed as -0.000000000001 and 1e300 with 301 digits.
#[test]
fn values_are_echoed_in_the_project_number_format() {
    for (from, to, shown) in [
        (
            "k_over_h_per_pa = 1e-12",
            "k_over_h_per_pa = -1e-12",
            "`: -1e-12 (",
        ),
        ("mu_s = 0.015", "mu_s = 1e300", "`: 1e300 ("),
        ("rtol = ", "rtol = 1e-300 #", "`: 1e-300 ("),
    ] {
        let msg = error_of(&replaced(from, to));
        assert!(msg.contains(shown) && !msg.contains("0000000"), "{msg}");
    }
}

#[test]
fn not_a_number() {
    let msg = error_of(&replaced("mass_kg = 0.30", "mass_kg = nan"));
    assert!(
        msg.contains("bodies[0].mass_kg") && msg.contains("NaN"),
        "{msg}"
    );
    let msg = error_of(&replaced("speed_rpm = -2000.0", "speed_rpm = inf"));
    assert!(msg.contains("driver.speed_rpm"), "{msg}");
}

#[test]
fn unknown_point_and_material() {
    let msg = error_of(&replaced("journal = \"rod.B\"", "journal = \"rod.Z\""));
    assert!(
        msg.contains("clearance[0].journal") && msg.contains("rod.Z"),
        "{msg}"
    );
    let msg = error_of(&replaced(
        "bearing_material = \"steel\"",
        "bearing_material = \"bronze\"",
    ));
    assert!(
        msg.contains("clearance[0].bearing_material") && msg.contains("bronze"),
        "{msg}"
    );
}

/// Fails on the code before: an unused material or ground point was never checked, so an
/// absurd value sat in the scene until an edit used it.
#[test]
fn unused_materials_and_ground_points_are_checked_too() {
    let msg = error_of(&replaced(
        "[materials.steel]",
        "[materials.bronze]\nyoungs_modulus_gpa = -110.0\npoisson_ratio = 0.34\n\n[materials.steel]",
    ));
    assert!(
        msg.contains("materials.bronze.youngs_modulus_gpa") && msg.contains("-110"),
        "{msg}"
    );
    let msg = error_of(&replaced(
        "points_mm = { O = [0.0, 0.0] }",
        "points_mm = { O = [0.0, 0.0], P = [1e9, 0.0] }",
    ));
    assert!(msg.contains("ground.points_mm.P"), "{msg}");
}

#[test]
fn friction_switch_velocities_ordered() {
    let msg = error_of(&replaced("v_d = 1e-3", "v_d = 1e-5"));
    assert!(msg.contains("clearance[0].friction.v_d"), "{msg}");
}

#[test]
fn bad_scene_file_reports_field_and_path() {
    let dir = std::env::temp_dir().join(format!("jointwear-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(&path, replaced("mass_kg = 0.30", "mass_kg = -1.0")).unwrap();
    let err = Scene::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("bodies[0].mass_kg") && err.contains("-1"),
        "{err}"
    );
    let missing = Scene::load(dir.join("absent.toml"))
        .unwrap_err()
        .to_string();
    assert!(missing.contains("absent.toml"), "{missing}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn driver_on_a_locked_angle() {
    // The translational joint already holds the slider's angle: driving it too is redundant.
    // The message named the translational joint alone ("already fixed by the others"); the
    // driver, the change made, goes unnamed.
    let msg = error_of(&replaced("body = \"crank\"", "body = \"slider\""));
    assert!(
        msg.contains("translational[0] (") && msg.contains("already fixed by driver (slider)"),
        "{msg}"
    );
}

/// A joint with both ends on the ground fixes nothing: the message listed no joint ("already
/// fixed by  (expected"). A clearance joint held ideal for the assembly was named as a revolute
/// beyond the scene's (`revolute[3]`).
#[test]
fn a_redundant_joint_is_named_as_the_scene_names_it() {
    let ground = "[[revolute]]\na = \"ground.O\"\nb = \"ground.O\"\n\n[driver]";
    let msg = error_of(&replaced("[driver]", ground));
    assert!(
        msg.contains("revolute[2] (ground-ground) constrains no coordinate"),
        "{msg}"
    );
    let text = replaced(
        "journal = \"rod.B\"\nbearing = \"slider.C\"",
        "journal = \"slider.C\"\nbearing = \"ground.O\"",
    )
    .replacen(
        "[driver]",
        "[[revolute]]\na = \"rod.B\"\nb = \"slider.C\"\n\n[driver]",
        1,
    );
    // (found when the scene is assembled with its clearance joints held ideal)
    let scene = SceneFile::parse(&text, Path::new("test.toml"))
        .and_then(|f| f.build())
        .unwrap();
    let msg = match scene.mechanism.assemble(&scene.guess) {
        Ok(_) => panic!("assembled"),
        Err(e) => e.to_string(),
    };
    assert!(
        msg.contains("already fixed by clearance joint `rod-slider` (slider-ground, held ideal)"),
        "{msg}"
    );
}
