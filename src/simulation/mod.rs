//! The coupled method of section 5: dynamics, contact, friction and wear advanced together.
//!
//! One run integrates eq. 10 with the adaptive integrator and, after every accepted step:
//! 1. locates the onset of each new contact (the zero of the gap δ(t) on the step's dense
//!    output, also beside an extremum of δ inside the step: a lift-off and landing within one
//!    step, [`crate::ode`]'s events), captures the normal velocity δ̇⁻ there for eq. 3,
//!    truncates the step at the onset and restarts the integrator from it;
//! 2. adds the step's Archard wear (eq. 9) to the bearing profile, evaluated at the step
//!    midpoint: `Δs = |v_t| Δt`, pressure from the joint's pressure model; the worn profile
//!    enters the gap of every later step (the paper's "coupled iterative" update);
//! 3. samples the recorded rotations on a uniform time grid from the dense output.
//!
//! Only what the scene asks for is computed: wear only for joints with a wear model,
//! samples only in the recorded rotations, energy quadratures only when requested.
//!
//! A run's answer does not depend on how it is driven: progress reports, recording, wear
//! snapshots, wear history and settling only read the dense output, and the integrator runs
//! through rotation ends without a restart ([`Simulation`]). Impact dynamics are chaotic, so
//! anything that changes the step sequence (a restart, a tolerance, an initial offset of a
//! nanometre) moves a single trajectory by as much as the ensemble spread of
//! [`crate::simulation::ensemble`]; results are statistics over such ensembles.

pub mod checkpoint;
pub mod ensemble;
pub mod folder;
pub mod journal;
pub mod longlife;
pub mod picture;
mod record;
mod run;
pub mod summary;

pub use checkpoint::Checkpoint;
pub use run::Simulation;

use crate::io::format::quantity;
use crate::io::progress::{Progress, Silent};
use crate::laws::wear::WearProfile;
use crate::mechanism::{ClearanceJoint, Mechanism};
use crate::ode::{Method, Stats, Tolerances};
use crate::scene::StepControlSpec;
use crate::Result;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// A validated scene in SI units, ready to simulate: what a run is made of. Scene files
/// are read, checked and converted to it by [`crate::scene`].
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene's title, for figures and reports.
    pub title: String,
    /// The mechanism (immutable description).
    pub mechanism: Mechanism,
    /// Initial guess of the coordinates, `(x, y, φ)` per body (m, rad).
    pub guess: Vec<f64>,
    /// How to run it.
    pub run: RunSettings,
}

/// Run settings of a scene (SI).
#[derive(Clone, Debug, PartialEq)]
pub struct RunSettings {
    /// Driver rotations to simulate.
    pub rotations: u32,
    /// Number of final rotations recorded as time series.
    pub record_rotations: u32,
    /// Recording grid spacing (s).
    pub record_interval: f64,
    /// Rotation counts after which the wear profile is saved (sorted, unique).
    pub wear_snapshots: Vec<u32>,
    /// Integration method.
    pub method: Method,
    /// Step-size controller of an adaptive method (`run.step_control`).
    pub step_control: StepControlSpec,
    /// Error tolerances and step bounds.
    pub tolerances: Tolerances,
    /// Baumgarte α = β (1/s).
    pub baumgarte: f64,
    /// Integrate driver, normal-contact and friction work for the energy balance.
    pub energy_accounting: bool,
    /// Settle to a steady state first; then `rotations` more are simulated.
    pub settle: Option<SteadyState>,
    /// Wear profiles saved per rotation (0: none), for the wear history of figure 7.
    pub profile_history_per_rotation: u32,
    /// Accepted steps after which the run fails instead of going on (a guard against runs
    /// that crawl, e.g. a stiff contact resolved by ever smaller steps).
    pub max_steps: u64,
}

impl RunSettings {
    /// The largest step a run takes (s) and the scene key that sets it: `run.fixed_step_s` of
    /// `rk4`, else `run.max_step_s`.
    pub fn largest_step(&self) -> (&'static str, f64) {
        match self.method {
            Method::Rk4 { step } => ("run.fixed_step_s", step),
            _ => ("run.max_step_s", self.tolerances.max_step),
        }
    }
}

/// Steady-state criterion: the journal orbit of each clearance joint, sampled at
/// [`ORBIT_PHASES`] driver phases per rotation, changes from one rotation to the next by an RMS
/// of at most `tolerance` times the radial clearance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SteadyState {
    /// Largest RMS orbit change between rotations, as a fraction of the clearance.
    pub tolerance: f64,
    /// Give up settling after this many rotations (chaotic impact motion never repeats).
    pub max_rotations: u32,
}

/// Deepest wear, as a fraction of the bearing radius, that the wear model describes: the gap
/// takes the worn bearing as a circle whose radius grows by h(θ) along its own normal, with the
/// contact normal along the journal's eccentricity; past a tenth of the radius the worn bore is
/// no longer a slightly perturbed circle and that geometry, like the constant Archard
/// coefficient of mild wear, no longer holds. A run stops there (checked after every step).
pub const MAX_WEAR_RATIO: f64 = 0.1;

/// The allowance on a bound of [`MAX_WEAR_RATIO`] times a radius for the rounding of the ratio
/// or the product: a clearance of exactly a tenth of the radius as written (0.14 in 1.4,
/// whose quotient rounds to 0.10000000000000002) is within it.
pub const RATIO_ROUNDING: f64 = 1.0 + 4.0 * f64::EPSILON;

/// The steepest worn profile, |dh/dθ| / (c + h), that the paper's gap `δ = |e| − c − h(θ)`
/// describes (θ the eccentricity's angle, the normal force along e/|e|). That gap is the
/// deepest overlap of journal and worn bore only while the profile is flat on the clearance's
/// scale: the deepest overlap lies about |h′|/(c + h) rad off θ, and the gap reads it short by
/// about half its square times c + h. Off that, the normal force is not the gradient of an
/// energy and does work around the journal's orbits. Measured on the standard scene at
/// k/H = 5e-12 1/Pa (energy accounting, per rotation, two members): that work is 1-3 % of
/// the driver's up to 0.3, 5-9 % at 0.5-0.6 and 30-100 % past 0.85; past 1, 2 of 176 members
/// ran away into a whirl of 1e6 N. The paper's runs end at 0.17 or less. A run stops past 0.3
/// (checked at every rotation's end; a long-life prediction's blocks stop short of it). The
/// README's validity limits give the measurements in full.
pub const MAX_ECCENTRICITY_SLOPE: f64 = 0.3;

/// `(|dh/dθ| / (c + h), angle in rad)` of `profile` worn into clearance joint `cj` when it
/// passes [`MAX_ECCENTRICITY_SLOPE`] (a NaN profile passes it too); `None` within it, and for
/// a joint that does not wear.
pub fn too_steep(cj: &ClearanceJoint, profile: &WearProfile) -> Option<(f64, f64)> {
    cj.wear.as_ref()?;
    let (ratio, angle) = profile.steepest(cj.clearance());
    (ratio > MAX_ECCENTRICITY_SLOPE || ratio.is_nan()).then_some((ratio, angle))
}

/// Why clearance joint `cj` worn to `profile` is [`too_steep`], `when` saying when (`after
/// simulated driver rotation 3`): how steep, where and how deep, against the bound; the cause
/// of the [`crate::Error::Validity`] a run stops with. `None` within the bound.
pub fn steepness_cause(cj: &ClearanceJoint, profile: &WearProfile, when: &str) -> Option<String> {
    let (ratio, angle) = too_steep(cj, profile)?;
    Some(format!(
        "the worn bearing of clearance joint `{}` has |dh/dθ| / (c + h) = {ratio:.4} at {:.1} \
         deg {when} (deepest wear {} on a radial clearance of {}), above the \
         {MAX_ECCENTRICITY_SLOPE} up to which the paper's gap δ = |e| − c − h(θ) describes the \
         worn bore (README, validity limits)",
        cj.name,
        angle.to_degrees(),
        quantity(profile.deepest() * 1e3, "mm"),
        quantity(cj.given_clearance * 1e3, "mm"),
    ))
}

/// The deepest wear (m) the wear model describes in joint `cj` ([`MAX_WEAR_RATIO`]).
pub fn wear_limit(cj: &ClearanceJoint) -> f64 {
    MAX_WEAR_RATIO * cj.r_bearing
}

/// `rotations` of a run whose caller decides when it ends (long-life prediction simulates
/// blocks of rotations until it has extrapolated to its target): a bound, not an end, so no
/// pace is projected to it; only a crawl (under [`CRAWL_FRACTION`] of a period per window) or
/// `run.max_steps` stops such a run.
pub const OPEN_ENDED: u32 = u32::MAX;

/// Accepted steps over which a run's pace is judged, at every multiple of it from the second
/// on (the first holds the start's transient): a run that at the pace of its last window
/// would not finish within `run.max_steps` stops there, naming the steps it would need and
/// the cause, instead of crawling for minutes into the limit.
pub const CRAWL_WINDOW: u64 = 100_000;

/// Least share of a driver period that a chattering [`CRAWL_WINDOW`] (mean step under
/// [`CHATTER_STEP_RATIO`] of the largest) must advance; only a window under it is judged by
/// its pace, as a sticking start may slip and speed up. Measured per window: stick-slip
/// friction (`data/scenes/stability/stick_slip.toml`) sticks for its first 2e5 steps at
/// 2.3e-8 s, 7.8 % of a period, a pace that would need 5e7 steps for its 40 rotations, then
/// slips and finishes in 5.5e5; pure Coulomb friction (`coulomb_0.5.toml`) never slips and
/// advances 0.045 % in its first judged window, 0.05 % to 1.3 % later.
pub const CRAWL_FRACTION: f64 = 0.01;

/// Mean step of a [`CRAWL_WINDOW`], as a fraction of the largest step, below which the
/// integrator is taken to chatter (a switching force, judged by [`CRAWL_FRACTION`]) rather
/// than to follow smooth dynamics at a pace it holds (a driver too slow for its steps, judged
/// by its pace alone): pure Coulomb friction chatters at 1e-7 of `run.max_step_s` and
/// stick-slip's start at 2.3e-5, the standard scene at 0.01 r/min steps at 0.24 of it, and
/// the slowest smooth window of a shipped scene (stick-slip once it slips, restitution 0.1's
/// impacts at 2000 r/min; measured over up to 300 rotations) at 2.1e-3.
pub const CHATTER_STEP_RATIO: f64 = 1e-3;

/// Share of a closed contact's oscillation period (2π √(m/k)) from which a run's mean step is
/// the contact's time scale rather than a switching force's chatter: the standard scene at
/// 0.01 r/min and below steps 0.48 of it (2.4e-4 s against 5.0e-4 s) while resting in
/// contact, pure Coulomb friction (`coulomb_0.5.toml`) 1.3e-6 of it (1.0e-10 s against
/// 7.7e-5 s) in sticking contact.
pub const CONTACT_STEP_SHARE: f64 = 1e-3;

/// Orbit samples per rotation for the steady-state test.
pub const ORBIT_PHASES: usize = 360;

/// How a run settled before recording.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settling {
    /// Rotations simulated before the recorded ones.
    pub rotations: u32,
    /// RMS orbit change of the last settling rotation over the clearance.
    pub orbit_change: f64,
    /// Whether the criterion was met (false: `max_rotations` was reached).
    pub steady: bool,
}

impl Settling {
    /// What a run that reached `run.steady_state.max_rotations` unsettled says of it (None if
    /// it settled): its recorded rotations are no steady state. The program prints it under
    /// the run's summary, Python warns with it.
    pub fn unsettled_note(&self) -> Option<String> {
        (!self.steady).then(|| {
            format!(
                "not settled: after {} settling rotations (run.steady_state.max_rotations) the \
                 orbit still changed by {} of the clearance per rotation, above \
                 run.steady_state.orbit_tolerance; the recorded rotations are not a steady state",
                self.rotations,
                crate::io::format::number(self.orbit_change)
            )
        })
    }
}

/// Time series of one clearance joint on the recording grid.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrace {
    /// Journal centre relative to the bearing centre (m).
    pub ex: Vec<f64>,
    /// See `ex`.
    pub ey: Vec<f64>,
    /// Contact angle in the bearing frame (rad).
    pub theta: Vec<f64>,
    /// Penetration (m), negative in free flight.
    pub delta: Vec<f64>,
    /// Normal force (N).
    pub normal_force: Vec<f64>,
    /// Friction force on the journal along the tangent (N).
    pub friction_force: Vec<f64>,
    /// Relative sliding velocity (m/s).
    pub sliding_velocity: Vec<f64>,
    /// Peak contact pressure (Pa), zero out of contact or without a wear model.
    pub pressure: Vec<f64>,
    /// Wear rate dh/dt at the contact centre (m/s): k/H · P · |v_t|.
    pub wear_rate: Vec<f64>,
}

/// Time series on the recording grid.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Recording {
    /// Time (s).
    pub time: Vec<f64>,
    /// Driver angle (rad).
    pub driver_angle: Vec<f64>,
    /// Positions `(x, y, φ)` of every body (m, rad), indexed `[body][component]`.
    pub positions: Vec<[Vec<f64>; 3]>,
    /// Accelerations `(ẍ, ÿ, φ̈)` of every body (m/s², rad/s²), indexed `[body][component]`.
    pub accelerations: Vec<[Vec<f64>; 3]>,
    /// Per clearance joint.
    pub joints: Vec<JointTrace>,
}

impl Recording {
    /// The time series as named columns, in the order of `jointwear run`'s `timeseries.csv`
    /// (documented in the `README.txt` it writes beside it): time, driver angle, per clearance
    /// joint `J.ex_m` … `J.wear_rate_m_s` (the contact angle in degrees in [0, 360), the
    /// bearing frame of the wear profile), per body `B.ax_m_s2`, `B.ay_m_s2`,
    /// `B.alpha_rad_s2`. With nothing recorded every column is empty, the names complete.
    pub fn columns(&self, mechanism: &Mechanism) -> Vec<(String, Cow<'_, [f64]>)> {
        let mut columns: Vec<(String, Cow<[f64]>)> = vec![
            ("time_s".into(), Cow::from(&self.time[..])),
            ("driver_angle_rad".into(), Cow::from(&self.driver_angle[..])),
        ];
        for (k, cj) in mechanism.clearance_joints.iter().enumerate() {
            let trace = self.joints.get(k);
            let of = |f: fn(&JointTrace) -> &Vec<f64>| -> Cow<'_, [f64]> {
                trace.map_or(Cow::Borrowed(&[]), |t| Cow::Borrowed(&f(t)[..]))
            };
            // θ in [0, 2π) as degrees in [0, 360): a θ just below 2π may round up to 360.
            let theta = of(|t| &t.theta);
            let degrees = theta.iter().map(|t| {
                let d = t.to_degrees();
                if d >= 360.0 {
                    d - 360.0
                } else {
                    d
                }
            });
            let series: [(&str, Cow<[f64]>); 9] = [
                ("ex_m", of(|t| &t.ex)),
                ("ey_m", of(|t| &t.ey)),
                ("contact_angle_deg", Cow::Owned(degrees.collect())),
                ("penetration_m", of(|t| &t.delta)),
                ("normal_force_n", of(|t| &t.normal_force)),
                ("friction_force_n", of(|t| &t.friction_force)),
                ("sliding_velocity_m_s", of(|t| &t.sliding_velocity)),
                ("pressure_pa", of(|t| &t.pressure)),
                ("wear_rate_m_s", of(|t| &t.wear_rate)),
            ];
            for (name, data) in series {
                columns.push((format!("{}.{name}", cj.name), data));
            }
        }
        for (b, body) in mechanism.bodies().iter().enumerate() {
            for (c, name) in ["ax_m_s2", "ay_m_s2", "alpha_rad_s2"].iter().enumerate() {
                let data = self.accelerations.get(b).map_or(&[][..], |acc| &acc[c][..]);
                columns.push((format!("{}.{name}", body.name), Cow::from(data)));
            }
        }
        columns
    }
}

/// Wear depth of every sector of every joint after a number of rotations (m).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WearSnapshot {
    /// Rotations completed.
    pub rotation: u32,
    /// Depth per joint per sector (m).
    pub depths: Vec<Vec<f64>>,
}

/// Energy account of a run with `energy_accounting` (J).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnergyAccount {
    /// Work done by the driver.
    pub driver_work: f64,
    /// Work of the normal contact forces on the system (elastic + damping).
    pub normal_work: f64,
    /// Work of the friction forces (≤ 0).
    pub friction_work: f64,
    /// Change of kinetic + gravitational + contact elastic energy.
    pub mechanical_change: f64,
    /// Change of the contact elastic energy alone.
    pub elastic_change: f64,
}

impl EnergyAccount {
    /// Energy dissipated by contact damping: −(normal work) − elastic energy change.
    pub fn damping_loss(&self) -> f64 {
        -self.normal_work - self.elastic_change
    }

    /// driver work − (mechanical change + damping + friction losses), relative to driver work
    /// (or to the mechanical change when the driver does no net work).
    pub fn residual(&self) -> f64 {
        let losses = self.damping_loss() - self.friction_work;
        let r = self.driver_work - (self.mechanical_change + losses);
        r / self
            .driver_work
            .abs()
            .max(self.mechanical_change.abs())
            .max(f64::MIN_POSITIVE)
    }
}

/// Everything a run produces.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunOutput {
    /// Time series of the recorded rotations.
    pub recording: Recording,
    /// Profiles at the scene's snapshot rotations.
    pub wear_snapshots: Vec<WearSnapshot>,
    /// `(time, depths per joint)` at `profile_history_per_rotation` points per rotation (each at
    /// the end of the first step that reaches it).
    pub profile_history: Vec<(f64, Vec<Vec<f64>>)>,
    /// Final wear depth per joint per sector (m).
    pub final_wear: Vec<Vec<f64>>,
    /// State at the end.
    pub final_state: Vec<f64>,
    /// Integrator work counters of the whole run.
    pub stats: Stats,
    /// Largest penetration of each joint over the accepted steps of the whole run (m), at their
    /// ends and at a maximum inside them on the dense output ([`crate::ode::Integrator::
    /// peak_inside`]: searched where the ends' tangents reach above the largest so far, a bound
    /// for a concave peak): the start-up transient and
    /// settling included, unlike the recorded rotations' statistics (README, windows).
    pub max_penetration_whole_run: Vec<f64>,
    /// Contact onsets of each joint.
    pub impacts: Vec<u64>,
    /// Energy balance, with `energy_accounting`.
    pub energy: Option<EnergyAccount>,
    /// Settling phase, for runs with [`RunSettings::settle`].
    pub settling: Option<Settling>,
    /// Driver rotation period (s).
    pub period: f64,
    /// Wall-clock time of the run (s).
    pub wall_time: f64,
}

impl RunOutput {
    /// Rotations simulated from the start under `run`: its rotations, plus the settling
    /// rotations of a run that settles.
    pub fn rotations_simulated(&self, run: &RunSettings) -> u32 {
        self.settling.map_or(0, |s| s.rotations) + run.rotations
    }
}

/// Simulates a scene.
pub fn simulate(scene: &Scene) -> Result<RunOutput> {
    simulate_with_progress(scene, &Silent)
}

/// Simulates a scene, telling `progress` the driver rotations done after each (the total is
/// unknown while the run settles to its steady state). Observing a run never changes it: the
/// result is bit-identical to [`simulate`]'s.
pub fn simulate_with_progress(scene: &Scene, progress: &dyn Progress) -> Result<RunOutput> {
    let mut sim = Simulation::start(scene)?;
    sim.run_to_end(progress)?;
    Ok(sim.finish())
}
