//! The coupled method of section 5: dynamics, contact, friction and wear advanced together.
//!
//! One run integrates eq. 10 with the adaptive integrator and, after every accepted step:
//! 1. locates the onset of each new contact (the zero of the gap δ(t) on the step's dense
//!    output), captures the normal velocity δ̇⁻ there for eq. 3, truncates the step at the
//!    onset and restarts the integrator from it;
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
//! [`crate::ensemble`]; results are statistics over such ensembles.

use crate::integrator::{
    locate_root, Integrator, IntegratorState, Method, OdeSystem, Stats, Tolerances,
};
use crate::mechanism::Mechanism;
use crate::scene::Scene;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

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
/// coefficient of mild wear, no longer holds. A run stops there (checked after every rotation).
pub const MAX_WEAR_RATIO: f64 = 0.1;

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
    /// Largest penetration of each joint at the accepted step ends (m).
    pub max_penetration: Vec<f64>,
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

/// The mechanism seen as an ODE; a failed right-hand side is kept to report its cause.
struct Dynamics<'a> {
    mechanism: &'a mut Mechanism,
    failure: Option<Error>,
}

impl<'a> Dynamics<'a> {
    fn new(mechanism: &'a mut Mechanism) -> Self {
        Dynamics {
            mechanism,
            failure: None,
        }
    }
}

impl OdeSystem for Dynamics<'_> {
    fn dim(&self) -> usize {
        self.mechanism.state_len()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        if let Err(e) = self.mechanism.rhs(t, y, dy) {
            dy.fill(f64::NAN);
            self.failure.get_or_insert(e);
        }
    }
}

/// Simulates a scene.
pub fn simulate(scene: &Scene) -> Result<RunOutput> {
    simulate_with_progress(scene, |_, _| {})
}

/// Simulates a scene, calling `progress(done, total)` after every driver rotation (`total` is
/// `None` while the run settles to its steady state). Observing a run never changes it: the
/// result is bit-identical to [`simulate`]'s.
pub fn simulate_with_progress(
    scene: &Scene,
    progress: impl FnMut(u32, Option<u32>),
) -> Result<RunOutput> {
    let mut sim = Simulation::start(scene)?;
    sim.run_to_end(progress)?;
    Ok(sim.finish())
}

/// Everything a run carries from one rotation to the next: resuming from it continues the
/// run bit for bit ([`Simulation::checkpoint`], [`Simulation::resume`]).
#[derive(Serialize, Deserialize)]
pub struct Checkpoint {
    /// Rotations completed.
    rotation: u32,
    end_rotation: Option<u32>,
    integrator: IntegratorState,
    gaps: Vec<f64>,
    /// Wear depth per joint per sector (m).
    profiles: Vec<Vec<f64>>,
    /// Onset velocity of each joint's current contact (m/s).
    impact_velocities: Vec<f64>,
    settler: Option<Settler>,
    sampler: Option<Sampler>,
    /// `None` without a wear history (JSON has no infinity).
    next_history: Option<f64>,
    energy_start: Option<(f64, f64)>,
    /// The outputs so far; `wall_time` is the wall time spent so far.
    out: RunOutput,
}

/// A coupled run in progress: the integrator, the contact bookkeeping and the outputs so far.
///
/// A run is advanced one driver rotation at a time ([`Simulation::advance_rotation`]); the
/// integrator is never restarted between rotations, so however a caller drives the run (in one
/// go, rotation by rotation with progress reports, or with long-life wear jumps in between,
/// which do restart it) the step sequence is the same for the same calls.
pub struct Simulation {
    mechanism: Mechanism,
    settings: RunSettings,
    integrator: Integrator,
    period: f64,
    /// The length of the run, known up front unless it first settles to a steady state.
    end_rotation: Option<u32>,
    settler: Option<Settler>,
    sampler: Option<Sampler>,
    history_interval: f64,
    next_history: f64,
    energy_start: Option<(f64, f64)>,
    /// Penetration of each joint at the end of the last accepted step.
    gaps: Vec<f64>,
    y_event: Vec<f64>,
    y_mid: Vec<f64>,
    wears: bool,
    rotation: u32,
    out: RunOutput,
    clock: std::time::Instant,
}

impl Simulation {
    /// Starts a run from state `y0` with the mechanism's current wear profiles and captured
    /// onset velocities.
    pub fn new(mut mechanism: Mechanism, settings: RunSettings, y0: &[f64]) -> Simulation {
        let clock = std::time::Instant::now();
        let n = mechanism.coordinates();
        let joints = mechanism.clearance_joints.len();
        let period = TAU / mechanism.driver.omega.abs();
        let dim = mechanism.state_len();
        let mut integrator = Integrator::new(settings.method, dim, 2 * n, settings.tolerances);
        let settler = settings.settle.map(|s| Settler::new(&mechanism, s, period));
        let end_rotation = settler.is_none().then_some(settings.rotations);
        // Wear history points do not cut steps (that would change the run they describe): a
        // point is taken at the end of the first step that reaches it.
        let history_interval = period / settings.profile_history_per_rotation.max(1) as f64;
        let next_history = if settings.profile_history_per_rotation > 0 {
            history_interval
        } else {
            f64::INFINITY
        };
        let energy_start = settings
            .energy_accounting
            .then(|| mechanical_energy(&mechanism, y0));
        let gaps = (0..joints).map(|k| gap(&mechanism, k, y0)).collect();
        let wears = mechanism.clearance_joints.iter().any(|c| c.wear.is_some());
        integrator.reset(&mut Dynamics::new(&mut mechanism), 0.0, y0);
        let mut sim = Simulation {
            mechanism,
            integrator,
            period,
            end_rotation,
            settler,
            sampler: None,
            history_interval,
            next_history,
            energy_start,
            gaps,
            y_event: vec![0.0; dim],
            y_mid: vec![0.0; dim],
            wears,
            rotation: 0,
            out: RunOutput {
                recording: Recording::default(),
                wear_snapshots: Vec::new(),
                profile_history: Vec::new(),
                final_wear: Vec::new(),
                final_state: Vec::new(),
                stats: Stats::default(),
                max_penetration: vec![f64::NEG_INFINITY; joints],
                impacts: vec![0; joints],
                energy: None,
                settling: None,
                period,
                wall_time: 0.0,
            },
            clock,
            settings,
        };
        sim.sampler = end_rotation.map(|end| sim.recording_window(end));
        sim
    }

    /// The recorder of the `record_rotations` rotations that end at rotation `end`.
    fn recording_window(&self, end: u32) -> Sampler {
        let start = end.saturating_sub(self.settings.record_rotations) as f64 * self.period;
        Sampler::new(
            self.mechanism.state_len(),
            start,
            self.settings.record_interval,
            end as f64 * self.period,
        )
    }

    /// Starts a run of `scene` from its assembled configuration.
    pub fn start(scene: &Scene) -> Result<Simulation> {
        let y0 = scene.mechanism.assemble(&scene.guess)?;
        Ok(Simulation::new(
            scene.mechanism.clone(),
            scene.run.clone(),
            &y0,
        ))
    }

    /// The state to [`Simulation::resume`] this run from, taken between rotations.
    pub fn checkpoint(&self) -> Checkpoint {
        let cjs = &self.mechanism.clearance_joints;
        let mut out = self.out.clone();
        out.wall_time += self.clock.elapsed().as_secs_f64();
        Checkpoint {
            rotation: self.rotation,
            end_rotation: self.end_rotation,
            integrator: self.integrator.state(),
            gaps: self.gaps.clone(),
            profiles: cjs.iter().map(|c| c.profile.depths().to_vec()).collect(),
            impact_velocities: cjs.iter().map(|c| c.impact_velocity).collect(),
            settler: self.settler.clone(),
            sampler: self.sampler.clone(),
            next_history: self.next_history.is_finite().then_some(self.next_history),
            energy_start: self.energy_start,
            out,
        }
    }

    /// Continues the run of `scene` saved in `checkpoint`: the same steps, bit for bit, as
    /// the run that wrote it. Fails if the checkpoint does not fit the scene's mechanism.
    pub fn resume(scene: &Scene, checkpoint: Checkpoint) -> Result<Simulation> {
        let c = checkpoint;
        let mut mechanism = scene.mechanism.clone();
        let misfit = |what: &str| {
            Error::invalid(
                "checkpoint",
                format!("its {what} do not fit the scene"),
                "a checkpoint written by a run of this scene",
            )
        };
        let joints = mechanism.clearance_joints.len();
        if c.profiles.len() != joints
            || c.impact_velocities.len() != joints
            || c.gaps.len() != joints
        {
            return Err(misfit("clearance joints"));
        }
        for ((cj, depths), v) in mechanism
            .clearance_joints
            .iter_mut()
            .zip(&c.profiles)
            .zip(&c.impact_velocities)
        {
            if !cj.profile.set_depths(depths) {
                return Err(misfit("wear profiles"));
            }
            cj.impact_velocity = *v;
        }
        let y: Vec<f64> = c.integrator.y().to_vec();
        if y.len() != mechanism.state_len() {
            return Err(misfit("states"));
        }
        let mut sim = Simulation::new(mechanism, scene.run.clone(), &y);
        sim.integrator
            .restore(c.integrator)
            .map_err(|_| misfit("integrator buffers"))?;
        sim.rotation = c.rotation;
        sim.end_rotation = c.end_rotation;
        sim.gaps = c.gaps;
        sim.settler = c.settler;
        sim.sampler = c.sampler;
        sim.next_history = c.next_history.unwrap_or(f64::INFINITY);
        sim.energy_start = c.energy_start;
        sim.out = c.out;
        Ok(sim)
    }

    /// Driver rotations completed.
    pub fn rotations_done(&self) -> u32 {
        self.rotation
    }

    /// Rotations of the whole run; `None` while it settles to its steady state.
    pub fn total_rotations(&self) -> Option<u32> {
        self.end_rotation
    }

    /// Whether the run has simulated all its rotations.
    pub fn is_finished(&self) -> bool {
        self.end_rotation.is_some_and(|end| self.rotation >= end)
    }

    /// The mechanism with its current wear profiles.
    pub fn mechanism(&self) -> &Mechanism {
        &self.mechanism
    }

    /// Runs the remaining rotations, calling `progress(done, total)` after each.
    pub fn run_to_end(&mut self, mut progress: impl FnMut(u32, Option<u32>)) -> Result<()> {
        while !self.is_finished() {
            self.advance_rotation()?;
            progress(self.rotation, self.end_rotation);
        }
        Ok(())
    }

    /// Deepens every joint's wear profile by `factor` times `increments` (per joint, per
    /// sector), as a long-life block jump does, and restarts the integrator at the current
    /// state: the gap, and so the right-hand side, changed discontinuously.
    pub fn add_wear(&mut self, increments: &[Vec<f64>], factor: f64) {
        for (cj, inc) in self.mechanism.clearance_joints.iter_mut().zip(increments) {
            cj.profile.add_depths(inc, factor);
        }
        let (t, y) = (self.integrator.t(), self.integrator.y().to_vec());
        for (k, g) in self.gaps.iter_mut().enumerate() {
            *g = gap(&self.mechanism, k, &y);
        }
        self.integrator
            .reset(&mut Dynamics::new(&mut self.mechanism), t, &y);
    }

    /// Integrates one driver rotation: accepted steps up to the rotation's end, each followed
    /// by contact-onset location, wear and recording (see the module documentation).
    pub fn advance_rotation(&mut self) -> Result<()> {
        let boundary = (self.rotation + 1) as f64 * self.period;
        loop {
            self.accepted_step(boundary)?;
            if self.integrator.t() >= boundary {
                break;
            }
        }
        self.rotation += 1;
        self.check_wear_depth()?;
        if self
            .settings
            .wear_snapshots
            .binary_search(&self.rotation)
            .is_ok()
        {
            self.out.wear_snapshots.push(WearSnapshot {
                rotation: self.rotation,
                depths: wear_depths(&self.mechanism),
            });
        }
        if self.end_rotation.is_none() {
            if let Some(settled) = self
                .settler
                .as_mut()
                .and_then(|s| s.end_rotation(self.rotation))
            {
                self.out.settling = Some(settled);
                let end = self.rotation + self.settings.rotations;
                self.end_rotation = Some(end);
                self.sampler = Some(self.recording_window(end));
                self.settler = None;
            }
        }
        Ok(())
    }

    /// Stops a run whose wear left the model's validity ([`MAX_WEAR_RATIO`]).
    fn check_wear_depth(&self) -> Result<()> {
        for cj in &self.mechanism.clearance_joints {
            let deepest = cj.profile.depths().iter().cloned().fold(0.0, f64::max);
            let limit = MAX_WEAR_RATIO * cj.r_bearing;
            if deepest > limit {
                return Err(Error::Integration {
                    time: self.integrator.t(),
                    cause: format!(
                        "wear of clearance joint `{}` is {deepest:.3e} m deep after {} rotations, \
                         beyond the wear model's limit of {:.0} % of its bearing radius ({limit:.3e} m): \
                         k/H far too large (a unit error?) or a life far past the bearing's; \
                         `jointwear longlife --until` stops at a stated depth",
                        cj.name,
                        self.rotation,
                        100.0 * MAX_WEAR_RATIO
                    ),
                });
            }
        }
        Ok(())
    }

    /// One accepted step towards `boundary`, cut at the earliest contact onset in it.
    fn accepted_step(&mut self, boundary: f64) -> Result<()> {
        let n = self.mechanism.coordinates();
        let mut sys = Dynamics::new(&mut self.mechanism);
        // A failed right-hand side only matters if the integrator could not step around it.
        if let Err(e) = self.integrator.step(&mut sys, boundary) {
            return Err(sys.failure.unwrap_or(e));
        }
        let (ta, tb) = (self.integrator.t_prev(), self.integrator.t());
        if self.integrator.stats().steps >= self.settings.max_steps {
            return Err(Error::Integration {
                time: tb,
                cause: format!("step limit of {} steps reached", self.settings.max_steps),
            });
        }
        let (mechanism, integrator, y_event) =
            (&mut self.mechanism, &self.integrator, &mut self.y_event);
        // 1. Contact onsets: the earliest gap sign change from free flight to contact.
        let mut onset: Option<(f64, usize)> = None;
        for (k, g_prev) in self.gaps.iter_mut().enumerate() {
            let g = gap(mechanism, k, integrator.y());
            if *g_prev < 0.0 && g >= 0.0 {
                let dense_gap = |t| {
                    integrator.dense(t, y_event);
                    gap(mechanism, k, y_event)
                };
                let t = locate_root(dense_gap, ta, *g_prev, tb, g, 1e-12 * tb.max(1.0));
                if onset.is_none_or(|(t0, _)| t < t0) {
                    onset = Some((t, k));
                }
            }
            *g_prev = g;
        }
        let t_stop = onset.map_or(tb, |(t, _)| t);
        // 2. Wear at the interval midpoint, 3. samples, both over [ta, t_stop].
        if self.wears {
            integrator.dense(0.5 * (ta + t_stop), &mut self.y_mid);
            add_wear(mechanism, &self.y_mid[..2 * n], t_stop - ta);
        }
        if let Some(s) = self.sampler.as_mut() {
            s.sample(
                mechanism,
                integrator,
                ta,
                t_stop,
                &mut self.out.recording,
                y_event,
            )?;
        }
        if let Some(s) = self.settler.as_mut() {
            s.sample(mechanism, integrator, ta, t_stop, y_event);
        }
        if let Some((t, k)) = onset {
            integrator.dense(t, y_event);
            let cs = mechanism.contact_kinematics(k, &y_event[..n], &y_event[n..2 * n]);
            mechanism.clearance_joints[k].impact_velocity = cs.delta_dot;
            self.out.impacts[k] += 1;
            for (j, g) in self.gaps.iter_mut().enumerate() {
                *g = if j == k {
                    0.0
                } else {
                    gap(mechanism, j, y_event)
                };
            }
            self.integrator.record_event();
            self.integrator
                .reset(&mut Dynamics::new(&mut self.mechanism), t, &self.y_event);
        }
        for (m, g) in self.out.max_penetration.iter_mut().zip(&self.gaps) {
            *m = m.max(*g);
        }
        if t_stop >= self.next_history * (1.0 - 1e-12) {
            self.out
                .profile_history
                .push((t_stop, wear_depths(&self.mechanism)));
            self.next_history += self.history_interval;
        }
        Ok(())
    }

    /// The outputs of the run so far.
    pub fn finish(mut self) -> RunOutput {
        let n = self.mechanism.coordinates();
        let y = self.integrator.y().to_vec();
        if let Some(start) = self.energy_start {
            let end = mechanical_energy(&self.mechanism, &y);
            self.out.energy = Some(EnergyAccount {
                driver_work: y[2 * n],
                normal_work: y[2 * n + 1],
                friction_work: y[2 * n + 2],
                mechanical_change: end.0 - start.0,
                elastic_change: end.1 - start.1,
            });
        }
        self.out.stats = self.integrator.stats();
        self.out.final_wear = wear_depths(&self.mechanism);
        self.out.final_state = y;
        self.out.wall_time += self.clock.elapsed().as_secs_f64();
        self.out
    }
}

/// Penetration of joint `k` at state `y`.
fn gap(m: &Mechanism, k: usize, y: &[f64]) -> f64 {
    let n = m.coordinates();
    m.contact_kinematics(k, &y[..n], &y[n..2 * n]).delta
}

fn wear_depths(mechanism: &Mechanism) -> Vec<Vec<f64>> {
    mechanism
        .clearance_joints
        .iter()
        .map(|cj| cj.profile.depths().to_vec())
        .collect()
}

/// (kinetic + gravitational + contact elastic energy, contact elastic energy) at state y.
fn mechanical_energy(mechanism: &Mechanism, y: &[f64]) -> (f64, f64) {
    let n = mechanism.coordinates();
    let (q, v) = (&y[..n], &y[n..2 * n]);
    let elastic = mechanism.contact_energy(q, v);
    (
        mechanism.kinetic_energy(v) + mechanism.potential_energy(q) + elastic,
        elastic,
    )
}

/// Archard wear of an interval of length `dt` evaluated at state `y` (eq. 9).
fn add_wear(mechanism: &mut Mechanism, y: &[f64], dt: f64) {
    let n = mechanism.coordinates();
    for k in 0..mechanism.clearance_joints.len() {
        let Some(law) = mechanism.clearance_joints[k].wear else {
            continue;
        };
        let cs = mechanism.contact_state(k, &y[..n], &y[n..2 * n]);
        if cs.f_n > 0.0 {
            let p = law.pressure(cs.f_n, cs.delta, cs.local_clearance);
            mechanism.clearance_joints[k].profile.add_wear(
                cs.theta,
                &p,
                law.k_over_h,
                cs.v_t.abs() * dt,
            );
        }
    }
}

/// Samples the uniform recording grid from each step's dense output.
#[derive(Clone, Serialize, Deserialize)]
struct Sampler {
    next: usize,
    start: f64,
    interval: f64,
    count: usize,
    dy: Vec<f64>,
}

impl Sampler {
    fn new(dim: usize, start: f64, interval: f64, end: f64) -> Sampler {
        // Grid points t_i = start + i·interval for t_i ≤ end (with a hair of slack for rounding).
        let count = if end > start {
            ((end - start) / interval * (1.0 + 1e-12)).floor() as usize + 1
        } else {
            0
        };
        Sampler {
            next: 0,
            start,
            interval,
            count,
            dy: vec![0.0; dim],
        }
    }

    fn sample(
        &mut self,
        mechanism: &mut Mechanism,
        integrator: &Integrator,
        ta: f64,
        tb: f64,
        rec: &mut Recording,
        y: &mut [f64],
    ) -> Result<()> {
        let n = mechanism.coordinates();
        while self.next < self.count {
            let t = self.start + self.next as f64 * self.interval;
            if t > tb {
                break;
            }
            self.next += 1;
            if t < ta {
                continue;
            }
            integrator.dense(t, y);
            mechanism.rhs(t, y, &mut self.dy)?;
            if rec.accelerations.is_empty() {
                rec.positions = vec![Default::default(); mechanism.bodies().len()];
                rec.accelerations = vec![Default::default(); mechanism.bodies().len()];
                rec.joints = vec![JointTrace::default(); mechanism.clearance_joints.len()];
            }
            rec.time.push(t);
            rec.driver_angle.push(y[3 * mechanism.driver.body + 2]);
            for (b, (pos, acc)) in rec
                .positions
                .iter_mut()
                .zip(&mut rec.accelerations)
                .enumerate()
            {
                for c in 0..3 {
                    pos[c].push(y[3 * b + c]);
                    acc[c].push(self.dy[n + 3 * b + c]);
                }
            }
            for (k, tr) in rec.joints.iter_mut().enumerate() {
                let cs = mechanism.contact_state(k, &y[..n], &y[n..2 * n]);
                let pressure = match mechanism.clearance_joints[k].wear {
                    Some(law) if cs.f_n > 0.0 => (
                        law.pressure(cs.f_n, cs.delta, cs.local_clearance).peak,
                        law.k_over_h,
                    ),
                    _ => (0.0, 0.0),
                };
                tr.ex.push(cs.e.x);
                tr.ey.push(cs.e.y);
                tr.theta.push(cs.theta);
                tr.delta.push(cs.delta);
                tr.normal_force.push(cs.f_n);
                tr.friction_force.push(cs.f_t);
                tr.sliding_velocity.push(cs.v_t);
                tr.pressure.push(pressure.0);
                tr.wear_rate.push(pressure.1 * pressure.0 * cs.v_t.abs());
            }
        }
        Ok(())
    }
}

/// Samples the journal orbit at fixed driver phases to detect a steady state.
#[derive(Clone, Serialize, Deserialize)]
struct Settler {
    criterion: SteadyState,
    period: f64,
    clearances: Vec<f64>,
    /// `[rotation parity][joint][phase]` journal eccentricity.
    orbits: [Vec<Vec<[f64; 2]>>; 2],
    rotation: usize,
    next_phase: usize,
}

impl Settler {
    fn new(mechanism: &Mechanism, criterion: SteadyState, period: f64) -> Settler {
        let joints = mechanism.clearance_joints.len();
        let orbit = vec![vec![[0.0; 2]; ORBIT_PHASES]; joints];
        Settler {
            criterion,
            period,
            clearances: mechanism
                .clearance_joints
                .iter()
                .map(|c| (c.r_bearing - c.r_journal).max(1e-9))
                .collect(),
            orbits: [orbit.clone(), orbit],
            rotation: 0,
            next_phase: 0,
        }
    }

    fn sample(
        &mut self,
        mechanism: &Mechanism,
        integrator: &Integrator,
        ta: f64,
        tb: f64,
        y: &mut [f64],
    ) {
        let n = mechanism.coordinates();
        while self.next_phase < ORBIT_PHASES {
            let t =
                (self.rotation as f64 + self.next_phase as f64 / ORBIT_PHASES as f64) * self.period;
            if t > tb {
                break;
            }
            if t >= ta {
                integrator.dense(t, y);
                for (k, orbit) in self.orbits[self.rotation % 2].iter_mut().enumerate() {
                    let e = mechanism.contact_kinematics(k, &y[..n], &y[n..2 * n]).e;
                    orbit[self.next_phase] = [e.x, e.y];
                }
            }
            self.next_phase += 1;
        }
    }

    /// Called at the end of rotation `done` (1-based): `Some` when settling is over.
    fn end_rotation(&mut self, done: u32) -> Option<Settling> {
        self.rotation += 1;
        self.next_phase = 0;
        if done < 2 {
            return None;
        }
        let [a, b] = &self.orbits;
        let change = a
            .iter()
            .zip(b)
            .zip(&self.clearances)
            .map(|((oa, ob), c)| {
                let ms: f64 = oa
                    .iter()
                    .zip(ob)
                    .map(|(p, q)| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2))
                    .sum();
                (ms / ORBIT_PHASES as f64).sqrt() / c
            })
            .fold(0.0, f64::max);
        let steady = change <= self.criterion.tolerance;
        (steady || done >= self.criterion.max_rotations).then_some(Settling {
            rotations: done,
            orbit_change: change,
            steady,
        })
    }
}
