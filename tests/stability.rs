//! Every stability scene (`data/scenes/stability/`) on a short horizon of one rotation: it
//! completes with finite values, bounded penetration and a closed energy balance, or fails
//! with an error that names the time and the cause (never a panic or a hang).

use jointwear::paper::studies::{stability_case, stability_cases, StabilityRow};

/// Step guard of the short runs: the slowest completing case (stick-slip) needs ~250 000
/// steps, most of them while it sticks in its first 5 ms.
const MAX_STEPS: u64 = 400_000;
/// Penetration bound (m): the softest case (E = 1 GPa) reaches 0.14 mm; 0.5 mm is far beyond
/// any physical contact yet far below the 10 mm bearing radius.
const MAX_PENETRATION: f64 = 5e-4;
/// Energy-balance residual bound over these tests' one rotation, relative to the driver work.
/// The energy quadratures are outside error control, so the residual grows with the tolerance
/// and the horizon: over one rotation restitution_0.1, the largest, has 3.0e-4 at rtol 1.5e-7
/// and 5.2e-4 at 2.5e-7 with either step control (measured 2026-11-28; the bound was 5e-4
/// while the scenes ran at 1.5e-7); over the stability study's three rotations grazing_floor
/// reaches 1.6e-3 (`data/stability.csv`), which this bound does not cover. The
/// smallest loss term of the suite, restitution_1.0's normal-force work, is 2.5e-3 of its
/// driver work: a dropped term still fails (checked: without the friction work in the
/// balance, or without the damping loss, the tests fail).
const MAX_RESIDUAL: f64 = 1e-3;

fn completes(name: &str) -> StabilityRow {
    let r = stability_case(name, 1, MAX_STEPS).expect("scene loads");
    assert!(r.failure.is_none(), "{name}: {:?}", r.failure);
    assert!(r.finite, "{name}: non-finite values {r:?}");
    assert!(
        r.max_penetration_whole_run.is_finite() && r.max_penetration_whole_run < MAX_PENETRATION,
        "{name}: penetration {:e} m",
        r.max_penetration_whole_run
    );
    assert!(
        r.energy_residual.abs() < MAX_RESIDUAL,
        "{name}: energy residual {:e}",
        r.energy_residual
    );
    r
}

#[test]
fn every_stability_scene_is_tested() {
    let expected = [
        "clearance_1mm",
        "clearance_1um",
        "coulomb_0.5",
        "deep_wear",
        "grazing_floor",
        "grazing_touch",
        "restitution_0.1",
        "restitution_1.0",
        "speed_10000rpm",
        "speed_30rpm",
        "stick_slip",
        "two_clearance",
        "youngs_1000gpa",
        "youngs_1gpa",
        "zero_clearance",
    ];
    assert_eq!(stability_cases().unwrap(), expected);
}

#[test]
fn soft_contact() {
    completes("youngs_1gpa");
}

#[test]
fn stiff_contact() {
    completes("youngs_1000gpa");
}

#[test]
fn tiny_clearance() {
    completes("clearance_1um");
}

#[test]
fn large_clearance() {
    completes("clearance_1mm");
}

/// A case whose one rotation runs and whose wear then leaves the paper's gap: it stops at the
/// rotation's end (t = 0.03 s at 2000 r/min) with the error that says so.
fn stops_where_the_gap_stops_holding(name: &str) {
    let r = stability_case(name, 1, MAX_STEPS).unwrap();
    let failure = r
        .failure
        .expect("the worn bearing is too steep for the gap");
    for needle in [
        "the run left its model at t = 3.000000e-2 s",
        "|dh/dθ| / (c + h) = ",
    ] {
        assert!(failure.contains(needle), "{needle}: {failure}");
    }
}

#[test]
fn zero_clearance() {
    // Hertz line pressure is refused at ΔR = 0 (infinite half-width, zero peak); the scene
    // uses the elastic-foundation pressure, which holds for conformal contact, and no wear:
    // against no clearance any uneven wear is too steep for the paper's gap, and a worn
    // zero-clearance joint is refused (tests/scenes.rs).
    let r = completes("zero_clearance");
    assert_eq!(r.max_wear, 0.0);
}

#[test]
fn slow_driver() {
    completes("speed_30rpm");
}

#[test]
fn fast_driver() {
    completes("speed_10000rpm");
}

#[test]
fn plastic_impacts() {
    completes("restitution_0.1");
}

#[test]
fn elastic_impacts() {
    completes("restitution_1.0");
}

#[test]
fn tiny_grazing_floor() {
    completes("grazing_floor");
}

#[test]
fn journal_just_touches() {
    completes("grazing_touch");
}

#[test]
fn stick_slip() {
    completes("stick_slip");
}

#[test]
fn wear_deeper_than_the_clearance() {
    // 0.11 mm deep on a 0.02 mm clearance in one rotation, |dh/dθ| / (c + h) = 3.2, ten
    // times the gap's bound.
    stops_where_the_gap_stops_holding("deep_wear");
}

#[test]
fn two_clearance_joints() {
    completes("two_clearance");
}

#[test]
fn pure_coulomb_friction_stalls_into_a_clear_error_fast() {
    // The sign switch of pure Coulomb friction at zero sliding velocity makes the adaptive
    // step collapse (chattering): the crawl guard turns it into an error at its first judged
    // window (2 × CRAWL_WINDOW steps), long before the step limit.
    let r = stability_case("coulomb_0.5", 1, MAX_STEPS).unwrap();
    let failure = r.failure.expect("pure Coulomb friction does not complete");
    for needle in [
        "integration failed at t = ",
        "the run is too slow for its step limit",
        "pure Coulomb friction",
    ] {
        assert!(failure.contains(needle), "{needle}: {failure}");
    }
}
