//! The shipped scenes beyond the paper's mechanism: a four-bar linkage with a worn
//! coupler-rocker joint, and the slider-crank with two clearance joints.

use jointwear::laws::friction::FrictionModel;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::{simulate, RunOutput};

/// A shipped scene cut to `rotations` rotations, all recorded, wear saved after the first.
fn short(name: &str, rotations: u32) -> SceneFile {
    let mut f = SceneFile::read(scene_path(name)).expect("shipped scene");
    f.run.rotations = rotations;
    f.run.record_rotations = rotations;
    f.run.wear_snapshots = vec![1, rotations];
    f
}

/// Completes, stays finite, presses somewhere in every joint, and every bearing wears more
/// after the last rotation than after the first.
fn assert_sound(out: &RunOutput) {
    assert!(out.final_state.iter().all(|x| x.is_finite()));
    for (k, trace) in out.recording.joints.iter().enumerate() {
        assert!(trace
            .normal_force
            .iter()
            .all(|f| f.is_finite() && *f >= 0.0));
        assert!(trace.ex.iter().chain(&trace.ey).all(|e| e.is_finite()));
        assert!(
            trace.normal_force.iter().any(|&f| f > 0.0),
            "joint {k} never in contact"
        );
        let (first, last) = (
            &out.wear_snapshots[0].depths[k],
            &out.wear_snapshots[1].depths[k],
        );
        let total = |d: &[f64]| d.iter().sum::<f64>();
        assert!(first.iter().zip(last).all(|(a, b)| b >= a));
        assert!(
            total(last) > total(first) && total(first) > 0.0,
            "joint {k} does not wear"
        );
    }
}

#[test]
fn fourbar_runs_and_wears() {
    let out = simulate(&short("fourbar", 3).build().unwrap()).unwrap();
    assert_eq!(out.recording.joints.len(), 1);
    assert_sound(&out);
}

#[test]
fn two_clearance_slider_crank_runs_and_wears_both_joints() {
    let out = simulate(&short("two_clearance", 3).build().unwrap()).unwrap();
    assert_eq!(out.recording.joints.len(), 2);
    assert_sound(&out);
}

/// Rocker pivot D = (100, 0) mm; link lengths crank a, coupler b, rocker c (m).
const D: f64 = 0.100;
const A: f64 = 0.030;
const B: f64 = 0.090;
const C: f64 = 0.070;

/// Ideal elbow-up closure: the coupler-rocker pin for crank angle `theta`.
fn ideal_pin(theta: f64) -> (f64, f64) {
    let (ax, ay) = (A * theta.cos(), A * theta.sin());
    let (dx, dy) = (D - ax, -ay);
    let dist = dx.hypot(dy);
    // Along A→D by x, then y to the left (the elbow-up branch of the scene).
    let x = (B * B - C * C + dist * dist) / (2.0 * dist);
    let y = (B * B - x * x).sqrt();
    let (ux, uy) = (dx / dist, dy / dist);
    (ax + x * ux - y * uy, ay + x * uy + y * ux)
}

#[test]
fn zero_clearance_fourbar_follows_ideal_closure() {
    let mut f = short("fourbar", 2);
    f.clearance[0].clearance_mm = 0.0;
    f.clearance[0].friction = FrictionModel::None;
    f.clearance[0].wear = None;
    f.run.wear_snapshots.clear();
    let out = simulate(&f.build().unwrap()).unwrap();
    let rec = &out.recording;
    let rocker = &rec.positions[2];
    let mut worst: f64 = 0.0;
    for (i, &theta) in rec.driver_angle.iter().enumerate() {
        // rocker's pin point B = centre + R(φ)·(35 mm, 0)
        let phi = rocker[2][i];
        let pin = (
            rocker[0][i] + 0.035 * phi.cos(),
            rocker[1][i] + 0.035 * phi.sin(),
        );
        let ideal = ideal_pin(theta);
        worst = worst.max((pin.0 - ideal.0).hypot(pin.1 - ideal.1));
    }
    // Without clearance only the contact compliance lets the pin move in its bushing.
    assert!(
        worst < 5e-6,
        "rocker pin deviates {worst:e} m from the ideal closure"
    );
    assert!(rec.time.len() > 1000);
}
