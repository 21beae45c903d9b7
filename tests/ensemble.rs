//! Ensembles: bit-identical for a seed whatever the thread count, members that differ where the
//! motion is chaotic and agree where it is not, offsets that keep every ideal joint closed, and
//! `jointwear run --ensemble` end to end.

mod common;

use common::{jointwear, temp_dir};
use jointwear::io::progress::Silent;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::ensemble::{
    member_offsets, member_state, run, run_member, EnsembleSettings, OFFSET_RADIUS,
};
use jointwear::simulation::Scene;

fn short(name: &str, rotations: u32) -> Scene {
    let mut f = SceneFile::read(scene_path(name)).unwrap();
    f.run.rotations = rotations;
    f.run.record_rotations = 0;
    f.run.wear_snapshots.clear();
    f.build().unwrap()
}

fn final_wear(scene: &Scene, members: usize, threads: usize) -> Vec<Vec<f64>> {
    let settings = EnsembleSettings { members, seed: 7 };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run(scene, &settings, |_, o| o.final_wear[0].clone(), &Silent))
        .unwrap()
}

#[test]
fn bit_identical_for_a_seed_whatever_the_thread_count() {
    let scene = short("clearance_0.5mm", 3);
    let one = final_wear(&scene, 4, 1);
    assert_eq!(one, final_wear(&scene, 4, 2));
    assert_eq!(one, final_wear(&scene, 4, 3));
    // chaotic: the 10 nm offsets give visibly different profiles
    let max = |w: &[f64]| w.iter().cloned().fold(0.0, f64::max);
    let spread = one.iter().map(|w| max(w)).fold(0.0, f64::max)
        - one.iter().map(|w| max(w)).fold(f64::INFINITY, f64::min);
    assert!(spread > 1e-3 * max(&one[0]), "members agree: {spread:e}");
}

#[test]
fn members_agree_where_the_motion_is_not_chaotic() {
    // 30 r/min: the journal rests on the bottom of the bearing; the offsets wash out
    let scene = short("speed_30rpm", 10);
    let w = final_wear(&scene, 3, 2);
    let max = |w: &[f64]| w.iter().cloned().fold(0.0, f64::max);
    for m in &w[1..] {
        approx::assert_relative_eq!(max(m), max(&w[0]), max_relative = 1e-3);
    }
}

#[test]
fn offsets_keep_every_ideal_joint_closed_and_move_the_journal_by_nanometres() {
    let scene = short("standard", 1);
    let m = &scene.mechanism;
    let (state, mut ws) = (m.initial_state(), m.workspace());
    let base = m.assemble(&scene.guess).unwrap();
    let n = m.coordinates();
    assert!(
        m.contact_kinematics(&state, 0, &base[..n], &base[n..2 * n])
            .e
            .norm()
            < 1e-12
    );
    let journal = scene.mechanism.clearance_joints[0].journal.body.unwrap();
    for member in 0..5 {
        let d = member_offsets(1, member, 1)[0];
        let y = member_state(&scene, 1, member).unwrap();
        // e0 = R(phi_J) d, measured with the real journal point
        let e = m.contact_kinematics(&state, 0, &y[..n], &y[n..2 * n]).e;
        let rotated = nalgebra::Rotation2::new(y[3 * journal + 2]) * d;
        assert!(
            (e - rotated).norm() < 1e-6 * OFFSET_RADIUS,
            "{e:?} vs {rotated:?}"
        );
        assert!(e.norm() <= OFFSET_RADIUS && e.norm() > 0.0);
        let phi = m.constraint_vector(&mut ws, 0.0, &y[..n]);
        assert!(phi.iter().all(|p| p.abs() < 1e-12), "{phi:?}");
        // the member's run starts from that state
        let out = run_member(&scene, &scene.run, 1, member, &Silent).unwrap();
        assert!(out.final_wear[0].iter().all(|x| x.is_finite()));
    }
}

#[test]
fn command_line_ensemble_writes_statistics_and_refuses_zero_members() {
    let dir = temp_dir("ensemble", "run");
    let file = dir.join("scene.toml");
    std::fs::write(
        &file,
        format!(
            "extends = {:?}\n[overrides]\n\"run.rotations\" = 2\n\"run.record_rotations\" = 1\n\
             \"run.wear_snapshots\" = []\n",
            scene_path("clearance_0.5mm").display().to_string()
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    let r = jointwear(&["run", f, "--out", o, "--ensemble", "3", "--seed", "5"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(
        text.contains("3 members (seed 5)") && text.contains("of 3 members"),
        "{text}"
    );
    let (header, rows) =
        jointwear::io::output::read_rows(&out.join("ensemble_members.csv")).unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(header[0], "member");
    let (_, summary) = jointwear::io::output::read_rows(&out.join("ensemble_summary.csv")).unwrap();
    assert!(summary
        .iter()
        .any(|r| r[1] == "max_wear_depth_m" && r[2] == "3"));
    let (_, band) =
        jointwear::io::output::read_csv(&out.join("ensemble_wear_rod-slider.csv")).unwrap();
    // mean between min and max in every sector
    assert!((0..band[0].len()).all(|i| band[3][i] <= band[1][i] && band[1][i] <= band[9][i]));
    assert!(out.join("wear.png").exists());
    let bad = jointwear(&["run", f, "--out", o, "--ensemble", "0"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--ensemble"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sweep_runs_each_case_as_an_ensemble_with_mean_and_sd_columns() {
    let dir = temp_dir("ensemble", "sweep");
    let out = dir.join("sweep.csv");
    let r = jointwear(&[
        "sweep",
        scene_path("standard").to_str().unwrap(),
        "--set",
        "run.rotations=1",
        "--set",
        "run.record_rotations=1",
        "--set",
        "run.wear_snapshots=[]",
        "--set",
        "clearance.0.clearance_mm=0.2,0.5",
        "--ensemble",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2);
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for row in &rows {
        assert_eq!(row[col("members")], "2");
        let sd: f64 = row[col("rod-slider.max_wear_depth_m.sd")].parse().unwrap();
        let mean: f64 = row[col("rod-slider.max_wear_depth_m.mean")]
            .parse()
            .unwrap();
        assert!(mean > 0.0 && sd >= 0.0 && sd < mean, "{mean} {sd}");
        assert!(row[col("error")].is_empty());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
