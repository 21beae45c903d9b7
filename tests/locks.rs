//! Linkages that lock or cannot close: the run stops with an error naming the time, the
//! driver angle and the joints within a bounded number of steps, and the assembly names the
//! joints where a loop stays open.

use jointwear::scene::{scene_path, RevoluteSpec, SceneFile};
use jointwear::simulation::simulate;
use jointwear::Error;

/// Steps within which a locked run must fail: the standard scene takes ~5000 steps per
/// rotation, a locked one crawled into the 20-million-step limit.
const MAX_STEPS: u64 = 2000;

/// The standard slider-crank with a 20 mm rod, shorter than the 50 mm crank: the rod cannot
/// reach the slider's axis once the crank is 23.6 deg from it.
fn short_rod() -> SceneFile {
    let mut f = SceneFile::read(scene_path("standard")).unwrap();
    let rod = &mut f.bodies[1];
    rod.position_mm = [60.0, 0.0];
    rod.points_mm.insert("A".into(), [-10.0, 0.0]);
    rod.points_mm.insert("B".into(), [10.0, 0.0]);
    f.bodies[2].position_mm = [70.0, 0.0];
    f.run.rotations = 2;
    f.run.wear_snapshots.clear();
    f.run.max_steps = MAX_STEPS;
    f
}

/// The integration error of simulating `f`, which must fail while running.
#[track_caller]
fn run_failure(f: &SceneFile) -> (f64, String) {
    match simulate(&f.build().unwrap()) {
        Err(Error::Integration { time, cause }) => (time, cause),
        other => panic!("expected an integration error, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn a_rod_shorter_than_the_crank_stops_at_the_clearance_joint_it_pulls_apart() {
    let (time, cause) = run_failure(&short_rod());
    for needle in [
        "clearance joint `rod-slider` (journal on rod, bearing on slider)",
        "beyond 10 % of its journal radius (9.980e-4 m)",
        "driver angle 335.1 deg",
        "lock the mechanism",
    ] {
        assert!(cause.contains(needle), "lacks `{needle}`: {cause}");
    }
    // Clockwise at 2000 r/min, the crank passes 23.6 deg at 1.96 ms; the clearance and the
    // contact compliance let it go a little further.
    assert!((1.9e-3..2.2e-3).contains(&time), "t = {time}");
}

#[test]
fn an_ideal_loop_at_its_lock_position_names_its_joints() {
    let mut f = short_rod();
    f.clearance.clear();
    f.revolute.push(RevoluteSpec {
        a: "rod.B".into(),
        b: "slider.C".into(),
    });
    let (time, cause) = run_failure(&f);
    for needle in [
        "the linkage locks at driver angle 336.4 deg",
        "revolute[2] (rod-slider)",
        "revolute[1] (crank-rod)",
        "dead-centre",
    ] {
        assert!(cause.contains(needle), "lacks `{needle}`: {cause}");
    }
    // The rod stands upright when 50 mm · sin θ = 20 mm: θ = 23.58 deg at 1.965 ms.
    assert!((time - 1.9648e-3).abs() < 1e-6, "t = {time}");
}

#[test]
fn a_fourbar_whose_links_cannot_close_names_the_open_joints() {
    let mut f = SceneFile::read(scene_path("fourbar")).unwrap();
    // A 200 mm coupler cannot close the loop at crank angle 0: its pin A is 70 mm from the
    // rocker pivot, and the 70 mm rocker reaches at most 140 mm from A.
    let coupler = &mut f.bodies[1];
    coupler.points_mm.insert("A".into(), [-100.0, 0.0]);
    coupler.points_mm.insert("B".into(), [100.0, 0.0]);
    let scene = f.build().unwrap();
    let msg = scene
        .mechanism
        .assemble(&scene.guess)
        .unwrap_err()
        .to_string();
    for needle in [
        "`joints (assembly)`",
        "the loop cannot close",
        "after 50 Newton iterations",
        "links whose lengths can close every loop",
    ] {
        assert!(msg.contains(needle), "lacks `{needle}`: {msg}");
    }
    // Least squares spreads the gap over the joints of the loop next to the rocker.
    for joint in [
        "revolute[2] (ground-rocker) by 6.958e-2",
        "clearance joint `coupler-rocker` (coupler-rocker, held ideal) by 6.958e-2",
    ] {
        assert!(msg.contains(joint), "lacks `{joint}`: {msg}");
    }
}
