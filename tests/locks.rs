//! Linkages that lock or cannot close: a run is refused before it simulates, naming the driver
//! angles its ideal loop cannot turn through and the joints left open, and the assembly names
//! the joints where a loop stays open.

use jointwear::scene::{scene_path, RevoluteSpec, SceneFile};
use jointwear::simulation::simulate;
use jointwear::simulation::Scene;
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

/// The standard slider-crank with a 50 mm rod, as long as the crank.
fn long_as_crank() -> SceneFile {
    let mut f = short_rod();
    f.bodies[1].position_mm = [75.0, 0.0];
    f.bodies[1].points_mm.insert("A".into(), [-25.0, 0.0]);
    f.bodies[1].points_mm.insert("B".into(), [25.0, 0.0]);
    f.bodies[2].position_mm = [100.0, 0.0];
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

/// The refusal of `f`'s run before it simulates: a lock of its ideal loop, bad input.
#[track_caller]
fn refused_before_running(f: &SceneFile) -> String {
    match simulate(&f.build().unwrap()) {
        Err(e @ Error::Invalid { .. }) => {
            assert_eq!(jointwear::error::exit_code(&e), 2);
            e.to_string()
        }
        other => panic!("expected a refusal, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn a_rod_shorter_than_the_crank_is_refused_before_it_runs() {
    // Before: the run simulated up to the lock and failed there (exit 1) when the clearance
    // joint was pulled 20 clearances apart at 336.3 deg, 2 ms in, naming the lock beside it.
    let msg = refused_before_running(&short_rod());
    for needle in [
        "`joints (one driver rotation)`",
        "the driver cannot turn from 336.4 to 23.6 deg of driver angle (turning clockwise)",
        "revolute[1] (crank-rod)",
        "clearance joint `rod-slider` (rod-slider, held ideal)",
        // what a slider-crank needs, not only a four-bar's condition
        "a slider-crank's crank turns fully when its rod is no shorter than the crank plus \
         the slider guide's offset from the crank pivot",
    ] {
        assert!(msg.contains(needle), "lacks `{needle}`: {msg}");
    }
    // So is the same linkage with the clearance joint ideal.
    let mut f = short_rod();
    f.clearance.clear();
    f.revolute.push(RevoluteSpec {
        a: "rod.B".into(),
        b: "slider.C".into(),
    });
    let msg = refused_before_running(&f);
    for needle in [
        "cannot turn from 336.4 to 23.6 deg",
        "revolute[2] (rod-slider)",
    ] {
        assert!(msg.contains(needle), "lacks `{needle}`: {msg}");
    }
}

/// A rod as long as the crank closes the loop at every crank angle: at 90 and 270 deg the
/// slider reaches the crank pivot, a singular pose where both branches (slider at 2r cos θ,
/// and slider held at the pivot) cross. Newton fails at that pose, and the sweep called it a
/// lock from 270 to 90 deg, which the run disproves: it turns through on the smooth branch
/// (the slider within 0.1 mm of 2r cos θ, the journal at most 37 µm into its bearing, under
/// 2 clearances). Fails with the sweep stopping at the singular pose.
#[test]
fn a_rod_as_long_as_the_crank_turns_through_its_change_points() {
    let mut f = long_as_crank();
    f.run.max_steps = 100_000;
    let scene = f.build().unwrap();
    assert_eq!(rotation_lock(&scene), None);
    simulate(&scene).unwrap();
}

/// The rod-as-long-as-the-crank linkage with its clearance joint ideal: its loop closes at
/// every angle, but with ideal joints it cannot pass the singular pose, where the constraints
/// become dependent; the run stops there naming the joints.
#[test]
fn an_ideal_loop_at_its_singular_pose_names_its_joints() {
    let mut f = long_as_crank();
    f.clearance.clear();
    f.revolute.push(RevoluteSpec {
        a: "rod.B".into(),
        b: "slider.C".into(),
    });
    let (time, cause) = run_failure(&f);
    for needle in [
        "the linkage locks at driver angle 270.0 deg",
        "revolute[2] (rod-slider)",
        "dead-centre",
    ] {
        assert!(cause.contains(needle), "lacks `{needle}`: {cause}");
    }
    // Clockwise at 2000 r/min, 90 deg at 7.5 ms.
    assert!((time - 7.5e-3).abs() < 1e-5, "t = {time}");
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
        "revolute[2] (ground-rocker) by 69.58 mm",
        "clearance joint `coupler-rocker` (coupler-rocker, held ideal) by 69.58 mm",
    ] {
        assert!(msg.contains(joint), "lacks `{joint}`: {msg}");
    }
}

/// The four-bar of `data/scenes/fourbar.toml` with ground 120, crank 40, coupler 30 and rocker
/// 90 mm, assembled at crank angle 0 (pin B at (35, 29.58) mm): past the crank angle where the
/// crank pin is 120 mm from the rocker pivot, acos(1/6) = 80.406 deg, coupler and rocker
/// cannot reach.
fn locked_fourbar() -> SceneFile {
    let mut f = SceneFile::read(scene_path("fourbar")).unwrap();
    f.ground.points_mm.insert("D".into(), [120.0, 0.0]);
    let points = |a: &str, b: &str, half: f64| {
        [(a.to_string(), [-half, 0.0]), (b.to_string(), [half, 0.0])].into()
    };
    let [crank, coupler, rocker] = &mut f.bodies[..] else {
        panic!("the four-bar has three bodies")
    };
    (crank.points_mm, crank.position_mm) = (points("O", "A", 20.0), [20.0, 0.0]);
    (coupler.points_mm, coupler.position_mm) = (points("A", "B", 15.0), [37.5, 14.79]);
    coupler.angle_deg = 99.6;
    (rocker.points_mm, rocker.position_mm) = (points("D", "B", 45.0), [77.5, 14.79]);
    rocker.angle_deg = 160.8;
    f
}

/// The lock of the ideal loop of `scene` over one rotation from its assembled start.
fn rotation_lock(scene: &Scene) -> Option<jointwear::mechanism::Lock> {
    let y = scene.mechanism.assemble(&scene.guess).unwrap();
    scene.mechanism.check_rotation(0.0, &y).unwrap()
}

#[test]
fn one_driver_rotation_finds_where_a_fourbar_cannot_close() {
    // Before, `check` assembled only at t = 0 and passed this scene. Fails if the sweep turns
    // against the driver (it would stop at 279.6 deg first).
    let lock = rotation_lock(&locked_fourbar().build().unwrap()).expect("the four-bar locks");
    // The loop closes while the crank pin is at most 120 mm from the rocker pivot: up to
    // acos(1/6) = 80.4059 deg each way (an exact scan). Tolerance: the sweep's resolution
    // (1e-3 deg) plus Newton's slower convergence at the limit position, where the loop's
    // Jacobian becomes singular (found: 80.405 and 279.595 deg, within 1e-3 deg).
    let limit = (1.0f64 / 6.0).acos().to_degrees();
    approx::assert_abs_diff_eq!(lock.from, limit, epsilon = 2e-3);
    approx::assert_abs_diff_eq!(lock.to, 360.0 - limit, epsilon = 2e-3);
    let text = lock.error().to_string();
    for needle in [
        "`joints (one driver rotation)`",
        "the driver cannot turn from 80.4 to 279.6 deg of driver angle (turning counter-clockwise)",
        // What the sweep found, and how finely: no claim about the angles it never reached.
        "from its start at 0.0 deg in steps of 1 deg",
        "closes counter-clockwise as far as 80.405 deg and clockwise as far as 279.595 deg, \
         and fails to close within 0.001 deg past each",
        "clearance joint `coupler-rocker`",
        "revolute[2] (ground-rocker)",
    ] {
        assert!(text.contains(needle), "lacks `{needle}`: {text}");
    }
    // The shipped scenes turn fully.
    for name in ["fourbar", "standard", "two_clearance"] {
        assert_eq!(
            rotation_lock(&Scene::load(scene_path(name)).unwrap()),
            None,
            "{name}"
        );
    }
}

/// The four-bar with ground 100, crank 40, coupler 20 and rocker 90 mm, assembled at crank
/// angle 60 deg or, `mirrored` about the ground line, at 300 deg. Coupler and rocker reach the
/// crank pin only between 70 and 110 mm from the rocker pivot: at crank angles from
/// acos(0.8375) = 33.123 to acos(-0.0625) = 93.583 deg and their mirror, 266.417 to 326.877
/// deg, two ranges no turning driver joins.
fn two_range_fourbar(mirrored: bool) -> SceneFile {
    let mut f = SceneFile::read(scene_path("fourbar")).unwrap();
    let sign = if mirrored { -1.0 } else { 1.0 };
    let points = |a: &str, b: &str, half: f64| {
        [(a.to_string(), [-half, 0.0]), (b.to_string(), [half, 0.0])].into()
    };
    let [crank, coupler, rocker] = &mut f.bodies[..] else {
        panic!("the four-bar has three bodies")
    };
    // Pin A at (20, 34.64) mm, pin B at (27.42, 53.21) mm.
    (crank.points_mm, crank.position_mm) = (points("O", "A", 20.0), [10.0, sign * 17.32]);
    let start = if mirrored { 300.0 } else { 60.0 };
    crank.angle_deg = start;
    (coupler.points_mm, coupler.position_mm) = (points("A", "B", 10.0), [23.71, sign * 43.93]);
    coupler.angle_deg = sign * 68.2;
    (rocker.points_mm, rocker.position_mm) = (points("D", "B", 45.0), [63.71, sign * 26.61]);
    rocker.angle_deg = sign * 143.8;
    f.driver.angle_deg = start;
    f
}

#[test]
fn the_lock_message_claims_only_the_ends_the_sweep_found() {
    // Before: "cannot close from 93.6 to 33.1 deg of driver angle", although the loop closes
    // from 266.4 to 326.9 deg, which the sweep from 60 deg never reached; the message now
    // gives the ends found and says the driver cannot turn between them (the former message
    // fails the needles below).
    let lock =
        |mirrored| rotation_lock(&two_range_fourbar(mirrored).build().unwrap()).expect("it locks");
    let (near, far) = (
        0.8375f64.acos().to_degrees(),
        (-0.0625f64).acos().to_degrees(),
    );
    let (from_60, from_300) = (lock(false), lock(true));
    // Tolerance: as for the four-bar above, the resolution and Newton at the limit position.
    approx::assert_abs_diff_eq!(from_60.from, far, epsilon = 2e-3);
    approx::assert_abs_diff_eq!(from_60.to, near, epsilon = 2e-3);
    // Inside the range the driver cannot turn through from 60 deg, the loop closes.
    approx::assert_abs_diff_eq!(from_300.from, 360.0 - near, epsilon = 2e-3);
    approx::assert_abs_diff_eq!(from_300.to, 360.0 - far, epsilon = 2e-3);
    let text = from_60.describe();
    for needle in [
        "turned from its start at 60.0 deg in steps of 1 deg",
        "closes counter-clockwise as far as 93.58",
        "and clockwise as far as 33.12",
        "the driver cannot turn from 93.6 to 33.1 deg of driver angle (turning counter-clockwise)",
    ] {
        assert!(text.contains(needle), "lacks `{needle}`: {text}");
    }
}

#[test]
fn a_fourbar_that_locks_is_refused_before_it_runs() {
    // Before: it ran 13.4 ms into the lock at 80.4 deg and failed there (exit 1).
    let msg = refused_before_running(&locked_fourbar());
    assert!(
        msg.contains("the driver cannot turn from 80.4 to 279.6 deg of driver angle"),
        "{msg}"
    );
}
