//! The valid ranges of scene values and the budgets a run must fit in (steps, recorded
//! bytes): each check names the field, the value, the range and the likely cause.

use super::SceneFile;
use crate::io::format::exact;
use crate::io::format::number as terminal;
use crate::laws::friction::FrictionModel;
use crate::mechanism::{ClearanceJoint, Mechanism};
use crate::ode::Method;
use crate::simulation::folder::joint_file_part;
use crate::simulation::{Scene, MAX_WEAR_RATIO};
use crate::{Error, Result};
use std::path::Path;

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Checks that `value` is finite and inside `[lo, hi]`.
pub(super) fn check(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            exact(value),
            format!("a finite number in [{}, {}]", terminal(lo), terminal(hi)),
        ))
    }
}

/// Checks that `value` is finite, `> lo` and `≤ hi`.
pub(super) fn check_open(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    if value.is_finite() && value > lo && value <= hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            exact(value),
            format!("a finite number in ({}, {}]", terminal(lo), terminal(hi)),
        ))
    }
}

/// A validity limit of the models: the range of a scene value and why values outside it are
/// refused (the README's "Validity limits" table states the same).
pub struct Limit {
    /// Smallest valid value.
    pub lo: f64,
    /// Largest valid value.
    pub hi: f64,
    /// Why values outside are refused, and their likely cause.
    pub why: &'static str,
}

/// Body mass (kg).
pub const MASS_KG: Limit = Limit {
    lo: 1e-6,
    hi: 1e6,
    why: "a body lighter than 1 mg turns newtons of contact force into accelerations the \
          integrator cannot resolve (1e-300 kg gave infinite penetration); likely cause: a \
          mass in the wrong unit",
};

/// Moment of inertia about the centre of mass (kg m²).
pub const INERTIA_KG_M2: Limit = Limit {
    lo: 1e-12,
    hi: 1e6,
    why: "below 1 mg at 1 mm radius of gyration the angular accelerations of contact torques \
          cannot be resolved; likely cause: an inertia in g mm² or another unit",
};

/// Largest radius of gyration √(I/m) of a body, as a multiple of the mechanism's size (the
/// diagonal of the box holding its points at their initial positions, the farthest point from a
/// body's centre of mass, or the largest bearing's diameter, whichever is largest: a journal
/// free in a bearing at the origin has all its points there). A flywheel ten times the size of
/// the linkage is not a joint-wear scene; an inertia typed in kg mm² (10⁶ times its value in
/// kg m², so a radius of gyration 1000 times too long) or in g cm² (10⁷) is.
pub const MAX_GYRATION_PER_SIZE: f64 = 10.0;

/// Checks every body's radius of gyration against [`MAX_GYRATION_PER_SIZE`] times the size of
/// the mechanism `f` describes (its values already checked to be finite and in range).
pub(super) fn check_gyration(f: &SceneFile) -> Result<()> {
    let mut farthest: f64 = 0.0;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut hold = |p: [f64; 2]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    };
    f.ground.points_mm.values().for_each(|&p| hold(p));
    for b in &f.bodies {
        let (s, c) = b.angle_deg.to_radians().sin_cos();
        hold(b.position_mm);
        for p in b.points_mm.values() {
            farthest = farthest.max(p[0].hypot(p[1]));
            hold([
                b.position_mm[0] + c * p[0] - s * p[1],
                b.position_mm[1] + s * p[0] + c * p[1],
            ]);
        }
    }
    let bearing = (f.clearance.iter()).fold(0.0, |d: f64, c| d.max(2.0 * c.bearing_radius_mm));
    let size = (hi[0] - lo[0])
        .hypot(hi[1] - lo[1])
        .max(farthest)
        .max(bearing)
        * 1e-3;
    if size <= 0.0 {
        // every point at one place and no bearing: no length to compare with
        return Ok(());
    }
    let limit = MAX_GYRATION_PER_SIZE * size;
    match f
        .bodies
        .iter()
        .enumerate()
        .find(|(_, b)| (b.inertia_kg_m2 / b.mass_kg).sqrt() > limit)
    {
        None => Ok(()),
        Some((i, b)) => Err(Error::invalid(
            format!("bodies[{i}].inertia_kg_m2"),
            exact(b.inertia_kg_m2),
            format!(
                "at most {} kg m² for its mass of {} kg: its radius of gyration √(I/m), {} m, \
                 is over {MAX_GYRATION_PER_SIZE} times the mechanism's size of {} m; likely \
                 cause: an inertia in kg mm² or g cm² instead of kg m²",
                terminal(b.mass_kg * limit * limit),
                terminal(b.mass_kg),
                terminal((b.inertia_kg_m2 / b.mass_kg).sqrt()),
                terminal(size)
            ),
        )),
    }
}

/// Largest Archard coefficient k/H (1/Pa) of a scene's wear law (and of `longlife --k-over-h`).
pub const MAX_K_OVER_H_PER_PA: f64 = 1e-6;

/// Young's modulus (GPa).
pub const YOUNGS_MODULUS_GPA: Limit = Limit {
    lo: 0.1,
    hi: 1e4,
    why: "the contact laws are linear-elastic small-strain models of metals, ceramics and \
          engineering polymers; below 0.1 GPa (elastomers) the penetration reaches the \
          clearance (1e-300 GPa gave 115 mm); likely cause: a modulus in Pa or MPa",
};

/// Bearing radius R_i (mm).
pub const BEARING_RADIUS_MM: Limit = Limit {
    lo: 0.1,
    hi: 1e4,
    why: "a pin thinner than 0.2 mm is outside the rigid-pin contact model; likely cause: a \
          radius in m",
};

/// Bearing length L (mm).
pub const BEARING_LENGTH_MM: Limit = Limit {
    lo: 0.1,
    hi: 1e4,
    why: "the contact pressure and the wear rate grow as 1/L: below 0.1 mm they are unbounded \
          (1e-300 mm wore the bearing away at once, leaving zero force); likely cause: a \
          length in m",
};

/// Coefficient of restitution c_e of a contact.
pub const RESTITUTION: Limit = Limit {
    lo: 0.1,
    hi: 1.0,
    why: "the dissipation laws are elastic contact with hysteresis damping, checked against \
          the restitution they achieve for c_e in [0.1, 0.99] (the contact_laws study); below \
          0.1 an impact is nearly plastic, which they do not describe, and the damping of \
          gonthier, flores and hu-guo grows as 1/c_e (flores: 14 at 0.1, 1600 at 0.001, where \
          the standard scene ran 60 times slower; 1e-300 gave infinite penetration)",
};

/// Floor of a contact's onset velocity in the damping term (m/s).
pub const GRAZING_VELOCITY_M_S: Limit = Limit {
    lo: 1e-9,
    hi: 10.0,
    why: "the floor stands in for the onset velocity of a contact that begins with almost \
          none, and the damping grows as 1/floor: a nanometre a second is already resting \
          contact, and the smallest floor the stability study runs; at 1e-100 m/s the damping \
          of a grazing contact overflowed (infinite penetration, blamed on the linkage)",
};

/// Absolute tolerance of the integrator, in the units of the state (m, rad, m/s, rad/s).
pub const ABSOLUTE_TOLERANCE: Limit = Limit {
    lo: 1e-20,
    hi: 1.0,
    why: "below 1e-20 of the state's units it is finer than the spacing of the doubles of any \
          coordinate beyond 1e-4 m or rad (2.2e-20), so no step can meet it, and the initial \
          step's scaled norm overflows (1e-200 stopped at t = 0 with a step size underflow); \
          likely cause: a typo in the exponent",
};

/// Largest step of a run (s): `run.max_step_s`, `run.fixed_step_s` of `rk4`.
pub const MAX_STEP_S: f64 = 1.0;

/// Largest step limit of a run, `run.max_steps`.
pub const MAX_RUN_STEPS: u64 = 10_000_000_000;

/// Slowest driver (|r/min|): 6e-9, at which one rotation (1e10 s) takes [`MAX_RUN_STEPS`]
/// steps of [`MAX_STEP_S`]. No run settings can finish a slower rotation (the step budget,
/// [`Scene::check_step_budget`]); before, -1e-300 r/min was refused naming
/// `run.record_interval_s`.
pub const MIN_SPEED_RPM: f64 = 60.0 / (MAX_RUN_STEPS as f64 * MAX_STEP_S);

/// Largest |coordinate| of a point or position guess (mm).
pub const COORDINATE_MM: f64 = 1e6;

/// Initial guess of a body's angle (deg): a hundred turns either way. A guess some turns on
/// assembles that many turns on (the same pose), but the radians of a far larger one keep too
/// few digits for the assembly: 1e8 deg (1.7e6 rad, its doubles 2.3e-10 rad apart) failed,
/// blaming a loop that "stays open by 4e-9 mm" at a revolute.
pub const BODY_ANGLE_DEG: Limit = Limit {
    lo: -36000.0,
    hi: 36000.0,
    why: "an angle guess turns on the same pose every 360 deg, and beyond a hundred turns its \
          radians keep too few digits to assemble the loop; likely cause: an angle in another \
          unit, or a typo in the exponent",
};

/// Largest |gravity| component (m/s²): 1000 g.
pub const GRAVITY_M_S2: f64 = 1e4;

/// Smallest clearance over bearing radius, c/R_i, of the Hertz-based laws (Hertz line-contact
/// pressure, Lankarani-Nikravesh force). Hertz treats the surfaces as half-spaces, so its
/// contact half-width must stay small against the radius; for conformal cylinders
/// `b/R_i = sqrt((8/π)(p̄/E*)/(c/R_i))` with `p̄ = F/(2 R_i L)` the projected bearing
/// pressure. At c/R_i = 1e-4 a typical steel bearing (p̄/E* ≈ 1e-5) already has
/// b/R_i ≈ 0.5, and as c → 0 the effective radius R* = R_i R_j / c is unbounded: at zero
/// clearance the half-width is infinite and the pressure zero (435 N of force, no wear).
pub const MIN_HERTZ_CLEARANCE_RATIO: f64 = 1e-4;

/// Largest radial clearance over bearing radius, c/R_i: the wear model's limit
/// ([`MAX_WEAR_RATIO`]). The contact laws are those of a journal conforming to its bore
/// (internal cylinders of nearly equal radii), and the wear model holds to wear of a tenth of
/// the radius, the depth that doubles a clearance of a tenth (`longlife`'s default limit,
/// which a wider joint could not reach). A wider joint is a loose pin: 9.9 mm in a 10 mm
/// bearing passed validation and failed while running (its 0.1 mm journal penetrated beyond
/// its radius's tenth), 9999 mm in 10 m gave a disconnected linkage with exit 0.
pub const MAX_CLEARANCE_RATIO: f64 = MAX_WEAR_RATIO;

/// Largest scene file (bytes): the largest shipped scene is a few kB, so a file of more is
/// almost surely not a scene, and reading it whole would only fill the memory.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// Longest title (bytes): it is drawn above every figure, where 400 bytes already fill
/// several lines (a 1e6-byte title made `check` take 1.5 GB to lay out).
pub const MAX_TITLE_BYTES: usize = 400;

/// Longest name of a body, point, material or clearance joint (bytes). Names become column
/// and file names (`wear_<joint>.csv`, at most 83 bytes with this limit, within every file
/// system's 255), so a longer one failed only when the outputs were written, after simulating.
pub const MAX_NAME_BYTES: usize = 64;

/// Checks that `name` has 1 to [`MAX_NAME_BYTES`] bytes.
pub(super) fn check_name(field: &str, name: &str) -> Result<()> {
    if (1..=MAX_NAME_BYTES).contains(&name.len()) {
        return Ok(());
    }
    Err(Error::invalid(
        field,
        format!("a name of {} bytes", name.len()),
        format!(
            "a name of 1 to {MAX_NAME_BYTES} bytes (names become column and file names; likely \
             cause: a description where a short name belongs)"
        ),
    ))
}

/// Checks that no two clearance joints write the same files: their [`joint_file_part`]s
/// must differ ignoring case (file systems of macOS and Windows ignore it), or one joint's
/// profile would silently replace the other's.
pub(super) fn check_joint_file_names(names: &[&str]) -> Result<()> {
    let parts: Vec<String> = names
        .iter()
        .map(|n| joint_file_part(n).to_lowercase())
        .collect();
    for (j, part) in parts.iter().enumerate() {
        if let Some(i) = parts[..j].iter().position(|p| p == part) {
            return Err(Error::invalid(
                format!("clearance[{j}].name"),
                format!("\"{}\"", names[j]),
                format!(
                    "a name whose output files differ from those of clearance[{i}] \
                     (\"{}\"): both would write wear_{}.csv (file names keep letters, digits, - \
                     and _, turn every other character into _, and are compared ignoring case)",
                    names[i],
                    joint_file_part(names[j])
                ),
            ));
        }
    }
    Ok(())
}

/// Checks that `value` is finite and within `limit`, saying why if not.
pub(super) fn within(field: &str, value: f64, limit: &Limit) -> Result<f64> {
    if value.is_finite() && value >= limit.lo && value <= limit.hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            exact(value),
            format!(
                "a finite number in [{}, {}]: {}",
                terminal(limit.lo),
                terminal(limit.hi),
                limit.why
            ),
        ))
    }
}

/// Checks that every coordinate is finite and within ±[`COORDINATE_MM`].
pub(super) fn check_coordinates(field: &str, values: &[f64]) -> Result<()> {
    match values
        .iter()
        .find(|v| !(v.is_finite() && v.abs() <= COORDINATE_MM))
    {
        Some(v) => Err(Error::invalid(
            field,
            exact(*v),
            format!(
                "finite coordinates within ±{} mm (1 km; likely cause: a coordinate in µm or \
                 another unit)",
                terminal(COORDINATE_MM)
            ),
        )),
        None => Ok(()),
    }
}

/// Memory budget of what a run records (bytes): 2 GiB of `f64`s. A run holds its time series,
/// wear history and wear snapshots in memory until it ends, growing them by doubling (briefly
/// twice the size), and writes them as CSV text about three times larger; 2 GiB keeps that within an
/// ordinary workstation, where a larger estimate is almost always an interval in the wrong
/// unit, and fails at validation instead of on a failed allocation deep into the run.
pub const RECORD_BUDGET_BYTES: f64 = 2.0 * GIB;

/// Largest `run.atol` of an adaptive method per metre of the smallest radial clearance
/// ([`Scene::check_tolerances`]): a tenth, so that MATLAB's default 1e-6, which the accuracy
/// study runs on the paper's 0.02 mm clearance (a twentieth), passes.
pub const ATOL_PER_CLEARANCE: f64 = 0.1;

/// The penetration of a journal in its bearing per metre of bearing radius that
/// [`Scene::check_tolerances`] takes where it exceeds the radial clearance: a journal with
/// (almost) no clearance moves in its bearing only by its penetration, of the order of 1e-4 of
/// the radius at the loads of metal bearings (2.3 µm in the 10 mm bearing of the zero-clearance
/// stability scene, at 723 N). Without it a joint without clearance had no length to resolve:
/// atol 1 m ran that scene with exit 0 reporting 1.58e6 N (1e-3 m: 1134 N; 1e-5 m: 722 N), and
/// a clearance of 1e-17 mm asked for an atol below the smallest valid one.
pub const PENETRATION_PER_RADIUS: f64 = 1e-4;

/// Fewest samples per driver rotation of a recording (`run.record_interval_s` at most the
/// driver period over this): one per 10 degrees of driver angle, so that each of the 4 to 5
/// contact onsets a rotation of the standard joint gets about 8 samples (the shipped scenes
/// record 3000 a rotation, the oracle and checkpoint tests 300). A coarser grid does not show
/// the motion it summarises: an interval of 1 s on the standard scene's 30 ms period recorded
/// only t = 0 (the centred start) and reported 0 N, -20 µm and 0 % in contact of a journal in
/// continuous contact, exit 0; 0.01 s (10 ms for 10 µs) sampled the same three driver angles
/// every rotation and called the continuous contact free flight.
pub const MIN_RECORD_SAMPLES_PER_ROTATION: f64 = 36.0;

/// Recorded `f64`s per time-series row: time and driver angle, position and acceleration
/// (x, y, φ) per body, and per clearance joint e_x, e_y, θ, δ, F_n, F_t, v_t, p and dh/dt.
pub(super) fn record_columns(mechanism: &Mechanism) -> usize {
    2 + 6 * mechanism.bodies().len() + 9 * mechanism.clearance_joints.len()
}

impl Scene {
    /// Reads, validates and converts a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene> {
        SceneFile::read(path)?.build()
    }

    /// The driver's period (s).
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.mechanism.driver.omega.abs()
    }

    /// The samples of the recorded rotations: `run.record_rotations` driver periods sampled
    /// every `run.record_interval_s`, both ends included (a settling run's window may hold one
    /// sample fewer, as its start rounds).
    pub fn recorded_samples(&self) -> f64 {
        (f64::from(self.run.record_rotations) * self.period() / self.run.record_interval).floor()
            + 1.0
    }

    /// Checks that the run can finish within `run.max_steps` at all: its largest step (the
    /// fixed step of `rk4`) needs at least `rotations` × period / step steps. A smaller step
    /// would crawl into the step limit (1e-300 s took 78 s to fail); it fails here at once.
    pub fn check_step_budget(&self) -> Result<()> {
        let run = &self.run;
        let (field, step) = run.largest_step();
        let period = self.period();
        let needed = run.rotations as f64 * period / step;
        if needed <= run.max_steps as f64 {
            return Ok(());
        }
        Err(Error::invalid(
            field,
            format!("{step:e} s"),
            format!(
                "a step with which {} rotations of {period:.4e} s can finish within \
                 run.max_steps = {}: they need at least {needed:.3e} steps of it; likely cause: \
                 a step in the wrong unit (seconds), or raise run.max_steps",
                run.rotations, run.max_steps
            ),
        ))
    }

    /// Checks that an adaptive method's absolute tolerance resolves the smallest length a
    /// journal moves by in its bearing: `run.atol` at most [`ATOL_PER_CLEARANCE`] of a joint's
    /// radial clearance or, where larger, of its penetration ([`PENETRATION_PER_RADIUS`] of its
    /// bearing radius). The error is controlled to about `atol` in the journal's position, so
    /// a coarser one leaves contact onsets and micrometre penetrations to chance: rtol 0.01
    /// with atol 1e-4 m, five times the standard clearance, turned its continuous contact into
    /// free flight with 119 impacts a rotation and 20 kN against 4.5 and 3.2 kN, exit 0. `rk4`
    /// does not use it.
    pub fn check_tolerances(&self) -> Result<()> {
        let run = &self.run;
        if matches!(run.method, Method::Rk4 { .. }) {
            return Ok(());
        }
        let length =
            |c: &ClearanceJoint| (c.given_clearance).max(PENETRATION_PER_RADIUS * c.r_bearing);
        let smallest =
            (self.mechanism.clearance_joints.iter()).min_by(|a, b| length(a).total_cmp(&length(b)));
        let Some(joint) = smallest else {
            return Ok(());
        };
        let largest = ATOL_PER_CLEARANCE * length(joint);
        if run.tolerances.atol <= largest {
            return Ok(());
        }
        let moves = if joint.given_clearance >= length(joint) {
            format!(
                "the radial clearance of `{}` ({} m)",
                joint.name,
                terminal(joint.given_clearance)
            )
        } else {
            format!(
                "the penetration of the journal of `{}`, about {PENETRATION_PER_RADIUS:e} x its \
                 bearing radius ({} m), which exceeds its radial clearance of {} m",
                joint.name,
                terminal(length(joint)),
                terminal(joint.given_clearance)
            )
        };
        Err(Error::invalid(
            "run.atol",
            run.tolerances.atol,
            format!(
                "at most {} m, {ATOL_PER_CLEARANCE} of {moves}: the integrator holds the \
                 journal's position to about atol, and a coarser one cannot tell contact from \
                 free flight; likely cause: a tolerance meant for another scale or unit \
                 (MATLAB's ode45 default is 1e-6)",
                terminal(largest),
            ),
        ))
    }

    /// Checks what a run records: its grid resolves the driver's rotation
    /// ([`MIN_RECORD_SAMPLES_PER_ROTATION`]) and its outputs fit the record budget
    /// ([`Scene::check_record_budget`]). A run that records nothing has no grid to check.
    /// `always` says that the caller needs recorded rotations (a sweep, which refuses
    /// `run.record_rotations = 0`; `animate`, which records all): recording none is then no
    /// remedy to offer.
    pub fn check_recording(&self, always: bool) -> Result<()> {
        let run = &self.run;
        let period = self.period();
        let coarsest = period / MIN_RECORD_SAMPLES_PER_ROTATION;
        if run.record_rotations > 0 && run.record_interval > coarsest {
            return Err(Error::invalid(
                "run.record_interval_s",
                format!("{:e} s", run.record_interval),
                format!(
                    "an interval of at most {coarsest:.4e} s, the driver period of {period:.4e} s \
                     over {MIN_RECORD_SAMPLES_PER_ROTATION} (a sample per 10 degrees of driver angle): \
                     a coarser grid misses the contacts, forces and motion the recorded \
                     rotations report ({:.3} samples per rotation); likely cause: an interval \
                     in ms or another unit (seconds), or a driver speed changed without it{}",
                    period / run.record_interval,
                    if always {
                        " (this command needs recorded rotations: recording none is no remedy)"
                    } else {
                        " (or record no rotations, run.record_rotations = 0)"
                    }
                ),
            ));
        }
        self.check_record_budget()
    }

    /// Checks that the time series (`run.record_rotations` of the driver period sampled every
    /// `run.record_interval_s`), the wear history and the wear snapshots fit in
    /// [`RECORD_BUDGET_BYTES`], naming the setting that dominates the estimate if not.
    pub fn check_record_budget(&self) -> Result<()> {
        let (run, m) = (&self.run, &self.mechanism);
        let (period, rows) = (self.period(), self.recorded_samples());
        let columns = record_columns(m);
        let series = rows * columns as f64 * 8.0;
        let points = run.rotations as f64 * run.profile_history_per_rotation as f64;
        let sectors: usize = m
            .clearance_joints
            .iter()
            .map(|c| c.initial_profile.depths().len())
            .sum();
        let history = points * sectors as f64 * 8.0;
        let snapshots = run.wear_snapshots.len() as f64;
        let snapshot_bytes = snapshots * sectors as f64 * 8.0;
        if series + history + snapshot_bytes <= RECORD_BUDGET_BYTES {
            return Ok(());
        }
        let budget = format!("the record budget of {:.0} GiB", RECORD_BUDGET_BYTES / GIB);
        // The setting of the largest part names the error.
        Err(if series >= history.max(snapshot_bytes) {
            Error::invalid(
                "run.record_interval_s",
                format!("{:e} s", run.record_interval),
                format!(
                    "an interval whose recording fits in {budget}: {} recorded rotations of \
                     {period:.4e} s every {:e} s are {rows:.3e} rows x {columns} columns = \
                     {:.3e} GiB; likely cause: an interval in the wrong unit (seconds) or too \
                     many recorded rotations (run.record_rotations)",
                    run.record_rotations,
                    run.record_interval,
                    series / GIB
                ),
            )
        } else if history >= snapshot_bytes {
            Error::invalid(
                "run.profile_history_per_rotation",
                run.profile_history_per_rotation,
                format!(
                    "a wear history that fits in {budget}: {points:.3e} profiles x {sectors} \
                     sectors = {:.3e} GiB; likely cause: a history of every rotation of a long \
                     run (save fewer per rotation, or use run.wear_snapshots)",
                    history / GIB
                ),
            )
        } else {
            Error::invalid(
                "run.wear_snapshots",
                format!("{snapshots} snapshots"),
                format!(
                    "snapshots that fit in {budget}: {snapshots:.3e} profiles x {sectors} \
                     sectors = {:.3e} GiB; likely cause: a snapshot after every rotation of a \
                     long run (snapshot fewer rotations, or fewer wear.sectors)",
                    snapshot_bytes / GIB
                ),
            )
        })
    }
}

pub(super) fn validate_friction(field: &str, friction: &FrictionModel) -> Result<()> {
    match *friction {
        FrictionModel::None => {}
        FrictionModel::Coulomb { mu } => {
            check(&format!("{field}.mu"), mu, 0.0, 2.0)?;
        }
        FrictionModel::Modified {
            mu_s,
            mu_d,
            v_s,
            v_d,
        } => {
            check(&format!("{field}.mu_s"), mu_s, 0.0, 2.0)?;
            check(&format!("{field}.mu_d"), mu_d, 0.0, 2.0)?;
            check_open(&format!("{field}.v_s"), v_s, 0.0, 100.0)?;
            if !(v_d.is_finite() && v_d > v_s && v_d <= 100.0) {
                return Err(Error::invalid(
                    format!("{field}.v_d"),
                    exact(v_d),
                    format!("a finite number in ({}, 100] (above v_s)", terminal(v_s)),
                ));
            }
        }
    }
    Ok(())
}
