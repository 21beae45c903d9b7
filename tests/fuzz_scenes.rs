//! A bounded fuzz of the scene reader: mutated scene texts (extreme numbers, lost or repeated
//! lines, flipped characters) must parse, build and assemble to a value or an error, never a
//! panic, and an assembled state must be finite. Deterministic (a fixed-seed xorshift), so a
//! failure names a case that reproduces.

use jointwear::scene::{scene_path, SceneFile};
use std::path::Path;

/// Mutated scenes per shipped scene.
const CASES: usize = 1500;

/// Values that break naive validation.
const EXTREMES: [&str; 14] = [
    "0",
    "-0.0",
    "-1",
    "1e-300",
    "-1e-300",
    "1e300",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "-9223372036854775808",
    "0.5",
    "1e-12",
    "\"x\"",
];

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Byte ranges of the numbers in `text` (digits with signs, dots and exponents).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_alphabetic()) {
            let start = if i > 0 && bytes[i - 1] == b'-' {
                i - 1
            } else {
                i
            };
            let mut end = i;
            while end < bytes.len()
                && (bytes[end].is_ascii_alphanumeric() || b".-+".contains(&bytes[end]))
            {
                end += 1;
            }
            out.push((start, end));
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

fn mutate(text: &str, rng: &mut XorShift) -> String {
    let mut text = text.to_string();
    for _ in 0..1 + rng.below(3) {
        match rng.below(4) {
            0 | 1 => {
                let spans = numbers(&text);
                let (a, b) = spans[rng.below(spans.len())];
                text.replace_range(a..b, EXTREMES[rng.below(EXTREMES.len())]);
            }
            2 => {
                let lines: Vec<&str> = text.lines().collect();
                let k = rng.below(lines.len());
                let mut out: Vec<&str> = lines.clone();
                if rng.below(2) == 0 {
                    out.remove(k);
                } else {
                    out.insert(k, lines[k]);
                }
                text = out.join("\n");
            }
            _ => {
                let at = rng.below(text.len());
                if text.is_char_boundary(at) && text.is_char_boundary(at + 1) {
                    let ch = b"=[],.{}\"#-0e"[rng.below(12)] as char;
                    text.replace_range(at..at + 1, &ch.to_string());
                }
            }
        }
    }
    text
}

#[test]
fn mutated_scenes_give_a_value_or_an_error_never_a_panic() {
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let (mut built, mut assembled) = (0, 0);
    for name in ["standard", "fourbar", "two_clearance"] {
        let path = scene_path(name);
        let base = std::fs::read_to_string(&path).unwrap();
        for case in 0..CASES {
            let text = mutate(&base, &mut rng);
            let result = std::panic::catch_unwind(|| {
                let scene = SceneFile::parse(&text, Path::new(&path))
                    .ok()?
                    .build()
                    .ok()?;
                let y = scene.mechanism.assemble(&scene.guess).ok();
                Some(y.map(|y| y.iter().all(|v| v.is_finite())))
            });
            match result {
                Err(_) => panic!("{name} case {case} panicked on:\n{text}"),
                Ok(Some(Some(finite))) => {
                    assert!(
                        finite,
                        "{name} case {case}: non-finite assembly of:\n{text}"
                    );
                    built += 1;
                    assembled += 1;
                }
                Ok(Some(None)) => built += 1,
                Ok(None) => {}
            }
        }
    }
    // The fuzz reaches the builder and the assembly (1144 and 1141 of 4500 cases), not only
    // the parser's errors.
    assert!(
        built > 800 && assembled > 800,
        "built {built}, assembled {assembled}"
    );
}

/// A log-uniform draw in [lo, hi].
fn log_uniform(rng: &mut XorShift, lo: f64, hi: f64) -> f64 {
    let u = (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
    lo * (hi / lo).powf(u)
}

#[test]
fn runs_of_valid_random_scenes_are_finite_and_within_the_validity_limits() {
    use jointwear::simulation::simulate;
    let mut rng = XorShift(0x2545_f491_4f6c_dd1d);
    let base = SceneFile::read(scene_path("standard")).unwrap();
    let (mut completed, mut failed) = (0, 0);
    for case in 0..32 {
        let mut f = base.clone();
        for b in &mut f.bodies {
            b.mass_kg = log_uniform(&mut rng, 1e-3, 10.0);
        }
        let steel = f.materials.get_mut("steel").unwrap();
        steel.youngs_modulus_gpa = log_uniform(&mut rng, 0.5, 2000.0);
        let c = &mut f.clearance[0];
        // up to a tenth of the 10 mm bearing radius (MAX_CLEARANCE_RATIO)
        c.clearance_mm = log_uniform(&mut rng, 0.001, 1.0);
        c.contact.restitution = log_uniform(&mut rng, 0.3, 1.0);
        f.driver.speed_rpm = -log_uniform(&mut rng, 100.0, 5000.0);
        f.run.rotations = 1;
        f.run.record_rotations = 1;
        f.run.wear_snapshots.clear();
        // Bounds the cost of a case: a run that needs more fails with the step limit.
        f.run.max_steps = 200_000;
        let scene = f.build().expect("valid values build");
        match simulate(&scene) {
            Ok(out) => {
                completed += 1;
                let rec = &out.recording;
                let series = rec.joints.iter().flat_map(|j| {
                    [
                        &j.ex,
                        &j.ey,
                        &j.delta,
                        &j.normal_force,
                        &j.pressure,
                        &j.wear_rate,
                    ]
                });
                assert!(
                    series
                        .flatten()
                        .chain(out.final_wear.iter().flatten())
                        .all(|v| v.is_finite()),
                    "case {case}: non-finite output"
                );
                let cj = &scene.mechanism.clearance_joints[0];
                assert!(
                    out.max_penetration_whole_run[0] <= cj.penetration_limit(),
                    "case {case}: penetration {:e} m",
                    out.max_penetration_whole_run[0]
                );
            }
            Err(jointwear::Error::Integration { .. } | jointwear::Error::Validity { .. }) => {
                failed += 1
            }
            Err(e) => panic!("case {case}: {e}"),
        }
    }
    // Most valid scenes run through (26 of 32 with this seed); a failure is a named
    // integration error. 31 completed before the penetration limit of 20 clearances (at least
    // 1 % of the journal radius): 5 of them, heavy bodies on soft materials with clearances
    // of 1-22 µm, pass it (20 to 99 clearances) and now stop naming it.
    assert!(completed >= 24, "{completed} completed, {failed} failed");
}
