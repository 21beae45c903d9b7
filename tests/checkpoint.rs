//! Checkpoints: a run saved between rotations and continued in another `Simulation` (through
//! the checkpoint file) is bit-identical to one that never stopped, while settling too; the
//! command line resumes from a checkpoint and refuses a missing or foreign one.

mod common;

use common::{assert_same_run, jointwear, temp_dir};
use jointwear::io::output::read_csv;
use jointwear::io::progress::Silent;
use jointwear::scene::variant::fingerprint;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::checkpoint::{read_checkpoint, write_checkpoint, CHECKPOINT_FILE};
use jointwear::simulation::Scene;
use jointwear::simulation::{RunOutput, Simulation};
use std::path::{Path, PathBuf};

/// The chaotic 0.5 mm scene, 5 rotations, the last 2 recorded, snapshots and history on;
/// `more` adds overrides.
fn scene_file(dir: &Path, settle: bool, more: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    let extra = if settle {
        "\"run.settle\" = true\n\"run.steady_state\" = { orbit_tolerance = 1e-9, max_rotations = 3 }\n\"run.rotations\" = 2\n\"run.wear_snapshots\" = []\n"
    } else {
        "\"run.rotations\" = 5\n\"run.wear_snapshots\" = [1, 4]\n\"run.profile_history_per_rotation\" = 6\n"
    };
    let text = format!(
        "extends = {:?}\n[overrides]\n\"run.record_rotations\" = 2\n{extra}{more}",
        scene_path("clearance_0.5mm").display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// [`assert_same_run`], and everything else a run outputs but its wall time.
fn assert_same(a: &RunOutput, b: &RunOutput) {
    assert_same_run(a, b);
    assert_eq!(a.max_penetration_whole_run, b.max_penetration_whole_run);
    assert_eq!(a.recording, b.recording);
    assert_eq!(a.profile_history, b.profile_history);
    assert_eq!(a.settling, b.settling);
}

/// Runs `scene` to rotation `stop`, saves it through a checkpoint file, and continues it in a
/// new `Simulation` to the end.
fn interrupted(scene: &Scene, stop: u32, file: &Path) -> RunOutput {
    let mut first = Simulation::start(scene).unwrap();
    for _ in 0..stop {
        first.advance_rotation().unwrap();
    }
    write_checkpoint(file, "fp", first.checkpoint()).unwrap();
    drop(first);
    let mut second = Simulation::resume(scene, read_checkpoint(file, "fp").unwrap()).unwrap();
    second.run_to_end(&Silent).unwrap();
    second.finish()
}

fn whole(scene: &Scene) -> RunOutput {
    let mut sim = Simulation::start(scene).unwrap();
    sim.run_to_end(&Silent).unwrap();
    sim.finish()
}

#[test]
fn a_resumed_run_is_bit_identical_to_one_that_never_stopped() {
    let dir = temp_dir("cp", "lib");
    let scene = Scene::load(scene_file(&dir, false, "")).unwrap();
    let reference = whole(&scene);
    for stop in [1, 3, 4] {
        assert_same(&reference, &interrupted(&scene, stop, &dir.join("cp.json")));
    }
}

/// PI.4.2 steers by the last two errors: a checkpoint must carry them. The standard scene
/// runs it; the I controller, a setting, resumes bit-identically too.
#[test]
fn a_run_under_either_step_control_resumes_bit_identically() {
    let dir = temp_dir("cp", "control");
    let scene = |control: &str| {
        let set = format!("\"run.step_control\" = \"{control}\"\n");
        Scene::load(scene_file(&dir, false, &set)).unwrap()
    };
    let (pi42, i) = (scene("pi42"), scene("i"));
    let reference = whole(&pi42);
    let i_controller = whole(&i);
    assert_ne!(reference.stats.steps, i_controller.stats.steps);
    for stop in [1, 3] {
        assert_same(&reference, &interrupted(&pi42, stop, &dir.join("cp.json")));
        assert_same(&i_controller, &interrupted(&i, stop, &dir.join("cp.json")));
    }
}

#[test]
fn a_run_resumed_while_settling_is_bit_identical_too() {
    let dir = temp_dir("cp", "settle");
    let scene = Scene::load(scene_file(&dir, true, "")).unwrap();
    let reference = whole(&scene);
    assert_eq!(reference.settling.map(|s| s.rotations), Some(3));
    // While settling, where it ends (the recording window opened then, with its first grid
    // point at that very time still to sample: refused when the check expected it sampled)
    // and after it.
    for stop in [2, 3, 4] {
        assert_same(&reference, &interrupted(&scene, stop, &dir.join("cp.json")));
    }
    // a checkpoint of another fingerprint is refused
    let e = read_checkpoint(&dir.join("cp.json"), "other")
        .err()
        .unwrap();
    assert!(e.to_string().contains("--resume"), "{e}");
}

#[test]
fn command_line_resumes_and_refuses_what_it_cannot() {
    let dir = temp_dir("cp", "cli");
    let path = scene_file(&dir, false, "");
    let scene = Scene::load(&path).unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let (p, o) = (path.to_str().unwrap(), out.to_str().unwrap());
    // nothing to resume
    let r = jointwear(&["run", p, "--out", o, "--resume"]);
    assert_eq!(
        r.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    // a checkpoint after 3 rotations, as `--checkpoint-every 3` writes it
    let doc = SceneFile::read_document(&path).unwrap();
    let mut sim = Simulation::start(&scene).unwrap();
    for _ in 0..3 {
        sim.advance_rotation().unwrap();
    }
    let saved = out.join(CHECKPOINT_FILE);
    write_checkpoint(
        &saved,
        &fingerprint(&doc, std::iter::empty()),
        sim.checkpoint(),
    )
    .unwrap();
    let r = jointwear(&["run", p, "--out", o, "--resume"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(!saved.exists(), "a completed run removes its checkpoint");
    let (_, columns) = read_csv(&out.join("wear_rod-slider.csv")).unwrap();
    assert_eq!(columns[1], whole(&scene).final_wear[0]);
    // a checkpoint of the scene before an edit is refused
    write_checkpoint(&saved, "0123456789abcdef", sim.checkpoint()).unwrap();
    let r = jointwear(&["run", p, "--out", o, "--resume"]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("edited since"));
    // so is one of the scene as it is, resumed with a --set it was not started with
    write_checkpoint(
        &saved,
        &fingerprint(&doc, std::iter::empty()),
        sim.checkpoint(),
    )
    .unwrap();
    // (another step-size controller too: a run continued under it would match neither's)
    for set in ["driver.speed_rpm=1000", "run.step_control=pi42"] {
        let r = jointwear(&["run", p, "--out", o, "--resume", "--set", set]);
        assert_eq!(r.status.code(), Some(2), "{set}");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(
            err.contains("started with other --set/--rotations values"),
            "{set}: {err}"
        );
    }
    // --checkpoint-every writes checkpoints and removes the last one when the run completes;
    // the folder's checkpoint of an unfinished run goes only when the user says so
    let every = ["run", p, "--out", o, "--checkpoint-every", "2"];
    assert_eq!(jointwear(&every).status.code(), Some(2));
    assert!(saved.exists());
    let r = jointwear(&[&every[..], &["--discard-checkpoint"]].concat());
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(!saved.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
