//! The calibration of the states rule (`jointwear::analysis::states`), rerun:
//! `cargo run --release --example states_calibration` (about a second; seeded, so every run
//! prints the same numbers).
//!
//! * False splits: the share of [`DRAWS`] unimodal samples (normal, uniform, lognormal
//!   σ = 0.5, Student t₃, exponential) of each size that the rule splits into two states,
//!   beside the share the pooled bound alone splits (the rule before the narrow side's bound).
//! * Detection: two normal states whose sds differ tenfold or thirtyfold, the smaller state
//!   (4 of 16, 5 of 32 members) the narrow one or the wide one, their means apart by a number
//!   of the narrow state's sds: the share of draws split exactly between the two, by the rule
//!   and by the pooled bound alone.

use jointwear::analysis::states::{gap_over_spread, States};

/// Samples per size and distribution.
const DRAWS: usize = 10_000;

/// Ensemble sizes checked for false splits.
const SIZES: [usize; 6] = [4, 8, 16, 20, 30, 32];

/// Uniform numbers in (0, 1): SplitMix64's output, top 53 bits.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut x = self.0;
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((x ^ (x >> 31)) >> 11) as f64 / (1u64 << 53) as f64 + 1e-17
    }

    /// A standard normal number (Box-Muller).
    fn normal(&mut self) -> f64 {
        (-2.0 * self.next().ln()).sqrt() * (std::f64::consts::TAU * self.next()).cos()
    }
}

/// One number drawn from a distribution.
type Draw = fn(&mut Uniform) -> f64;

/// The unimodal distributions the rule must not split, by name.
const FAMILIES: [(&str, Draw); 5] = [
    ("normal", Uniform::normal),
    ("uniform", Uniform::next),
    ("lognormal", |u| (0.5 * u.normal()).exp()),
    ("t3", |u| {
        let chi2: f64 = (0..3).map(|_| u.normal().powi(2)).sum();
        u.normal() / (chi2 / 3.0).sqrt()
    }),
    ("exponential", |u| -u.next().ln()),
];

/// Percentage of `count` in [`DRAWS`].
fn percent(count: usize) -> f64 {
    100.0 * count as f64 / DRAWS as f64
}

fn main() {
    println!("False splits of unimodal samples, % of {DRAWS} draws (pooled bound alone / rule):");
    for n in SIZES {
        let cells: Vec<String> = (FAMILIES.iter().enumerate())
            .map(|(f, (name, draw))| {
                let mut u = Uniform(1000 * n as u64 + f as u64);
                let (mut pooled, mut rule) = (0, 0);
                for _ in 0..DRAWS {
                    let v: Vec<f64> = (0..n).map(|_| draw(&mut u)).collect();
                    let s = States::of(&v);
                    pooled += usize::from(s.gap_ratio > gap_over_spread(n));
                    rule += usize::from(s.split());
                }
                format!("{name} {:.1} / {:.1}", percent(pooled), percent(rule))
            })
            .collect();
        println!("  {n:2} members: {}", cells.join(", "));
    }
    println!("Two normal states split exactly, % of {DRAWS} draws (pooled bound alone / rule):");
    for (n, few) in [(16, 4), (32, 5)] {
        for ratio in [10.0, 30.0] {
            for narrow_few in [true, false] {
                let cells: Vec<String> = [2.0, 3.0, 4.0, 6.0]
                    .iter()
                    .map(|&apart| {
                        let mut u = Uniform(n as u64 * 7919 + ratio as u64 + apart as u64);
                        let (few_sd, many_sd) = if narrow_few {
                            (1.0, ratio)
                        } else {
                            (ratio, 1.0)
                        };
                        let (mut pooled, mut rule) = (0, 0);
                        for _ in 0..DRAWS {
                            let v: Vec<f64> = (0..n)
                                .map(|i| match i < few {
                                    true => few_sd * u.normal(),
                                    false => apart * ratio + many_sd * u.normal(),
                                })
                                .collect();
                            let s = States::of(&v);
                            let exact = s.states[0].members.len() == few
                                && s.states[0].members.iter().all(|&i| i < few);
                            rule += usize::from(exact);
                            pooled += usize::from(exact && s.gap_ratio > gap_over_spread(n));
                        }
                        format!(
                            "{:.0} sd {:.1} / {:.1}",
                            apart * ratio,
                            percent(pooled),
                            percent(rule)
                        )
                    })
                    .collect();
                println!(
                    "  {few}/{n} {} (sds 1:{ratio}), apart by: {}",
                    if narrow_few { "narrow" } else { "wide" },
                    cells.join(", ")
                );
            }
        }
    }
}
