//! A run's answer does not depend on how it is driven: progress reports, rotation-by-rotation
//! driving, recording, snapshots, wear history, the command line and the long-life settling
//! phase all give bit-identical wear profiles for the same scene and settings. The scene keeps
//! the standard case's impacts (chaotic), so any change of the step sequence would show.

mod common;

use common::{assert_same_run, jointwear, temp_dir};
use jointwear::io::output::read_csv;
use jointwear::io::progress::Silent;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::longlife::{predict, LongLifeSettings};
use jointwear::simulation::Scene;
use jointwear::simulation::{simulate, simulate_with_progress, Simulation};

const ROTATIONS: u32 = 4;

fn scene(record_rotations: u32, history: u32) -> Scene {
    let mut f = SceneFile::read(scene_path("clearance_0.5mm")).unwrap();
    f.run.rotations = ROTATIONS;
    f.run.record_rotations = record_rotations;
    f.run.wear_snapshots = vec![1, 3];
    f.run.profile_history_per_rotation = history;
    f.build().unwrap()
}

#[test]
fn progress_and_rotation_by_rotation_driving_change_nothing() {
    let s = scene(1, 0);
    let whole = simulate(&s).unwrap();
    let seen = std::sync::Mutex::new(Vec::new());
    let observer = |done, total| seen.lock().unwrap().push((done, total));
    let observed = simulate_with_progress(&s, &observer).unwrap();
    assert_eq!(
        seen.into_inner().unwrap(),
        (1..=ROTATIONS as u64)
            .map(|r| (r, Some(ROTATIONS as u64)))
            .collect::<Vec<_>>()
    );
    assert_same_run(&whole, &observed);
    assert_eq!(whole.recording, observed.recording);
    // Driven by hand, one rotation per call, reading the mechanism in between.
    let m = s.mechanism.clone();
    let y0 = m.assemble(&s.guess).unwrap();
    let mut sim = Simulation::new(m, s.run.clone(), &y0).unwrap();
    while !sim.is_finished() {
        sim.advance_rotation().unwrap();
        assert!(sim.state().joints[0].wear.depths()[0] >= 0.0);
    }
    let by_hand = sim.finish();
    assert_same_run(&whole, &by_hand);
    assert_eq!(whole.recording, by_hand.recording);
    // Step by step: the same steps, each advancing the time.
    let mut sim = Simulation::new(s.mechanism.clone(), s.run.clone(), &y0).unwrap();
    while !sim.is_finished() {
        let start = sim.time();
        sim.advance_step().unwrap();
        assert!(sim.time() > start && sim.y().len() == s.mechanism.state_len());
    }
    let stepwise = sim.finish();
    assert_same_run(&whole, &stepwise);
    assert_eq!(whole.recording, stepwise.recording);
}

#[test]
fn recording_and_wear_history_change_nothing() {
    let bare = simulate(&scene(0, 0)).unwrap();
    let recorded = simulate(&scene(ROTATIONS, 36)).unwrap();
    assert!(bare.recording.time.is_empty() && !recorded.recording.time.is_empty());
    assert_eq!(recorded.profile_history.len(), 36 * ROTATIONS as usize);
    assert_same_run(&bare, &recorded);
}

#[test]
fn settling_is_a_plain_run_of_as_many_rotations() {
    // settling that gives up after 3 rotations (a tolerance no chaotic orbit meets), then 2 more
    let mut f = SceneFile::read(scene_path("clearance_0.5mm")).unwrap();
    f.run.settle = true;
    f.run.steady_state = Some(jointwear::scene::SteadyStateSpec {
        orbit_tolerance: 1e-9,
        max_rotations: 3,
    });
    f.run.rotations = 2;
    f.run.record_rotations = 1;
    f.run.wear_snapshots.clear();
    let settled = simulate(&f.build().unwrap()).unwrap();
    assert_eq!(
        settled.settling.map(|s| (s.rotations, s.steady)),
        Some((3, false))
    );
    let mut g = SceneFile::read(scene_path("clearance_0.5mm")).unwrap();
    g.run.rotations = 5;
    g.run.record_rotations = 0;
    g.run.wear_snapshots.clear();
    let plain5 = simulate(&g.build().unwrap()).unwrap();
    assert!(plain5.impacts[0] > 0);
    assert_eq!(settled.final_wear, plain5.final_wear);
    assert_eq!(settled.final_state, plain5.final_state);
    assert_eq!(settled.stats, plain5.stats);
}

#[test]
fn settling_phase_of_long_life_is_a_plain_run() {
    let s = scene(0, 0);
    let plain = simulate(&s).unwrap();
    let settings = LongLifeSettings {
        rotations: ROTATIONS as u64,
        settle_rotations: ROTATIONS,
        ..LongLifeSettings::default()
    };
    let life = predict(&s, &settings, &Silent).unwrap();
    assert_eq!(life.simulated, ROTATIONS as u64);
    assert_eq!(life.snapshots.last().unwrap().depths, plain.final_wear);
}

#[test]
fn command_line_run_writes_the_library_result() {
    let dir = temp_dir("determinism", "cli");
    let file = dir.join("scene.toml");
    let text = format!(
        "extends = {:?}\n[overrides]\n\"run.rotations\" = {ROTATIONS}\n\
         \"run.record_rotations\" = 1\n\"run.wear_snapshots\" = [1, 3]\n",
        scene_path("clearance_0.5mm").display().to_string()
    );
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let o = jointwear(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, columns) = read_csv(&out.join("wear_rod-slider.csv")).unwrap();
    let library = simulate(&scene(1, 0)).unwrap();
    assert_eq!(columns[1], library.final_wear[0]);
}
