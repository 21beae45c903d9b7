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
//! **Other protocols** ([`Perturbation`]): a disc of another radius, offsets along the journal
//! body's x axis only, the journal centred with its velocity relative to the bearing drawn from
//! a disc, or the journal centred with the integrator's tolerances jittered (members then differ
//! by their numerics, not their state). The default stays the 10 nm disc; the perturbation
//! study (`cargo run --release --bin perturbation`, `data/perturbation_sensitivity.csv`)
//! measures which ensemble statistics depend on the protocol.
//!
//! Members run in parallel (rayon); each depends only on its index and the seed, and results
//! come back in member order, so an ensemble is bit-identical for a given seed whatever the
//! number of threads. The SplitMix64 generator (Steele, Lea and Flood 2014) is written out here
//! rather than taken from a crate because its few lines fix the stream for good: a dependency
//! update can never move a recorded statistic.

use crate::io::format::{number, shift_decimal};
use crate::io::progress::{Cancellation, Counter, Progress};
use crate::mechanism::{ClearanceJoint, Mechanism};
use crate::simulation::Scene;
use crate::simulation::{RunOutput, RunSettings, Simulation};
use crate::{Error, Result};
use nalgebra::Vector2;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Radius of the disc the initial journal offsets are drawn from (m).
pub const OFFSET_RADIUS: f64 = 10e-9;

/// Largest initial velocity of the journal relative to its bearing that a `velocity_<V>um_s`
/// protocol draws (m/s): a million times the study's 10 µm/s and above the contact onsets of
/// the shipped scenes' own motion (a few to a few tens of mm/s in continuous contact), and of
/// the order of the links' own speeds in the slowest (the crank pin moves at 10.5 m/s at 2000
/// r/min, 0.16 m/s at 30 r/min): beyond it a draw is a launch, not a perturbation. Faster draws
/// failed as something else: 1000 m/s as a speed or load far beyond the contact laws, 10²⁴ m/s
/// as dependent joints.
pub const MAX_PERTURBATION_VELOCITY: f64 = 1.0;

/// Members of an ensemble unless asked otherwise: the size the convergence study picks
/// ([`crate::paper::convergence`]: the smallest at which the standard error of every Table 3
/// concordance is at most a fifth of its 0.03 tolerance; at 16 the 0.5 mm case's s-w is not).
pub const DEFAULT_MEMBERS: usize = 32;

/// Seed of the ensembles unless asked otherwise.
pub const DEFAULT_SEED: u64 = 1;

/// How the members of an ensemble differ from the scene's run and from each other. Every
/// draw `u, v ∈ [0, 1)` comes from (seed, member, joint) as in the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Perturbation {
    /// Journal offsets uniform over a disc of this radius (m) in the journal body's frame,
    /// `d = r √u (cos 2πv, sin 2πv)`: the default, with [`OFFSET_RADIUS`].
    Disc(f64),
    /// Journal offsets uniform on `[−r, r]` along the journal body's x axis only (m):
    /// `d = r (2u − 1, 0)`.
    Axis(f64),
    /// The journal centred, its initial velocity relative to the bearing drawn uniformly from a
    /// disc of this radius (m/s, global frame) as the offsets are; the other bodies' velocities
    /// follow from the ideal joints ([`Perturbation::start`]).
    Velocity(f64),
    /// The journal centred (every member starts from the same state), the run's relative and
    /// absolute tolerances multiplied by `1 + s (2u − 1)` (this is `s`): members differ by their
    /// step sequences only.
    Tolerance(f64),
}

impl Default for Perturbation {
    fn default() -> Self {
        Perturbation::Disc(OFFSET_RADIUS)
    }
}

/// Its key ([`Perturbation::key`]): how the command line and the perturbation study name it.
impl std::fmt::Display for Perturbation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.key())
    }
}

/// Time over which the velocity perturbation's offset is differenced (s): the relative
/// velocity `u` is the journal offset `u·τ` of the ideal-joint assembly divided by τ. Short
/// against a rotation (30 ms at 2000 r/min) so the offset stays below a nanometre, long against
/// the assembly's 1e-13 m closure so its rounding moves `u` by under 1e-6 relative.
const VELOCITY_DIFFERENCE_TIME: f64 = 1e-4;

impl Perturbation {
    /// The protocol as the study's CSV names it: `disc_10nm`, `axis_10nm`, `velocity_10um_s`,
    /// `tolerance_1e-3`.
    pub fn key(&self) -> String {
        match *self {
            Perturbation::Disc(r) => format!("disc_{}nm", r * 1e9),
            Perturbation::Axis(r) => format!("axis_{}nm", r * 1e9),
            Perturbation::Velocity(v) => format!("velocity_{}um_s", v * 1e6),
            Perturbation::Tolerance(s) => format!("tolerance_{s:e}"),
        }
    }

    /// The protocol named by `key`, as [`Perturbation::key`] writes it (`disc_10nm`,
    /// `axis_10nm`, `velocity_10um_s`, `tolerance_1e-3`, any positive size): the inverse of
    /// `key`, so a protocol of the perturbation study can be named on the command line. The
    /// number is read as a decimal of the named unit (`10` nm is the double of `10e-9`), so the
    /// protocol is bit for bit the one its key was written from. An error names the key and the
    /// forms accepted.
    pub fn from_key(key: &str) -> Result<Perturbation> {
        let bad = |why: &str| {
            Error::invalid(
                "perturbation",
                format!("`{key}`"),
                format!(
                    "disc_<R>nm, axis_<R>nm, velocity_<V>um_s or tolerance_<S> with R, V > 0 and \
                     0 < S < 1, as the perturbation study names its protocols (default {}){why}",
                    Perturbation::default().key()
                ),
            )
        };
        // `number` in a form's unit, `exponent` its power of ten in SI (`1e1` with an exponent
        // appended does not parse: nm and µm/s sizes are plain decimals)
        let size = |number: &str, exponent: &str| -> Result<f64> {
            match format!("{number}{exponent}").parse::<f64>() {
                Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
                _ => Err(bad(&format!("; `{number}` is not a positive decimal"))),
            }
        };
        // (prefix, unit, the unit's power of ten in SI, the protocol of that size)
        type Form = (
            &'static str,
            &'static str,
            &'static str,
            fn(f64) -> Perturbation,
        );
        const FORMS: [Form; 4] = [
            ("disc_", "nm", "e-9", Perturbation::Disc),
            ("axis_", "nm", "e-9", Perturbation::Axis),
            ("velocity_", "um_s", "e-6", Perturbation::Velocity),
            ("tolerance_", "", "", Perturbation::Tolerance),
        ];
        for (prefix, unit, exponent, make) in FORMS {
            if let Some(number) = key
                .strip_prefix(prefix)
                .and_then(|rest| rest.strip_suffix(unit))
            {
                let x = size(number, exponent)?;
                if prefix == "tolerance_" && x >= 1.0 {
                    return Err(bad("; a tolerance factor of 1 − S ≤ 0 is no tolerance"));
                }
                return Ok(make(x));
            }
        }
        Err(bad(""))
    }

    /// What it does, as a sentence fragment: `journal offsets uniform over a 10 nm disc`.
    pub fn describe(&self) -> String {
        match *self {
            Perturbation::Disc(r) => {
                format!("journal offsets uniform over a {} nm disc", r * 1e9)
            }
            Perturbation::Axis(r) => format!(
                "journal offsets uniform within ±{} nm along one body axis",
                r * 1e9
            ),
            Perturbation::Velocity(v) => format!(
                "journal centred, its initial velocity relative to the bearing uniform over a \
                 {} µm/s disc",
                v * 1e6
            ),
            Perturbation::Tolerance(s) => format!(
                "journal centred, rtol and atol multiplied by a factor uniform in [1 − {s}, 1 + {s}]"
            ),
        }
    }

    /// Checks that the protocol fits `scene`: a disc's or axis's offsets larger than the
    /// default's [`OFFSET_RADIUS`] must stay below the radial clearance of every clearance
    /// joint, or members start with the journal pressed into its bearing (1 mm against 0.02 mm
    /// failed while running, blaming a material). Offsets up to the default's are always
    /// taken: at a zero clearance they start the journal 10 nm into its bearing, deep inside
    /// the small-strain contact laws, as ensembles of such scenes always have. A velocity
    /// protocol's draws must stay at most [`MAX_PERTURBATION_VELOCITY`]. An error names the
    /// field `perturbation`.
    pub fn check(&self, scene: &Scene) -> Result<()> {
        if let Perturbation::Velocity(v) = *self {
            if v > MAX_PERTURBATION_VELOCITY {
                return Err(Error::invalid(
                    "perturbation",
                    self.key(),
                    format!(
                        "a velocity of at most {} µm/s ({MAX_PERTURBATION_VELOCITY} m/s), of \
                         the order of the links' own speeds: a perturbation, not a launch; likely \
                         cause: a speed in another unit than µm/s",
                        number(shift_decimal(MAX_PERTURBATION_VELOCITY, 6))
                    ),
                ));
            }
        }
        let (Perturbation::Disc(r) | Perturbation::Axis(r)) = *self else {
            return Ok(());
        };
        let joints = &scene.mechanism.clearance_joints;
        let misfit = |cj: &&ClearanceJoint| r > OFFSET_RADIUS && r >= cj.given_clearance;
        match joints.iter().find(misfit) {
            None => Ok(()),
            Some(cj) => Err(Error::invalid(
                "perturbation",
                self.key(),
                format!(
                    "offsets of at most {} nm, or below the radial clearance of every \
                     clearance joint (`{}`: {} nm), so that each member's journal starts inside \
                     its bearing; likely cause: a size in another unit than nm",
                    number(shift_decimal(OFFSET_RADIUS, 9)),
                    cj.name,
                    number(shift_decimal(cj.given_clearance, 9))
                ),
            )),
        }
    }

    /// The draws `(u, v)` of each of `joints` clearance joints of `member`.
    fn draws(seed: u64, member: usize, joints: usize) -> impl Iterator<Item = (f64, f64)> {
        let stream = splitmix64(splitmix64(seed) ^ member as u64);
        (0..joints as u64).map(move |j| {
            (
                unit(splitmix64(stream ^ (2 * j))),
                unit(splitmix64(stream ^ (2 * j + 1))),
            )
        })
    }

    /// A point of a disc of radius `r` from the draws `(u, v)`.
    fn in_disc(r: f64, (u, v): (f64, f64)) -> Vector2<f64> {
        let (s, c) = (TAU * v).sin_cos();
        r * u.sqrt() * Vector2::new(c, s)
    }

    /// The initial journal offset `d` of each of `joints` clearance joints of `member` (m, in
    /// the journal body's frame): zero for the protocols that start with the journal centred.
    pub fn offsets(&self, seed: u64, member: usize, joints: usize) -> Vec<Vector2<f64>> {
        Perturbation::draws(seed, member, joints)
            .map(|draw| match *self {
                Perturbation::Disc(r) => Perturbation::in_disc(r, draw),
                Perturbation::Axis(r) => Vector2::new(r * (2.0 * draw.0 - 1.0), 0.0),
                Perturbation::Velocity(_) | Perturbation::Tolerance(_) => Vector2::zeros(),
            })
            .collect()
    }

    /// The mechanism of `scene` with every journal point moved by member `member`'s offset `−d`
    /// in its body: assembled, it puts the journal centre at `e₀ = R(φ_J) d` from the bearing's.
    pub fn mechanism(&self, scene: &Scene, seed: u64, member: usize) -> Mechanism {
        shifted(
            scene,
            &self.offsets(seed, member, scene.mechanism.clearance_joints.len()),
        )
    }

    /// The factor member `member` multiplies `rtol` and `atol` by: uniform in [1 − S, 1 + S]
    /// under [`Perturbation::Tolerance`]`(S)`, exactly 1 under the other protocols.
    pub fn tolerance_factor(&self, seed: u64, member: usize) -> f64 {
        match *self {
            Perturbation::Tolerance(s) => {
                let (u, _) = Perturbation::draws(seed, member, 1)
                    .next()
                    .unwrap_or_default();
                1.0 + s * (2.0 * u - 1.0)
            }
            _ => 1.0,
        }
    }

    /// The run settings member `member` runs with: `settings` with `rtol` and `atol` multiplied
    /// by its [`Perturbation::tolerance_factor`] (so unchanged, bit for bit, under every
    /// protocol but [`Perturbation::Tolerance`]). What its outputs report as simulated.
    pub fn run_settings(&self, settings: &RunSettings, seed: u64, member: usize) -> RunSettings {
        let factor = self.tolerance_factor(seed, member);
        let mut settings = settings.clone();
        settings.tolerances.rtol *= factor;
        settings.tolerances.atol *= factor;
        settings
    }

    /// The run settings ([`Perturbation::run_settings`]) and initial state of member `member`
    /// of `scene` run with `settings`.
    ///
    /// For [`Perturbation::Velocity`] the state's velocities are the assembly's plus
    /// `(q(u·τ) − q(0))/τ`, `q(e)` the positions assembled with the journal at `e` from the
    /// bearing (in the journal body's frame) and τ = 0.1 ms: to first order the ideal-joint
    /// velocity field in which the journal centre moves at `u` relative to the bearing.
    pub fn start(
        &self,
        scene: &Scene,
        settings: &RunSettings,
        seed: u64,
        member: usize,
    ) -> Result<(RunSettings, Vec<f64>)> {
        let settings = self.run_settings(settings, seed, member);
        let y0 = match *self {
            Perturbation::Disc(_) | Perturbation::Axis(_) => {
                self.mechanism(scene, seed, member).assemble(&scene.guess)?
            }
            Perturbation::Velocity(speed) => {
                let joints = scene.mechanism.clearance_joints.len();
                let mut y = scene.mechanism.assemble(&scene.guess)?;
                let n = scene.mechanism.coordinates();
                // u in the global frame, turned into the journal body's frame for the offset
                let moved: Vec<Vector2<f64>> = Perturbation::draws(seed, member, joints)
                    .zip(&scene.mechanism.clearance_joints)
                    .map(|(draw, cj)| {
                        let angle = cj.journal.body.map_or(0.0, |b| y[3 * b + 2]);
                        let u = Perturbation::in_disc(speed, draw);
                        nalgebra::Rotation2::new(-angle) * u * VELOCITY_DIFFERENCE_TIME
                    })
                    .collect();
                let q = shifted(scene, &moved).assemble(&scene.guess)?;
                for i in 0..n {
                    y[n + i] += (q[i] - y[i]) / VELOCITY_DIFFERENCE_TIME;
                }
                y
            }
            Perturbation::Tolerance(_) => scene.mechanism.assemble(&scene.guess)?,
        };
        Ok((settings, y0))
    }
}

/// The mechanism of `scene` with the journal point of clearance joint `j` moved by `−d[j]`.
fn shifted(scene: &Scene, d: &[Vector2<f64>]) -> Mechanism {
    let mut shifted = scene.mechanism.clone();
    for (cj, d) in shifted.clearance_joints.iter_mut().zip(d) {
        cj.journal.local -= d;
    }
    shifted
}

/// Size, seed and protocol of an ensemble.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnsembleSettings {
    /// Members, ≥ 1.
    pub members: usize,
    /// Seed of the perturbations.
    pub seed: u64,
    /// How members are perturbed.
    pub perturbation: Perturbation,
}

impl Default for EnsembleSettings {
    fn default() -> Self {
        EnsembleSettings {
            members: DEFAULT_MEMBERS,
            seed: DEFAULT_SEED,
            perturbation: Perturbation::default(),
        }
    }
}

/// The largest ensemble accepted (a guard against a typo running for days).
pub const MAX_MEMBERS: usize = 10_000;

/// The smallest ensemble accepted: one member has no spread (its sd would read 0, a spread it
/// does not have), and a single run is run as one, not as an ensemble.
pub const MIN_MEMBERS: usize = 2;

/// What an ensemble of `members` of which `unsettled` reached
/// `run.steady_state.max_rotations` unsettled says of them (None if none did): their recorded
/// rotations are no steady state. The program prints it under the ensemble's summary, Python
/// warns with it.
pub fn unsettled_note(unsettled: usize, members: usize) -> Option<String> {
    (unsettled > 0).then(|| {
        format!(
            "not settled: {unsettled} of {members} members reached \
             run.steady_state.max_rotations with their orbit still changing beyond \
             run.steady_state.orbit_tolerance"
        )
    })
}

impl EnsembleSettings {
    /// Checks the member count (the field `members`; the program names its flag instead).
    pub fn validate(&self) -> Result<()> {
        if (MIN_MEMBERS..=MAX_MEMBERS).contains(&self.members) {
            Ok(())
        } else {
            Err(Error::invalid(
                "members",
                self.members,
                format!(
                    "a member count in [{MIN_MEMBERS}, {MAX_MEMBERS}]: the spread of one member \
                     is not zero but unknown; for one run, run the scene without an ensemble \
                     (`jointwear run` without --ensemble, Python's `run()`), or one member of \
                     an ensemble (--member K --seed S, `run(member=K, seed=S)`)"
                ),
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

/// The initial journal offset `d` of each of `joints` clearance joints of `member` under the
/// default protocol (m, in the journal body's frame).
pub fn member_offsets(seed: u64, member: usize, joints: usize) -> Vec<Vector2<f64>> {
    Perturbation::default().offsets(seed, member, joints)
}

/// The mechanism of member `member` of `scene` under the default protocol
/// ([`Perturbation::mechanism`]).
pub fn member_mechanism(scene: &Scene, seed: u64, member: usize) -> Mechanism {
    Perturbation::default().mechanism(scene, seed, member)
}

/// The initial state of member `member` of `scene` under the default protocol: the ideal-joint
/// configuration with every journal centre at its offset `e₀ = R(φ_J) d`.
pub fn member_state(scene: &Scene, seed: u64, member: usize) -> Result<Vec<f64>> {
    member_mechanism(scene, seed, member).assemble(&scene.guess)
}

/// The simulation of member `member` of an ensemble of `scene` run with `settings`, ready to
/// run: what `jointwear run --member` runs and [`run`] runs for every member. Refuses a
/// member outside the ensemble.
pub fn member_simulation(
    scene: &Scene,
    settings: &RunSettings,
    ensemble: &EnsembleSettings,
    member: usize,
) -> Result<Simulation> {
    ensemble.validate()?;
    ensemble.perturbation.check(scene)?;
    if member >= ensemble.members {
        return Err(Error::invalid(
            "member",
            member,
            format!(
                "a member number in [0, {}] (0-based) of an ensemble of {}",
                ensemble.members - 1,
                ensemble.members
            ),
        ));
    }
    let (settings, y0) = ensemble
        .perturbation
        .start(scene, settings, ensemble.seed, member)?;
    Simulation::new(scene.mechanism.clone(), settings, &y0)
}

/// Runs member `member` of an ensemble of `scene` with `settings` ([`member_simulation`]),
/// unless `cancel` asks it to stop ([`Progress::cancelled`]; its counts are not told).
pub fn run_member(
    scene: &Scene,
    settings: &RunSettings,
    ensemble: &EnsembleSettings,
    member: usize,
    cancel: &dyn Progress,
) -> Result<RunOutput> {
    let mut sim = member_simulation(scene, settings, ensemble, member)?;
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
    let all: Vec<usize> = (0..ensemble.members).collect();
    run_members(scene, ensemble, &all, keep, progress)
}

/// [`run`] of the members `members` of the ensemble only (those a resumed ensemble has not
/// finished), in their order: each member is the one [`run`] runs, bit for bit.
pub fn run_members<T: Send>(
    scene: &Scene,
    ensemble: &EnsembleSettings,
    members: &[usize],
    keep: impl Fn(usize, RunOutput) -> T + Sync,
    progress: &dyn Progress,
) -> Result<Vec<T>> {
    ensemble.validate()?;
    let done = Counter::new(progress, members.len());
    members
        .par_iter()
        .map(|&m| {
            let out = run_member(scene, &scene.run, ensemble, m, progress);
            let out =
                out.map_err(|e| e.in_run(&format!("ensemble member {m} (seed {})", ensemble.seed)));
            done.finish_one();
            out.map(|o| keep(m, o))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn protocols_are_read_back_from_their_keys_bit_for_bit() {
        // checked: reading `100` nm as 100.0 * 1e-9 (not the double of 100e-9) fails the 100 nm disc
        for p in [
            Perturbation::default(),
            Perturbation::Disc(1e-9),
            Perturbation::Disc(100e-9),
            Perturbation::Axis(OFFSET_RADIUS),
            Perturbation::Velocity(10e-6),
            Perturbation::Tolerance(1e-3),
        ] {
            assert_eq!(Perturbation::from_key(&p.key()).unwrap(), p, "{}", p.key());
        }
        for bad in [
            "disc",
            "disc_nm",
            "disc_-1nm",
            "disc_0nm",
            "disc_1e1nm",
            "ring_10nm",
            "velocity_10nm",
            "tolerance_1",
            "tolerance_nan",
            "",
        ] {
            let e = Perturbation::from_key(bad).unwrap_err().to_string();
            assert!(
                e.contains("perturbation")
                    && e.contains(&format!("`{bad}`"))
                    && e.contains("disc_10nm"),
                "{e}"
            );
        }
    }

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
