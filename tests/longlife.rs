//! Cycle-jump extrapolation against brute-force simulation.

use jointwear::io::progress::Silent;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::ensemble::{self, EnsembleSettings};
use jointwear::simulation::longlife::{predict, LongLifeSettings};
use jointwear::simulation::{simulate, Scene};

fn l2(a: &[f64]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Members of the brute-force ensemble of [`extrapolation_matches_brute_force`], and of its
/// ensemble of predictions.
const MEMBERS: usize = 8;

// The median helper takes the mean of the middle two.
const _: () = assert!(MEMBERS >= 2 && MEMBERS.is_multiple_of(2));

/// 100 rotations of the standard scene with k/H accelerated to 5e-12 1/Pa (about 10 µm of wear
/// on a 20 µm clearance, so the wear feeds back into the dynamics): the per-sector median
/// profile of [`MEMBERS`] extrapolated predictions against that of [`MEMBERS`] brute-force
/// members (seed 1, the default protocol). Each prediction runs its member's mechanism, the
/// journal pin shifted by the member's offset of at most 10 nm, from the assembled (centred)
/// start; its brute-force member starts the unshifted mechanism with the journal at that offset.
/// Both are perturbations of 10 nm of the same scene, not the same start.
///
/// Neither side is one trajectory. The motion is chaotic, a single run can settle into either
/// of two wear states, and the rotations an extrapolation samples are as much a draw: one
/// prediction against a brute-force mean missed its peak by 2.2 % to 7.5 % over six builds
/// that differed only in rounding, so a test of one prediction failed on a change of rounding.
/// Medians, not means: a rare brute-force member whirls round the worn bearing with forces
/// near 1e6 N and ends 15 times deeper (2 of 176 members over seeds 1-22 of one build, none of
/// 208 of the build before it; `jointwear run data/scenes/standard.toml --set
/// clearance.0.wear.k_over_h_per_pa=5e-12 --rotations 100 --member 7 --seed 6` at the commit
/// that wrote this is one), which one member in eight cannot move a median by.
///
/// Tolerances from the measured spread: this test with seeds 1-8 on two builds that differ
/// only in rounding (16 draws) gave peak errors of 0.4-5.9 % (mean 3.0 %, sd 1.6 %: the
/// extrapolation reads low) and L2 errors of 1.9-3.9 % (mean 2.7 %, sd 0.7 %). Asserted: the
/// peak at 8 %, its mean plus three sd (wider than the 5 % the old single prediction was held
/// to, which one draw had set); L2 at 6 %, above every draw and below the 7.5 % of the 1.1
/// scaling below (narrower than the old 10 %). Checked to fail: the extrapolated blocks' wear
/// scaled by 1.2 in `Simulation::add_wear` gives L2 errors of 14.7 % and 15.4 % (seeds 1 and 5),
/// by 1.1, 7.5 % at both. Past the clearance (k/H = 1e-11: 36 µm in 100 rotations) one
/// rotation no longer represents a block and the extrapolation is off by half: see the module
/// documentation.
#[test]
fn extrapolation_matches_brute_force() {
    let mut f = SceneFile::read(scene_path("standard")).unwrap();
    f.clearance[0].wear.as_mut().unwrap().k_over_h_per_pa = 5e-12;
    f.run.rotations = 100;
    f.run.record_rotations = 0;
    f.run.wear_snapshots.clear();
    let scene = f.build().unwrap();
    let seed = 1;
    let ensemble = EnsembleSettings {
        members: MEMBERS,
        seed,
        ..EnsembleSettings::default()
    };
    // Per sector, the median over the profiles (the mean of the middle two).
    let median = |profiles: &[Vec<f64>]| -> Vec<f64> {
        (0..profiles[0].len())
            .map(|i| {
                let mut d: Vec<f64> = profiles.iter().map(|m| m[i]).collect();
                d.sort_by(f64::total_cmp);
                let h = d.len() / 2;
                0.5 * (d[h - 1] + d[h])
            })
            .collect()
    };
    let members = ensemble::run(
        &scene,
        &ensemble,
        |_, mut o| o.final_wear.remove(0),
        &Silent,
    )
    .unwrap();
    let brute = median(&members);
    let settings = LongLifeSettings {
        rotations: 100,
        ..LongLifeSettings::default()
    };
    let mut predictions = Vec::new();
    for member in 0..MEMBERS {
        let start = Scene {
            mechanism: ensemble.perturbation.mechanism(&scene, seed, member),
            ..scene.clone()
        };
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let count = |_, _| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        };
        let life = predict(&start, &settings, &count).unwrap();
        let stage = life.snapshots.last().unwrap();
        assert_eq!(stage.rotations, 100);
        assert!(life.simulated < 60, "simulated {}", life.simulated);
        assert_eq!(calls.into_inner(), life.history.len() - 1);
        // Clearance growth is monotonic.
        assert!(life.history.windows(2).all(|w| {
            w[1].max_depth(0) >= w[0].max_depth(0) && w[1].rotations > w[0].rotations
        }));
        predictions.push(stage.depths[0].clone());
    }
    let predicted = median(&predictions);
    let max = |d: &[f64]| d.iter().cloned().fold(0.0, f64::max);
    let diff: Vec<f64> = predicted.iter().zip(&brute).map(|(a, b)| a - b).collect();
    let (peak_err, l2_err) = (
        (max(&predicted) - max(&brute)).abs() / max(&brute),
        l2(&diff) / l2(&brute),
    );
    let peaks = |p: &[Vec<f64>]| -> Vec<f64> { p.iter().map(|m| max(m) * 1e6).collect() };
    eprintln!(
        "brute median max {:.3} µm (members {:.3?}), predicted median max {:.3} µm (predictions \
         {:.3?}), peak error {peak_err:.3}, L2 error {l2_err:.3}",
        max(&brute) * 1e6,
        peaks(&members),
        max(&predicted) * 1e6,
        peaks(&predictions),
    );
    assert!(peak_err < 0.08 && l2_err < 0.06);
}

#[test]
fn realistic_coefficient_doubles_the_clearance_within_a_million_rotations_quickly() {
    let mut f = SceneFile::read(scene_path("standard")).unwrap();
    f.clearance[0].wear.as_mut().unwrap().k_over_h_per_pa = 1e-15;
    let scene = f.build().unwrap();
    let settings = LongLifeSettings {
        rotations: 1_000_000,
        snapshots: vec![250_000, 500_000],
        ..LongLifeSettings::default()
    };
    let life = predict(&scene, &settings, &Silent).unwrap();
    let counts: Vec<u64> = life.snapshots.iter().map(|s| s.rotations).collect();
    // the clearance doubles (the default limit) between 500 000 and a million rotations
    let (at, _) = life.reached.expect("the clearance doubles");
    assert!((500_000..1_000_000).contains(&at), "{at}");
    assert_eq!(counts, vec![250_000, 500_000, at]);
    assert!(life.simulated < 200, "simulated {}", life.simulated);
    let depth = life.snapshots.last().unwrap().max_depth(0);
    // 1000 times less wear per rotation than the accelerated 40-rotation run (0.56 µm), over
    // 20000 times more rotations: the 20 µm clearance, reached within one rotation's wear.
    assert!((20e-6..20.01e-6).contains(&depth), "{depth:e}");
}

/// The default limit is the clearance doubled: the prediction stops at the first sample
/// rotation that reaches it, reports when, and never carries the wear past it by more than
/// that rotation's increment.
#[test]
fn prediction_stops_when_the_clearance_doubles() {
    let mut f = SceneFile::read(scene_path("standard")).unwrap();
    f.clearance[0].wear.as_mut().unwrap().k_over_h_per_pa = 5e-12;
    let scene = f.build().unwrap();
    let settings = LongLifeSettings {
        rotations: 1_000_000,
        ..LongLifeSettings::default()
    };
    let life = predict(&scene, &settings, &Silent).unwrap();
    let (at, joint) = life.reached.expect("the clearance doubles");
    assert_eq!(joint, 0);
    let c = life.clearances[0];
    assert_eq!(life.limits[0], c);
    let last = life.history.last().unwrap();
    assert_eq!(last.rotations, at);
    let depth = last.max_depth(0);
    // Reached within one simulated rotation, never by an extrapolated block: the stage before
    // is one rotation earlier and below the limit. (A bound on the overshoot in µm would be a
    // bound on one chaotic rotation's wear: near the doubled clearance it is 0.1-1.5 µm
    // depending on the impact sequence; 1.5 µm on the joint-coordinate trajectory.) Fails when
    // a block's wear is extrapolated 3x (the block then crosses the limit); dropping the block's
    // to_limit bound alone does not fail it here, as max_change keeps the blocks short of it.
    let previous = &life.history[life.history.len() - 2];
    assert_eq!(previous.rotations + 1, at);
    let before = previous.max_depth(0);
    assert!(
        before < c && depth >= c,
        "{before:e}, {depth:e} against {c:e}"
    );
    // about 10 µm per 100 rotations at first: a few hundred rotations, not millions
    assert!((100..2000).contains(&at), "{at}");
    assert!(life
        .history
        .windows(2)
        .all(|w| w[1].max_depth(0) >= w[0].max_depth(0)));
}

#[test]
fn a_limit_beyond_the_wear_model_is_refused() {
    let scene = SceneFile::read(scene_path("standard"))
        .unwrap()
        .build()
        .unwrap();
    let settings = LongLifeSettings {
        until: Some(2e-3), // 20 % of the 10 mm bearing radius
        ..LongLifeSettings::default()
    };
    let e = predict(&scene, &settings, &Silent).unwrap_err().to_string();
    assert!(e.contains("--until") && e.contains("10 %"), "{e}");
}

#[test]
fn wear_past_the_model_stops_a_run_within_a_rotation() {
    let mut f = SceneFile::read(scene_path("standard")).unwrap();
    f.clearance[0].wear.as_mut().unwrap().k_over_h_per_pa = 1e-6;
    f.run.record_rotations = 0;
    let scene = f.build().unwrap();
    let e = simulate(&scene).unwrap_err().to_string();
    assert!(
        e.contains("beyond the wear model's limit") && e.contains("in driver rotation 1,"),
        "{e}"
    );
}
