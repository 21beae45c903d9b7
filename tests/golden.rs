//! Golden tests on ensemble statistics (`src/paper/golden.rs` gives the bound and why).
//!
//! - The model's statistics match the recorded ones (`data/golden/ensemble.toml`) for the
//!   recording seed and for another seed: a different sample of the same physics, as a change of
//!   rounding or thread count is, stays inside the sampling-error bound.
//! - A change of physics (restitution 0.9 → 0.8, or μ_d 0.01 → 0.03) moves them out of it.
//! - Against the paper (`data/golden/paper.toml`): where no deviation is declared, the paper's
//!   value lies within tolerance of the ensemble mean; where one is declared, it does not, so a
//!   declared deviation is a real one.
//!
//! The file runs minutes (about 6 on 2 cores): each of the first two tests computes two
//! ensembles of every golden case. Each computation says on stderr when it starts and how far it
//! got, seen with `cargo test --release --test golden -- --nocapture`.

use jointwear::io::progress::Progress;
use jointwear::laws::friction::FrictionModel;
use jointwear::paper::cases::{case_of_scene, Runs, CASES};
use jointwear::paper::golden::{
    angle_distance, compare, measure, EnsembleGolden, Golden, Quantity, SteadyQuantity, Violation,
    GOLDEN_NEEDS,
};
use jointwear::scene::SceneFile;
use jointwear::simulation::ensemble::EnsembleSettings;

/// Tells stderr how far the member runs of one computation got, every tenth of them: `what`
/// names the computation.
struct Told<'a> {
    what: &'a str,
}

impl Progress for Told<'_> {
    fn observe(&self, done: u64, total: Option<u64>) {
        let Some(total) = total else { return };
        if done * 10 / total != done.saturating_sub(1) * 10 / total {
            eprintln!("golden, {}: {done} of {total} member runs done", self.what);
        }
    }
}

/// The golden ensembles for `seed`, the case scenes varied by `modify` (`what` says how, for
/// the progress lines).
fn runs(seed: u64, what: &str, modify: &(dyn Fn(&mut SceneFile) + Sync)) -> Runs {
    let recorded = EnsembleGolden::load().unwrap();
    let ensemble = EnsembleSettings {
        members: recorded.members,
        seed,
        ..EnsembleSettings::default()
    };
    let what = format!("seed {seed}, {what}");
    eprintln!(
        "golden, {what}: {} ensembles of {} members start (the four such \
         computations of this file take about 6 min on 2 cores)",
        GOLDEN_NEEDS.len(),
        ensemble.members
    );
    Runs::compute(&GOLDEN_NEEDS, ensemble, modify, &Told { what: &what }).unwrap()
}

fn violations(seed: u64, what: &str, modify: &(dyn Fn(&mut SceneFile) + Sync)) -> Vec<Violation> {
    let golden = Golden::load().unwrap();
    let measured = measure(&runs(seed, what, modify), &golden).unwrap();
    compare(&measured, &EnsembleGolden::load().unwrap())
}

#[test]
fn recorded_statistics_hold_for_the_recording_seed_and_another() {
    let seed = EnsembleGolden::load().unwrap().seed;
    for s in [seed, seed + 1] {
        let v = violations(s, "the scenes as recorded", &|_| {});
        assert!(v.is_empty(), "seed {s}: {v:#?}");
    }
}

#[test]
fn a_change_of_physics_breaks_them() {
    let restitution = violations(1, "restitution 0.8", &|f| {
        for c in &mut f.clearance {
            c.contact.restitution = 0.8;
        }
    });
    assert!(!restitution.is_empty(), "restitution 0.8 went unnoticed");
    let friction = violations(1, "mu_d 0.03", &|f| {
        for c in &mut f.clearance {
            if let FrictionModel::Modified { mu_s, mu_d, .. } = &mut c.friction {
                *mu_s *= 3.0;
                *mu_d *= 3.0;
            }
        }
    });
    assert!(!friction.is_empty(), "mu_d 0.03 went unnoticed");
    eprintln!(
        "restitution 0.8: {} quantities out of bounds, mu_d 0.03: {}",
        restitution.len(),
        friction.len()
    );
}

#[test]
fn paper_values_match_where_and_only_where_no_deviation_is_declared() {
    let golden = Golden::load().unwrap();
    let recorded = EnsembleGolden::load().unwrap();
    let mean = |q: Quantity| {
        let name = q.name();
        recorded
            .quantity
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("{name} recorded"))
            .mean
    };
    let tol = golden.concordance_tolerance;
    for &(case, row) in CASES.zip(&golden.table3).list() {
        let steady = |q| mean(Quantity::Steady(*case, q));
        let matches = (steady(SteadyQuantity::Pw) - row.pw).abs() <= tol
            && (steady(SteadyQuantity::Sw) - row.sw).abs() <= tol
            && (steady(SteadyQuantity::ContinuousContact) >= 0.5)
                == (row.motion == "continuous contact")
            && (steady(SteadyQuantity::PwDominant) >= 0.5) == (row.dominant() == "P-w");
        let name = case.scene;
        assert_eq!(
            matches,
            row.deviation.is_none(),
            "{name}: the ensemble {} the paper, but paper.toml says it {}",
            if matches { "matches" } else { "departs from" },
            if row.deviation.is_none() {
                "matches"
            } else {
                "departs"
            }
        );
    }
    for claim in [&golden.standard_wear, &golden.low_speed_wear] {
        let tol = claim.angle_tolerance_deg;
        let case = case_of_scene(&claim.scene).unwrap();
        // the low-speed claim is about its deepest region only
        let regions = claim.scene != golden.standard_wear.scene
            || claim.peak_angles_deg.iter().all(|&a| {
                let near = Quantity::RegionNearOffset {
                    case,
                    claimed_deg: a,
                };
                mean(near).abs() <= tol
            });
        let deepest = mean(Quantity::DeepestRegionOffset(case));
        let matches = regions && angle_distance(deepest, 0.0) <= tol;
        assert_eq!(matches, claim.deviation.is_none(), "{}", claim.scene);
    }
}
