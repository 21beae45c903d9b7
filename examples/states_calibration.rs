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
//! * Quantised quantities: the share of [`DRAWS`] samples of counts (Poisson, binomial,
//!   Bernoulli) divided by what they are counted over that the rule splits, without the
//!   quantum ([`States::of`]) and with it ([`States::of_quantised`]); and two states of a
//!   count with empty levels between them, split exactly, without and with the quantum.

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

/// A Poisson count of mean `mean` (Knuth's product of uniforms; means up to a few tens).
fn poisson(u: &mut Uniform, mean: f64) -> f64 {
    let limit = (-mean).exp();
    let (mut count, mut product) = (0.0, u.next());
    while product > limit {
        count += 1.0;
        product *= u.next();
    }
    count
}

/// A binomial count of `trials` trials of probability `p`.
fn binomial(u: &mut Uniform, trials: usize, p: f64) -> f64 {
    (0..trials).map(|_| f64::from(u8::from(u.next() < p))).sum()
}

/// A quantity on a lattice: a count drawn by `count`, divided by `over` (the inverse of its
/// quantum).
struct Lattice {
    name: &'static str,
    count: fn(&mut Uniform) -> f64,
    over: f64,
}

/// The counts the rule must not split, as the program meets them: contact onsets per rotation
/// over 2 or 10 recorded rotations (Poisson rates of 0.5 and 3 a rotation, and 6-8 onsets in 2
/// rotations, the four-bar's), members in a mode (Bernoulli, 1 in 4).
const LATTICES: [Lattice; 6] = [
    Lattice {
        name: "poisson 0.5/rot over 2",
        count: |u| poisson(u, 1.0),
        over: 2.0,
    },
    Lattice {
        name: "poisson 3/rot over 2",
        count: |u| poisson(u, 6.0),
        over: 2.0,
    },
    Lattice {
        name: "poisson 3/rot over 10",
        count: |u| poisson(u, 30.0),
        over: 10.0,
    },
    Lattice {
        name: "6 + binomial(2, 0.5) over 2",
        count: |u| 6.0 + binomial(u, 2, 0.5),
        over: 2.0,
    },
    Lattice {
        name: "binomial(4, 0.5) over 2",
        count: |u| binomial(u, 4, 0.5),
        over: 2.0,
    },
    Lattice {
        name: "bernoulli 0.25",
        count: |u| binomial(u, 1, 0.25),
        over: 1.0,
    },
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
    println!(
        "False splits of quantised samples, % of {DRAWS} draws (without the quantum / with it):"
    );
    for n in SIZES {
        let cells: Vec<String> = (LATTICES.iter().enumerate())
            .map(|(f, lattice)| {
                let mut u = Uniform(3000 * n as u64 + f as u64);
                let (mut before, mut after) = (0, 0);
                for _ in 0..DRAWS {
                    let v: Vec<f64> = (0..n)
                        .map(|_| (lattice.count)(&mut u) / lattice.over)
                        .collect();
                    before += usize::from(States::of(&v).split());
                    after += usize::from(States::of_quantised(&v, 1.0 / lattice.over).split());
                }
                let name = lattice.name;
                format!("{name} {:.1} / {:.1}", percent(before), percent(after))
            })
            .collect();
        println!("  {n:2} members: {}", cells.join(", "));
    }
    println!(
        "Two states of onsets over 2 rotations, the smaller at 3 a rotation (Poisson), split \
         exactly, % of {DRAWS} draws (without the quantum / with it):"
    );
    for (n, few) in [(16, 4), (32, 5)] {
        let cells: Vec<String> = [0.0, 0.25, 0.5, 1.0]
            .iter()
            .map(|&low_rate| {
                let mut u = Uniform(n as u64 * 104_729 + (100.0 * low_rate) as u64);
                let (mut before, mut after) = (0, 0);
                for _ in 0..DRAWS {
                    let v: Vec<f64> = (0..n)
                        .map(|i| poisson(&mut u, 2.0 * if i < few { 3.0 } else { low_rate }) / 2.0)
                        .collect();
                    let exact = |s: &States| {
                        s.states.last().map(|s| &s.members[..])
                            == Some(&(0..few).collect::<Vec<_>>()[..])
                    };
                    before += usize::from(exact(&States::of(&v)));
                    after += usize::from(exact(&States::of_quantised(&v, 0.5)));
                }
                format!(
                    "the others at {low_rate}/rot {:.1} / {:.1}",
                    percent(before),
                    percent(after)
                )
            })
            .collect();
        println!("  {few}/{n}: {}", cells.join(", "));
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
