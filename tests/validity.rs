//! Validity limits of the scene values: what the models cannot describe is refused when the
//! scene is built, naming the field, the value, the limit and the likely cause.

use jointwear::scene::{scene_path, SceneFile};

fn standard() -> SceneFile {
    SceneFile::read(scene_path("standard")).unwrap()
}

/// The message of building `f`, which must fail.
#[track_caller]
fn refused(f: &SceneFile) -> String {
    match f.build() {
        Ok(_) => panic!("the scene was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_record_budget_admits_fine_grids_and_refuses_absurd_ones() {
    // Standard scene: 2 recorded rotations of 30 ms, 29 columns: 2 GiB holds 9.26e6 rows,
    // an interval of 6.5 ns.
    let mut f = standard();
    f.run.record_interval_s = 1e-8;
    f.build().unwrap();
    f.run.record_interval_s = 1e-9;
    let msg = refused(&f);
    assert!(
        msg.contains("`run.record_interval_s`") && msg.contains("6.000e7 rows"),
        "{msg}"
    );
    let mut f = standard();
    f.run.profile_history_per_rotation = 3600;
    f.run.rotations = 1_000_000;
    f.run.wear_snapshots.clear();
    let msg = refused(&f);
    assert!(
        msg.contains("`run.profile_history_per_rotation`") && msg.contains("3.600e9 profiles"),
        "{msg}"
    );
}
