//! The joint-coordinate formulation of tree-shaped linkages against the absolute one as
//! oracle: at states along a run, in contact and (with the bearings widened) in free flight,
//! both give the same accelerations of every body and the same energy powers.

use approx::assert_relative_eq;
use jointwear::mechanism::{Formulation, Mechanism, RunState};
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::Simulation;

/// Time step (s) of the central difference that turns the joint accelerations into body
/// accelerations: the difference's rounding is about 1e-16 |v| / h ≈ 1e-7 m/s² at the 10 m/s
/// of the slider, its truncation O(h²) of the kinematics along the path.
const H: f64 = 1e-8;

/// Allowed difference, relative to the largest body acceleration of the state: the central
/// difference's 1e-7 m/s² against accelerations of 1e2 to 1e6 m/s², and the absolute
/// formulation's Baumgarte terms, which vanish on the exactly closed joints of the state up to
/// rounding.
const TOLERANCE: f64 = 1e-6;

/// The shipped scenes integrated in joint coordinates (every one but two_clearance, whose rod
/// hangs on clearance joints only).
const TREES: [&str; 6] = [
    "standard",
    "clearance_0.2mm",
    "clearance_0.5mm",
    "speed_30rpm",
    "speed_600rpm",
    "fourbar",
];

/// Checks that both formulations of `m` give the same body accelerations and powers at the
/// absolute state `y` of time `t`.
fn agree(name: &str, m: &Mechanism, state: &RunState, t: f64, y: &[f64]) {
    let n = m.coordinates();
    let mut ws = m.workspace();
    let mut dy = vec![0.0; y.len()];
    m.rhs(state, &mut ws, t, y, &mut dy).unwrap();
    let z = m.ode_state(y);
    let mut dz = vec![0.0; z.len()];
    m.ode_rhs(state, &mut ws, t, &z, &mut dz).unwrap();
    // z along its quadratic path at t ± H: its velocities' central difference is the bodies'
    // acceleration.
    let f = m.ode_controlled() / 2;
    let at = |s: f64| {
        let mut zs = z.clone();
        for k in 0..f {
            zs[k] = z[k] + s * dz[k] + 0.5 * s * s * dz[f + k];
            zs[f + k] = dz[k] + s * dz[f + k];
        }
        let mut ys = vec![0.0; y.len()];
        m.absolute_state(t + s, &zs, &mut ys);
        ys
    };
    let (plus, minus) = (at(H), at(-H));
    let largest = dy[n..2 * n].iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    for i in 0..n {
        let tree = (plus[n + i] - minus[n + i]) / (2.0 * H);
        assert!(
            (tree - dy[n + i]).abs() <= TOLERANCE * largest,
            "{name} t = {t:e}: acceleration {i} {tree:e} (joint coordinates) against {:e} \
             (absolute), largest {largest:e}",
            dy[n + i]
        );
    }
    // Driver, normal-contact and friction power (W).
    for e in (0..3).filter(|_| m.energy_accounting) {
        assert_relative_eq!(
            dz[2 * f + e],
            dy[2 * n + e],
            epsilon = TOLERANCE * largest,
            max_relative = TOLERANCE
        );
    }
}

/// Compares both formulations at `states` states every `every` steps of the scene's run, as
/// they are and with the clearance joints widened by a millimetre (free flight); returns the
/// states in contact as they are.
fn compare(name: &str, states: usize, every: usize) -> usize {
    let mut file = SceneFile::read(scene_path(name)).unwrap();
    (file.run.record_rotations, file.run.rotations) = (0, 1);
    file.run.wear_snapshots.clear();
    let mut scene = file.build().unwrap();
    scene.mechanism.energy_accounting = true;
    scene.run.energy_accounting = true;
    let m = scene.mechanism.clone();
    assert!(
        matches!(m.formulation(), Formulation::JointCoordinates { .. }),
        "{name}: {}",
        m.formulation()
    );
    let mut wide = m.clone();
    for cj in &mut wide.clearance_joints {
        cj.r_bearing += 1e-3;
    }
    let mut without_energy = m.clone();
    without_energy.energy_accounting = false;
    let mut sim = Simulation::start(&scene).unwrap();
    let n = m.coordinates();
    let mut touching = 0;
    for _ in 0..states {
        for _ in 0..every {
            sim.advance_step().unwrap();
        }
        let (t, y, state) = (sim.time(), sim.y(), sim.state());
        agree(name, &m, state, t, &y);
        agree(name, &wide, state, t, &y);
        // Without energy accounting the joint formulation takes no driver column (its
        // sized path for the runs that do not ask for powers).
        agree(name, &without_energy, state, t, &y[..2 * n]);
        let contact = |m: &Mechanism| m.contact_state(state, 0, &y[..n], &y[n..2 * n]);
        assert!(!contact(&wide).in_contact());
        touching += usize::from(contact(&m).in_contact());
    }
    touching
}

// Fails when the centripetal term of a body's arm is left out of the joint formulation's
// accelerations (`+ c.arm_child * (c.w * c.w)` in mechanism/tree.rs): tried.
#[test]
fn joint_coordinates_give_the_absolute_accelerations_in_and_out_of_contact() {
    for name in TREES {
        // 60 states 20 steps apart cover the start-up's free flight and the first impacts.
        let touching = compare(name, 60, 20);
        assert!(touching > 0, "{name}: no state in contact");
    }
}

#[test]
fn the_absolute_state_round_trips_through_joint_coordinates() {
    for name in TREES {
        let scene = SceneFile::read(scene_path(name)).unwrap().build().unwrap();
        let m = &scene.mechanism;
        let y = m.assemble(&scene.guess).unwrap();
        let mut back = vec![0.0; y.len()];
        m.absolute_state(0.0, &m.ode_state(&y), &mut back);
        for (a, b) in y.iter().zip(&back) {
            // The assembly closes the joints to rounding of coordinates of order 0.1 m.
            assert_relative_eq!(*a, *b, epsilon = 1e-12);
        }
    }
}
