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
            msg.contains("clearance[0].contact.restitution") && msg.contains("(0, 1]"),
            "{msg}"
        );
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
    let msg = error_of(&replaced("body = \"crank\"", "body = \"slider\""));
    assert!(
        msg.contains("translational[0]") && msg.contains("already fixed by the others"),
        "{msg}"
    );
}
