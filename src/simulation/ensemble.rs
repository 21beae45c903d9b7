//! Ensembles: a result of this project is a statistic over runs, not one trajectory.
//!
//! Impacts in a clearance joint are chaotic, and eq. 3 remembers the normal velocity at the
//! onset of each contact, so one run's numbers depend on rounding: a nanometre of initial
//! offset, a tolerance or a summation order moves them by as much as the physics they are meant
//! to show. An ensemble runs `N` members of one scene, each from the scene's assembled
//! configuration with every clearance joint's journal centre displaced by
//!
//! ```text
//! d = r √u (cos 2πv, sin 2πv)   in the journal body's frame,   r = OFFSET_RADIUS = 10 nm,
//! ```
//!
//! uniform over a disc, with `u, v ∈ [0, 1)` drawn by SplitMix64 from (seed, member, joint); the
//! journal centre starts at `e₀ = R(φ_J) d` from the bearing centre (global frame, φ_J the
//! journal body's initial angle).
//! Why this perturbation: the paper starts with the journal centred, a position no
//! measurement or manufacturing process fixes to better than micrometres; 10 nm is 5·10⁻⁴ of the
//! smallest clearance studied (20 µm) and a thousandth of a ground surface's roughness, so it
//! is physically negligible, yet it is above the integrator's tolerance, so members take
//! independent step sequences. Where the motion is not chaotic (the journal resting on the
//! bottom of the bearing at 30 r/min) the offsets wash out: the members' deepest wear agrees to
//! 1e-3 after ten rotations (`tests/ensemble.rs`) and to 1e-4 after forty (its sd over its mean
//! in `data/golden/ensemble.toml`); where it is chaotic, they sample the attractor. The offset enters through the assembly (the journal point is moved in its
//! body before the ideal-joint configuration is solved), so every ideal joint holds exactly.
//!
//! Members run in parallel (rayon); each depends only on its index and the seed, and results
//! come back in member order, so an ensemble is bit-identical for a given seed whatever the
//! number of threads. The SplitMix64 generator (Steele, Lea and Flood 2014) is written out here
//! rather than taken from a crate because its few lines fix the stream for good: a dependency
//! update can never move a recorded statistic.

use crate::io::progress::{Cancellation, Counter, Progress};
use crate::mechanism::Mechanism;
use crate::simulation::Scene;
use crate::simulation::{RunOutput, RunSettings, Simulation};
use crate::{Error, Result};
use nalgebra::Vector2;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Radius of the disc the initial journal offsets are drawn from (m).
pub const OFFSET_RADIUS: f64 = 10e-9;

/// Members of an ensemble unless asked otherwise: the size the convergence study picks
/// ([`crate::paper::convergence`]: the smallest at which the standard error of every Table 3
/// concordance is at most a fifth of its 0.03 tolerance; at 16 the 0.5 mm case's s-w is not).
pub const DEFAULT_MEMBERS: usize = 32;

/// Seed of the ensembles unless asked otherwise.
pub const DEFAULT_SEED: u64 = 1;

/// Size and seed of an ensemble.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnsembleSettings {
    /// Members, ≥ 1.
    pub members: usize,
    /// Seed of the initial offsets.
    pub seed: u64,
}

impl Default for EnsembleSettings {
    fn default() -> Self {
        EnsembleSettings {
            members: DEFAULT_MEMBERS,
            seed: DEFAULT_SEED,
        }
    }
}

/// The largest ensemble accepted (a guard against a typo running for days).
pub const MAX_MEMBERS: usize = 10_000;

impl EnsembleSettings {
    /// Checks the member count (the field `members`; the program names its flag instead).
    pub fn validate(&self) -> Result<()> {
        if (1..=MAX_MEMBERS).contains(&self.members) {
            Ok(())
        } else {
            Err(Error::invalid(
                "members",
                self.members,
                format!("a member count in [1, {MAX_MEMBERS}]"),
            ))
        }
    }
}

/// SplitMix64's output function of state `z`.
fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from the top 53 bits.
fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 / (1u64 << 53) as f64
}

/// The initial journal offset `d` of each of `joints` clearance joints of `member` (m, in the
/// journal body's frame).
pub fn member_offsets(seed: u64, member: usize, joints: usize) -> Vec<Vector2<f64>> {
    let stream = splitmix64(splitmix64(seed) ^ member as u64);
    (0..joints as u64)
        .map(|j| {
            let u = unit(splitmix64(stream ^ (2 * j)));
            let v = unit(splitmix64(stream ^ (2 * j + 1)));
            let (s, c) = (TAU * v).sin_cos();
            OFFSET_RADIUS * u.sqrt() * Vector2::new(c, s)
        })
        .collect()
}

/// The mechanism of `scene` with every journal point moved by member `member`'s offset `−d`
/// in its body: assembled, it puts the journal centre at `e₀ = R(φ_J) d` from the bearing's.
pub fn member_mechanism(scene: &Scene, seed: u64, member: usize) -> Mechanism {
    let joints = scene.mechanism.clearance_joints.len();
    let mut shifted = scene.mechanism.clone();
    for (cj, d) in shifted
        .clearance_joints
        .iter_mut()
        .zip(member_offsets(seed, member, joints))
    {
        cj.journal.local -= d;
    }
    shifted
}

/// The initial state of member `member` of `scene`: the ideal-joint configuration with every
/// journal centre at its offset `e₀ = R(φ_J) d` (see the module documentation).
pub fn member_state(scene: &Scene, seed: u64, member: usize) -> Result<Vec<f64>> {
    member_mechanism(scene, seed, member).assemble(&scene.guess)
}

/// Runs member `member` of `scene` with `settings` from [`member_state`], unless `cancel`
/// asks it to stop ([`Progress::cancelled`]; its counts are not told).
pub fn run_member(
    scene: &Scene,
    settings: &RunSettings,
    seed: u64,
    member: usize,
    cancel: &dyn Progress,
) -> Result<RunOutput> {
    let y0 = member_state(scene, seed, member)?;
    let mut sim = Simulation::new(scene.mechanism.clone(), settings.clone(), &y0)?;
    sim.run_to_end(&Cancellation(cancel))?;
    Ok(sim.finish())
}

/// Runs the members of an ensemble of `scene` with the scene's run settings in parallel,
/// maps each output by `keep(member, output)` (so a large output need not be held), and
/// returns them in member order, telling `progress` the members finished. If members fail,
/// one of their errors is returned, naming its member.
pub fn run<T: Send>(
    scene: &Scene,
    ensemble: &EnsembleSettings,
    keep: impl Fn(usize, RunOutput) -> T + Sync,
    progress: &dyn Progress,
) -> Result<Vec<T>> {
    ensemble.validate()?;
    let done = Counter::new(progress, ensemble.members);
    (0..ensemble.members)
        .into_par_iter()
        .map(|m| {
            let out = run_member(scene, &scene.run, ensemble.seed, m, progress);
            let out = out.map_err(|e| match e {
                Error::Integration { time, cause } => Error::Integration {
                    time,
                    cause: format!("ensemble member {m} (seed {}): {cause}", ensemble.seed),
                },
                e => e,
            });
            done.finish_one();
            out.map(|o| keep(m, o))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_seeded_distinct_and_inside_the_disc() {
        let a = member_offsets(1, 0, 2);
        assert_eq!(a, member_offsets(1, 0, 2));
        assert_ne!(a, member_offsets(2, 0, 2));
        assert_ne!(a, member_offsets(1, 1, 2));
        assert_ne!(a[0], a[1]);
        let all: Vec<_> = (0..1000).flat_map(|m| member_offsets(7, m, 1)).collect();
        assert!(all.iter().all(|d| d.norm() <= OFFSET_RADIUS));
        // uniform over the disc: a quarter of the points within half the radius
        let inner = all
            .iter()
            .filter(|d| d.norm() <= 0.5 * OFFSET_RADIUS)
            .count();
        assert!((200..300).contains(&inner), "{inner}");
        // and in every quadrant
        let q1 = all.iter().filter(|d| d.x > 0.0 && d.y > 0.0).count();
        assert!((200..300).contains(&q1), "{q1}");
    }
}
