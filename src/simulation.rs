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

use crate::integrator::{locate_root, Integrator, Method, OdeSystem, Stats, Tolerances};
use crate::mechanism::Mechanism;
use crate::scene::Scene;
use crate::{Error, Result};
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
    pub method: Method,
    pub tolerances: Tolerances,
    /// Baumgarte α = β (1/s).
    pub baumgarte: f64,
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyState {
    /// Largest RMS orbit change between rotations, as a fraction of the clearance.
    pub tolerance: f64,
    /// Give up settling after this many rotations (chaotic impact motion never repeats).
    pub max_rotations: u32,
}

/// Orbit samples per rotation for the steady-state test.
pub const ORBIT_PHASES: usize = 360;

/// How a run settled before recording.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settling {
    /// Rotations simulated before the recorded ones.
    pub rotations: u32,
    /// RMS orbit change of the last settling rotation over the clearance.
    pub orbit_change: f64,
    /// Whether the criterion was met (false: `max_rotations` was reached).
    pub steady: bool,
}

/// Time series of one clearance joint on the recording grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointTrace {
    /// Journal centre relative to the bearing centre (m).
    pub ex: Vec<f64>,
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
#[derive(Clone, Debug, Default, PartialEq)]
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
#[derive(Clone, Debug, PartialEq)]
pub struct WearSnapshot {
    pub rotation: u32,
    pub depths: Vec<Vec<f64>>,
}

/// Energy account of a run with `energy_accounting` (J).
#[derive(Clone, Copy, Debug, PartialEq)]
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
#[derive(Clone, Debug)]
pub struct RunOutput {
    pub recording: Recording,
    pub wear_snapshots: Vec<WearSnapshot>,
    /// `(time, depths per joint)` at `profile_history_per_rotation` points per rotation (each at
    /// the end of the first step that reaches it).
    pub profile_history: Vec<(f64, Vec<Vec<f64>>)>,
    /// Final wear depth per joint per sector (m).
    pub final_wear: Vec<Vec<f64>>,
    /// State at the end.
    pub final_state: Vec<f64>,
    pub stats: Stats,
    /// Largest penetration of each joint at the accepted step ends (m).
    pub max_penetration: Vec<f64>,
    /// Contact onsets of each joint.
    pub impacts: Vec<u64>,
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
    let mut mechanism = scene.mechanism.clone();
    let y0 = mechanism.assemble(&scene.guess)?;
    run(&mut mechanism, &scene.run, y0)
}

/// Simulates from state `y0` with the mechanism's current wear profiles.
pub fn run(mechanism: &mut Mechanism, settings: &RunSettings, y0: Vec<f64>) -> Result<RunOutput> {
    let clock = std::time::Instant::now();
    let n = mechanism.coordinates();
    let joints = mechanism.clearance_joints.len();
    let period = TAU / mechanism.driver.omega.abs();
    let dim = mechanism.state_len();
    let mut integrator = Integrator::new(settings.method, dim, 2 * n, settings.tolerances);
    // The length of the run is known up front unless it first settles to a steady state.
    let mut settler = settings.settle.map(|s| Settler::new(mechanism, s, period));
    let mut end_rotation = settler.is_none().then_some(settings.rotations);
    let window = |end: u32| {
        let start = (end - settings.record_rotations) as f64 * period;
        Sampler::new(dim, start, settings.record_interval, end as f64 * period)
    };
    let mut sampler = end_rotation.map(window);
    // Wear history points do not cut steps (that would change the run they describe): a point
    // is taken at the end of the first step that reaches it.
    let history_interval = period / settings.profile_history_per_rotation.max(1) as f64;
    let mut next_history = if settings.profile_history_per_rotation > 0 {
        history_interval
    } else {
        f64::INFINITY
    };
    let mut out = RunOutput {
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
    };
    let energy_start = settings
        .energy_accounting
        .then(|| mechanical_energy(mechanism, &y0));
    let gap =
        |m: &Mechanism, k: usize, y: &[f64]| m.contact_kinematics(k, &y[..n], &y[n..2 * n]).delta;
    let mut gaps: Vec<f64> = (0..joints).map(|k| gap(mechanism, k, &y0)).collect();
    let mut y_event = vec![0.0; dim];
    let mut y_mid = vec![0.0; dim];
    let wears = mechanism.clearance_joints.iter().any(|c| c.wear.is_some());
    let mut rotation = 0u32;
    integrator.reset(
        &mut Dynamics {
            mechanism,
            failure: None,
        },
        0.0,
        &y0,
    );
    while end_rotation.is_none_or(|end| rotation < end) {
        let boundary = (rotation + 1) as f64 * period;
        let mut sys = Dynamics {
            mechanism,
            failure: None,
        };
        // A failed right-hand side only matters if the integrator could not step around it.
        if let Err(e) = integrator.step(&mut sys, boundary) {
            return Err(sys.failure.unwrap_or(e));
        }
        let (ta, tb) = (integrator.t_prev(), integrator.t());
        if integrator.stats().steps >= settings.max_steps {
            return Err(Error::Integration {
                time: tb,
                cause: format!("step limit of {} steps reached", settings.max_steps),
            });
        }
        // 1. Contact onsets: the earliest gap sign change from free flight to contact.
        let mut onset: Option<(f64, usize)> = None;
        for (k, g_prev) in gaps.iter_mut().enumerate() {
            let g = gap(mechanism, k, integrator.y());
            if *g_prev < 0.0 && g >= 0.0 {
                let dense_gap = |t| {
                    integrator.dense(t, &mut y_event);
                    gap(mechanism, k, &y_event)
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
        if wears {
            integrator.dense(0.5 * (ta + t_stop), &mut y_mid);
            add_wear(mechanism, &y_mid[..2 * n], t_stop - ta);
        }
        if let Some(s) = sampler.as_mut() {
            s.sample(
                mechanism,
                &integrator,
                ta,
                t_stop,
                &mut out.recording,
                &mut y_event,
            )?;
        }
        if let Some(s) = settler.as_mut() {
            s.sample(mechanism, &integrator, ta, t_stop, &mut y_event);
        }
        if let Some((t, k)) = onset {
            integrator.dense(t, &mut y_event);
            let cs = mechanism.contact_kinematics(k, &y_event[..n], &y_event[n..2 * n]);
            mechanism.clearance_joints[k].impact_velocity = cs.delta_dot;
            out.impacts[k] += 1;
            for (j, g) in gaps.iter_mut().enumerate() {
                *g = if j == k {
                    0.0
                } else {
                    gap(mechanism, j, &y_event)
                };
            }
            integrator.record_event();
            integrator.reset(
                &mut Dynamics {
                    mechanism,
                    failure: None,
                },
                t,
                &y_event,
            );
        }
        for (m, g) in out.max_penetration.iter_mut().zip(&gaps) {
            *m = m.max(*g);
        }
        if t_stop >= next_history * (1.0 - 1e-12) {
            out.profile_history.push((t_stop, wear_depths(mechanism)));
            next_history += history_interval;
        }
        if onset.is_some() || tb < boundary {
            continue;
        }
        rotation += 1;
        if settings.wear_snapshots.binary_search(&rotation).is_ok() {
            out.wear_snapshots.push(WearSnapshot {
                rotation,
                depths: wear_depths(mechanism),
            });
        }
        if end_rotation.is_none() {
            if let Some(settled) = settler.as_mut().and_then(|s| s.end_rotation(rotation)) {
                out.settling = Some(settled);
                end_rotation = Some(rotation + settings.rotations);
                sampler = end_rotation.map(window);
                settler = None;
            }
        }
    }
    let y = integrator.y().to_vec();
    if let Some(start) = energy_start {
        let end = mechanical_energy(mechanism, &y);
        out.energy = Some(EnergyAccount {
            driver_work: y[2 * n],
            normal_work: y[2 * n + 1],
            friction_work: y[2 * n + 2],
            mechanical_change: end.0 - start.0,
            elastic_change: end.1 - start.1,
        });
    }
    out.stats = integrator.stats();
    out.final_wear = wear_depths(mechanism);
    out.final_state = y;
    out.wall_time = clock.elapsed().as_secs_f64();
    Ok(out)
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
