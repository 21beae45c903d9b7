//! Scene files: a mechanism, its joints, materials, driver and run settings as TOML data.
//!
//! Scene files use engineering units, spelled in each key (`_mm`, `_deg`, `_rpm`, `_gpa`,
//! `_kg`, `_s`, `_m_s`, `_per_pa`); [`Scene::load`] converts them once to SI and validates
//! every value: a bad scene is an [`Error`] naming the field, the value and the valid range.
//! Unknown keys are rejected. Angles are counter-clockwise from +x; point coordinates are in
//! the body frame, whose origin is the body's centre of mass. The shipped scenes in
//! `data/scenes/` document every key.
//!
//! A scene may extend another: `extends = "standard.toml"` (relative to the file) takes the
//! base scene, replaces its top-level keys by the ones given (e.g. `title`), then applies the
//! `[overrides]` table, whose keys are dotted paths into the base document with array indices
//! as numbers, e.g. `"clearance.0.clearance_mm" = 0.2`. A path that does not exist in the base
//! is an error, so a typo cannot silently leave the base value in place.

use crate::contact::{compound_modulus, ContactLaw, NormalForceModel};
use crate::friction::FrictionModel;
use crate::integrator::{Method, Tolerances};
use crate::mechanism::{
    Body, BodyIndex, BodyPoint, ClearanceJoint, Driver, Mechanism, Revolute, Translational,
};
use crate::simulation::{RunSettings, SteadyState};
use crate::wear::{PressureModel, WearLaw, WearProfile};
use crate::{Error, Result};
use nalgebra::Vector2;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const MM: f64 = 1e-3;
const GPA: f64 = 1e9;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// A scene file as written (engineering units).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free text shown on figures and summaries.
    pub title: String,
    /// Gravitational acceleration (m/s²), e.g. `[0.0, -9.81]`.
    pub gravity_m_s2: [f64; 2],
    /// Named materials used by clearance joints.
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Named points fixed to the ground (mm).
    pub ground: GroundSpec,
    pub bodies: Vec<BodySpec>,
    #[serde(default)]
    pub revolute: Vec<RevoluteSpec>,
    #[serde(default)]
    pub translational: Vec<TranslationalSpec>,
    pub driver: DriverSpec,
    #[serde(default)]
    pub clearance: Vec<ClearanceSpec>,
    pub run: RunSpec,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Young's modulus (GPa), [0.1, 10000] ([`YOUNGS_MODULUS_GPA`]).
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio, [0, 0.5).
    pub poisson_ratio: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    pub points_mm: BTreeMap<String, [f64; 2]>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    /// Mass (kg), [1e-6, 1e6] ([`MASS_KG`]).
    pub mass_kg: f64,
    /// Moment of inertia about the centre of mass (kg m²), [1e-12, 1e6] ([`INERTIA_KG_M2`]).
    pub inertia_kg_m2: f64,
    /// Initial guess of the centre of mass (mm); assembled exactly at load.
    pub position_mm: [f64; 2],
    /// Initial guess of the body angle (deg).
    pub angle_deg: f64,
    /// Named points in the body frame (mm).
    pub points_mm: BTreeMap<String, [f64; 2]>,
}

/// Ideal revolute joint between two points, written `"body.point"` (`"ground.O"`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RevoluteSpec {
    pub a: String,
    pub b: String,
}

/// Ideal translational joint: point `a` slides along the line through point `b` whose
/// direction is `axis_deg` in `b`'s body frame; the bodies keep their relative angle.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TranslationalSpec {
    pub a: String,
    pub b: String,
    pub axis_deg: f64,
}

/// Constant-speed driver of one body's absolute angle.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriverSpec {
    pub body: String,
    /// Speed (r/min), non-zero, |speed| ≤ 100000; positive is counter-clockwise.
    pub speed_rpm: f64,
    /// Angle at t = 0 (deg).
    pub angle_deg: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClearanceSpec {
    pub name: String,
    /// Journal centre, `"body.point"`.
    pub journal: String,
    /// Bearing centre, `"body.point"`; the bearing is the part that wears.
    pub bearing: String,
    /// Unworn bearing radius R_i (mm), [0.1, 10000] ([`BEARING_RADIUS_MM`]).
    pub bearing_radius_mm: f64,
    /// Radial clearance c = R_i − R_j (mm), [0, R_i); at least
    /// [`MIN_HERTZ_CLEARANCE_RATIO`] R_i with a Hertz-based contact or pressure law.
    pub clearance_mm: f64,
    pub journal_material: String,
    pub bearing_material: String,
    pub contact: ContactSpec,
    /// Friction law (velocities in m/s); `{ model = "none" }` computes no friction.
    pub friction: FrictionModel,
    /// Absent: the scene computes no wear.
    pub wear: Option<WearSpec>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    pub model: NormalForceModel,
    /// Coefficient of restitution c_e, (0, 1].
    pub restitution: f64,
    /// Exponent n, [1, 3]; the paper uses 1.5.
    pub exponent: f64,
    /// Floor of the captured impact velocity (m/s), (0, 10].
    pub grazing_velocity_m_s: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearSpec {
    /// Archard coefficient over hardness k/H (1/Pa), [0, 1e-6].
    pub k_over_h_per_pa: f64,
    pub pressure: PressureModel,
    /// Bearing length L (mm), [0.1, 10000] ([`BEARING_LENGTH_MM`]).
    pub length_mm: f64,
    /// Number of sectors of the bearing profile, [8, 36000].
    pub sectors: usize,
}

/// Integration method of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodSpec {
    Dopri5,
    Dop853,
    Rk4,
    Rosenbrock,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Driver rotations to simulate, [1, 1000000].
    pub rotations: u32,
    /// How many of the last rotations to record as time series, [0, rotations].
    pub record_rotations: u32,
    /// Recording grid spacing (s), (0, 1].
    pub record_interval_s: f64,
    /// Rotation counts after which the wear profile is saved, each in [1, rotations].
    #[serde(default)]
    pub wear_snapshots: Vec<u32>,
    pub method: MethodSpec,
    /// Relative tolerance, [1e-13, 1].
    pub rtol: f64,
    /// Absolute tolerance, (0, 1].
    pub atol: f64,
    /// Largest step (s), (0, 1].
    pub max_step_s: f64,
    /// Step of `rk4` (s), required by it, (0, 1].
    pub fixed_step_s: Option<f64>,
    /// Baumgarte stabilisation α = β (1/s), [0, 1e6].
    pub baumgarte_per_s: f64,
    /// Integrate the energy balance (driver, contact and friction work).
    #[serde(default)]
    pub energy_accounting: bool,
    /// Settle to the steady state of `steady_state` before simulating `rotations` more.
    #[serde(default)]
    pub settle: bool,
    /// Required when `settle` is true.
    pub steady_state: Option<SteadyStateSpec>,
    /// Wear profiles saved per rotation for the wear history (0: none), [0, 3600].
    #[serde(default)]
    pub profile_history_per_rotation: u32,
    /// Accepted steps after which the run fails with an error, [1, 1e10].
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
}

fn default_max_steps() -> u64 {
    20_000_000
}

/// Steady state: the journal orbit repeats from one rotation to the next.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteadyStateSpec {
    /// Largest RMS change of the journal orbit between rotations over the clearance, (0, 1].
    pub orbit_tolerance: f64,
    /// Rotations after which settling gives up (chaotic motion), [2, 10000].
    pub max_rotations: u32,
}

/// A validated scene in SI units, ready to simulate.
#[derive(Clone, Debug)]
pub struct Scene {
    pub title: String,
    pub mechanism: Mechanism,
    /// Initial guess of the coordinates, `(x, y, φ)` per body (m, rad).
    pub guess: Vec<f64>,
    pub run: RunSettings,
}

/// Checks that `value` is finite and inside `[lo, hi]`.
fn check(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            value,
            format!("a finite number in [{lo:e}, {hi:e}]"),
        ))
    }
}

/// Checks that `value` is finite, `> lo` and `≤ hi`.
fn check_open(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    if value.is_finite() && value > lo && value <= hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            value,
            format!("a finite number in ({lo:e}, {hi:e}]"),
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

/// Largest |coordinate| of a point or position guess (mm).
pub const COORDINATE_MM: f64 = 1e6;

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

/// A number as a message shows it: scientific for very small or large magnitudes.
fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// Checks that `value` is finite and within `limit`, saying why if not.
fn within(field: &str, value: f64, limit: &Limit) -> Result<f64> {
    if value.is_finite() && value >= limit.lo && value <= limit.hi {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            number(value),
            format!(
                "a finite number in [{:e}, {:e}]: {}",
                limit.lo, limit.hi, limit.why
            ),
        ))
    }
}

/// Checks that every coordinate is finite and within ±[`COORDINATE_MM`].
fn check_coordinates(field: &str, values: &[f64]) -> Result<()> {
    match values
        .iter()
        .find(|v| !(v.is_finite() && v.abs() <= COORDINATE_MM))
    {
        Some(v) => Err(Error::invalid(
            field,
            number(*v),
            format!(
                "finite coordinates within ±{COORDINATE_MM:e} mm (1 km; likely cause: a \
                 coordinate in µm or another unit)"
            ),
        )),
        None => Ok(()),
    }
}

fn check_finite(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(Error::invalid(field, v, "finite numbers")),
        None => Ok(()),
    }
}

/// Memory budget of what a run records (bytes): 2 GiB of `f64`s. A run holds its time series
/// and wear history in memory until it ends, growing them by doubling (briefly twice the
/// size), and writes them as CSV text about three times larger; 2 GiB keeps that within an
/// ordinary workstation, where a larger estimate is almost always an interval in the wrong
/// unit, and fails at validation instead of on a failed allocation deep into the run.
pub const RECORD_BUDGET_BYTES: f64 = 2.0 * GIB;

/// Recorded `f64`s per time-series row: time and driver angle, position and acceleration
/// (x, y, φ) per body, and per clearance joint e_x, e_y, θ, δ, F_n, F_t, v_t, p and dh/dt.
fn record_columns(mechanism: &Mechanism) -> usize {
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

    /// Checks that the run can finish within `run.max_steps` at all: its largest step (the
    /// fixed step of `rk4`) needs at least `rotations` × period / step steps. A smaller step
    /// would crawl into the step limit (1e-300 s took 78 s to fail); it fails here at once.
    pub fn check_step_budget(&self) -> Result<()> {
        let run = &self.run;
        let (field, step) = match run.method {
            Method::Rk4 { step } => ("run.fixed_step_s", step),
            _ => ("run.max_step_s", run.tolerances.max_step),
        };
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

    /// Checks that the time series (`run.record_rotations` of the driver period sampled every
    /// `run.record_interval_s`) and the wear history fit in [`RECORD_BUDGET_BYTES`], naming the
    /// setting that dominates the estimate if not.
    pub fn check_record_budget(&self) -> Result<()> {
        let (run, m) = (&self.run, &self.mechanism);
        let period = self.period();
        let rows = (run.record_rotations as f64 * period / run.record_interval).floor() + 1.0;
        let columns = record_columns(m);
        let series = rows * columns as f64 * 8.0;
        let points = run.rotations as f64 * run.profile_history_per_rotation as f64;
        let sectors: usize = m
            .clearance_joints
            .iter()
            .map(|c| c.profile.depths().len())
            .sum();
        let history = points * sectors as f64 * 8.0;
        if series + history <= RECORD_BUDGET_BYTES {
            return Ok(());
        }
        let budget = format!("the record budget of {:.0} GiB", RECORD_BUDGET_BYTES / GIB);
        Err(if series >= history {
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
        } else {
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
        })
    }
}

impl SceneFile {
    /// Reads a scene file (resolving `extends`) without validating its values, so that it
    /// can be varied before [`SceneFile::build`].
    pub fn read(path: impl AsRef<Path>) -> Result<SceneFile> {
        let path = path.as_ref();
        SceneFile::from_document(SceneFile::read_document(path)?, path)
    }

    /// Parses scene text; `path` is used in error messages and to resolve `extends`.
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
        SceneFile::from_document(toml::Value::Table(parse_table(text, path, 0)?), path)
    }

    /// Validates and converts to SI.
    pub fn build(&self) -> Result<Scene> {
        if let Some(g) =
            (self.gravity_m_s2.iter()).find(|g| !(g.is_finite() && g.abs() <= GRAVITY_M_S2))
        {
            return Err(Error::invalid(
                "gravity_m_s2",
                number(*g),
                format!("finite components within ±{GRAVITY_M_S2:e} m/s² (1000 g)"),
            ));
        }
        if self.bodies.is_empty() {
            return Err(Error::invalid("bodies", "none", "at least one body"));
        }
        let mut bodies = Vec::new();
        let mut guess = Vec::new();
        for (i, b) in self.bodies.iter().enumerate() {
            let f = |k: &str| format!("bodies[{i}].{k}");
            if b.name == "ground" || self.bodies[..i].iter().any(|o| o.name == b.name) {
                return Err(Error::invalid(
                    f("name"),
                    &b.name,
                    "a unique name other than `ground`",
                ));
            }
            bodies.push(Body {
                name: b.name.clone(),
                mass: within(&f("mass_kg"), b.mass_kg, &MASS_KG)?,
                inertia: within(&f("inertia_kg_m2"), b.inertia_kg_m2, &INERTIA_KG_M2)?,
            });
            check_coordinates(&f("position_mm"), &b.position_mm)?;
            check_finite(&f("angle_deg"), &[b.angle_deg])?;
            for (name, p) in &b.points_mm {
                check_coordinates(&f(&format!("points_mm.{name}")), p)?;
            }
            guess.extend([
                b.position_mm[0] * MM,
                b.position_mm[1] * MM,
                b.angle_deg.to_radians(),
            ]);
        }
        let revolutes = self
            .revolute
            .iter()
            .enumerate()
            .map(|(i, r)| {
                Ok(Revolute {
                    a: self.point(&format!("revolute[{i}].a"), &r.a)?,
                    b: self.point(&format!("revolute[{i}].b"), &r.b)?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let translationals = self
            .translational
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let a = self.point(&format!("translational[{i}].a"), &t.a)?;
                let b = self.point(&format!("translational[{i}].b"), &t.b)?;
                let axis = check(
                    &format!("translational[{i}].axis_deg"),
                    t.axis_deg,
                    -360.0,
                    360.0,
                )?
                .to_radians();
                let angle = |p: &BodyPoint| p.body.map_or(0.0, |k| guess[3 * k + 2]);
                Ok(Translational {
                    a,
                    b,
                    normal: Vector2::new(-axis.sin(), axis.cos()),
                    relative_angle: angle(&a) - angle(&b),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let driver_body = self
            .body_index(&self.driver.body)
            .flatten()
            .ok_or_else(|| {
                Error::invalid(
                    "driver.body",
                    &self.driver.body,
                    "the name of a body (not ground)",
                )
            })?;
        let speed = self.driver.speed_rpm;
        if !(speed.is_finite() && speed != 0.0 && speed.abs() <= 1e5) {
            return Err(Error::invalid(
                "driver.speed_rpm",
                speed,
                "a finite non-zero number in [-1e5, 1e5]",
            ));
        }
        let driver = Driver {
            body: driver_body,
            omega: speed * std::f64::consts::TAU / 60.0,
            angle0: check("driver.angle_deg", self.driver.angle_deg, -360.0, 360.0)?.to_radians(),
        };
        guess[3 * driver_body + 2] = driver.angle0;
        let clearance_joints = self
            .clearance
            .iter()
            .enumerate()
            .map(|(i, c)| self.clearance_joint(i, c))
            .collect::<Result<Vec<_>>>()?;
        let run = self.run.build()?;
        let mechanism = Mechanism::new(
            bodies,
            revolutes,
            translationals,
            driver,
            clearance_joints,
            Vector2::new(self.gravity_m_s2[0], self.gravity_m_s2[1]),
            (run.baumgarte, run.baumgarte),
            run.energy_accounting,
        )?;
        let dof = mechanism.coordinates() as i64 - mechanism.constraint_count() as i64;
        if dof < 0 {
            return Err(Error::invalid(
                "joints",
                format!("{dof} degrees of freedom"),
                "a mechanism that is not over-constrained",
            ));
        }
        let scene = Scene {
            title: self.title.clone(),
            mechanism,
            guess,
            run,
        };
        scene.check_record_budget()?;
        scene.check_step_budget()?;
        Ok(scene)
    }

    /// `Some(None)` for the ground, `Some(Some(i))` for body i, `None` if unknown.
    fn body_index(&self, name: &str) -> Option<BodyIndex> {
        if name == "ground" {
            return Some(None);
        }
        self.bodies.iter().position(|b| b.name == name).map(Some)
    }

    /// Resolves `"body.point"` (local coordinates converted to m).
    fn point(&self, field: &str, spec: &str) -> Result<BodyPoint> {
        let bad = || {
            Error::invalid(
                field,
                format!("\"{spec}\""),
                "\"body.point\" naming a body (or ground) and one of its points",
            )
        };
        let (body, point) = spec.split_once('.').ok_or_else(bad)?;
        let index = self.body_index(body).ok_or_else(bad)?;
        let points = match index {
            None => &self.ground.points_mm,
            Some(i) => &self.bodies[i].points_mm,
        };
        let p = points.get(point).ok_or_else(bad)?;
        check_coordinates(field, p)?;
        Ok(BodyPoint {
            body: index,
            local: Vector2::new(p[0] * MM, p[1] * MM),
        })
    }

    fn material(&self, field: &str, name: &str) -> Result<(f64, f64)> {
        let m = self.materials.get(name).ok_or_else(|| {
            Error::invalid(
                field,
                format!("\"{name}\""),
                "the name of a [materials] entry",
            )
        })?;
        let mf = format!("materials.{name}");
        Ok((
            within(
                &format!("{mf}.youngs_modulus_gpa"),
                m.youngs_modulus_gpa,
                &YOUNGS_MODULUS_GPA,
            )? * GPA,
            check(&format!("{mf}.poisson_ratio"), m.poisson_ratio, 0.0, 0.4999)?,
        ))
    }

    fn clearance_joint(&self, i: usize, c: &ClearanceSpec) -> Result<ClearanceJoint> {
        let f = |k: &str| format!("clearance[{i}].{k}");
        let journal = self.point(&f("journal"), &c.journal)?;
        let bearing = self.point(&f("bearing"), &c.bearing)?;
        if journal.body == bearing.body {
            return Err(Error::invalid(
                f("bearing"),
                &c.bearing,
                "a point on another body than the journal's",
            ));
        }
        let r_bearing = within(
            &f("bearing_radius_mm"),
            c.bearing_radius_mm,
            &BEARING_RADIUS_MM,
        )? * MM;
        let clearance = c.clearance_mm * MM;
        if !(clearance.is_finite() && clearance >= 0.0 && clearance < r_bearing) {
            return Err(Error::invalid(
                f("clearance_mm"),
                c.clearance_mm,
                format!(
                    "a finite number in [0, {}) (the journal must fit in the bearing)",
                    c.bearing_radius_mm
                ),
            ));
        }
        let r_journal = r_bearing - clearance;
        let (ej, nj) = self.material(&f("journal_material"), &c.journal_material)?;
        let (eb, nb) = self.material(&f("bearing_material"), &c.bearing_material)?;
        let e_star = compound_modulus(eb, nb, ej, nj);
        let k = &c.contact;
        let contact = ContactLaw::new(
            k.model,
            e_star,
            r_bearing,
            r_journal,
            check(&f("contact.exponent"), k.exponent, 1.0, 3.0)?,
            check_open(&f("contact.restitution"), k.restitution, 0.0, 1.0)?,
            check_open(
                &f("contact.grazing_velocity_m_s"),
                k.grazing_velocity_m_s,
                0.0,
                10.0,
            )?,
        );
        validate_friction(&f("friction"), &c.friction)?;
        let hertz = [
            (
                k.model == NormalForceModel::LankaraniNikravesh,
                "contact.model",
                "model = \"hybrid\" (the paper's law, whose elastic-foundation stiffness \
                 holds down to zero clearance)",
            ),
            (
                c.wear
                    .as_ref()
                    .is_some_and(|w| w.pressure == PressureModel::HertzLine),
                "wear.pressure",
                "pressure = \"elastic-foundation\" (the Winkler overlap model, valid for \
                 conformal contact down to zero clearance)",
            ),
        ];
        // mm over mm: the ratio of the numbers as written (1 µm in 10 mm is exactly 1e-4).
        let ratio = c.clearance_mm / c.bearing_radius_mm;
        if let Some((_, key, instead)) = hertz
            .iter()
            .find(|(hertz, _, _)| *hertz && ratio < MIN_HERTZ_CLEARANCE_RATIO)
        {
            return Err(Error::invalid(
                f("clearance_mm"),
                c.clearance_mm,
                format!(
                    "at least {MIN_HERTZ_CLEARANCE_RATIO:e} x the bearing radius ({} mm) with \
                     the Hertz-based {key}: its contact half-width must stay small against the \
                     radius, and as the clearance goes to zero it is unbounded (zero pressure); \
                     use {instead}",
                    number(MIN_HERTZ_CLEARANCE_RATIO * c.bearing_radius_mm)
                ),
            ));
        }
        let (wear, sectors) = match &c.wear {
            None => (None, 8),
            Some(w) => {
                let sectors = w.sectors;
                if !(8..=36000).contains(&sectors) {
                    return Err(Error::invalid(
                        f("wear.sectors"),
                        sectors,
                        "an integer in [8, 36000]",
                    ));
                }
                let law = WearLaw {
                    k_over_h: check(&f("wear.k_over_h_per_pa"), w.k_over_h_per_pa, 0.0, 1e-6)?,
                    pressure: w.pressure,
                    length: within(&f("wear.length_mm"), w.length_mm, &BEARING_LENGTH_MM)? * MM,
                    e_star,
                    r_bearing,
                    r_journal,
                };
                (Some(law), sectors)
            }
        };
        Ok(ClearanceJoint {
            name: c.name.clone(),
            journal,
            bearing,
            r_journal,
            r_bearing,
            contact,
            friction: c.friction,
            wear,
            profile: WearProfile::new(sectors),
            impact_velocity: 0.0,
        })
    }
}

fn validate_friction(field: &str, friction: &FrictionModel) -> Result<()> {
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
                    v_d,
                    format!("a finite number in ({v_s:e}, 1e2] (above v_s)"),
                ));
            }
        }
    }
    Ok(())
}

impl RunSpec {
    fn build(&self) -> Result<RunSettings> {
        if !(1..=1_000_000).contains(&self.rotations) {
            return Err(Error::invalid(
                "run.rotations",
                self.rotations,
                "an integer in [1, 1000000]",
            ));
        }
        if self.record_rotations > self.rotations {
            return Err(Error::invalid(
                "run.record_rotations",
                self.record_rotations,
                format!("an integer in [0, {}]", self.rotations),
            ));
        }
        if let Some(&s) = self
            .wear_snapshots
            .iter()
            .find(|&&s| s == 0 || s > self.rotations)
        {
            return Err(Error::invalid(
                "run.wear_snapshots",
                s,
                format!("rotation counts in [1, {}]", self.rotations),
            ));
        }
        let tolerances = Tolerances {
            rtol: check("run.rtol", self.rtol, 1e-13, 1.0)?,
            atol: check_open("run.atol", self.atol, 0.0, 1.0)?,
            max_step: check_open("run.max_step_s", self.max_step_s, 0.0, 1.0)?,
            initial_step: 0.0,
        };
        let method = match self.method {
            MethodSpec::Dopri5 => Method::Dopri5,
            MethodSpec::Dop853 => Method::Dop853,
            MethodSpec::Rosenbrock => Method::Rosenbrock,
            MethodSpec::Rk4 => {
                let step = self.fixed_step_s.ok_or_else(|| {
                    Error::invalid(
                        "run.fixed_step_s",
                        "missing",
                        "a step in (0, 1] s for method rk4",
                    )
                })?;
                Method::Rk4 {
                    step: check_open("run.fixed_step_s", step, 0.0, 1.0)?,
                }
            }
        };
        let mut wear_snapshots = self.wear_snapshots.clone();
        wear_snapshots.sort_unstable();
        wear_snapshots.dedup();
        Ok(RunSettings {
            rotations: self.rotations,
            record_rotations: self.record_rotations,
            record_interval: check_open("run.record_interval_s", self.record_interval_s, 0.0, 1.0)?,
            wear_snapshots,
            method,
            tolerances,
            baumgarte: check("run.baumgarte_per_s", self.baumgarte_per_s, 0.0, 1e6)?,
            energy_accounting: self.energy_accounting,
            settle: match (&self.settle, &self.steady_state) {
                (false, _) => None,
                (true, Some(spec)) => Some(spec.build()?),
                (true, None) => {
                    return Err(Error::invalid(
                        "run.steady_state",
                        "missing",
                        "a steady-state criterion when run.settle is true",
                    ))
                }
            },
            profile_history_per_rotation: match self.profile_history_per_rotation {
                h @ 0..=3600 => h,
                h => {
                    return Err(Error::invalid(
                        "run.profile_history_per_rotation",
                        h,
                        "an integer in [0, 3600]",
                    ))
                }
            },
            max_steps: match self.max_steps {
                m @ 1..=10_000_000_000 => m,
                m => {
                    return Err(Error::invalid(
                        "run.max_steps",
                        m,
                        "an integer in [1, 1e10]",
                    ))
                }
            },
        })
    }
}

/// How deep `extends` chains may go (a cycle would otherwise recurse forever).
const MAX_EXTENDS_DEPTH: usize = 8;

fn read_table(path: &Path, depth: usize) -> Result<toml::Table> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_table(&text, path, depth)
}

/// Parses a scene document and resolves its `extends` and `[overrides]`.
fn parse_table(text: &str, path: &Path, depth: usize) -> Result<toml::Table> {
    let parse_error = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let mut table: toml::Table = toml::from_str(text).map_err(|e| parse_error(e.to_string()))?;
    let Some(base) = table.remove("extends") else {
        if table.contains_key("overrides") {
            return Err(parse_error(
                "`overrides` needs `extends = \"base.toml\"`".into(),
            ));
        }
        return Ok(table);
    };
    let base = base
        .as_str()
        .ok_or_else(|| parse_error("`extends` must be a file name".into()))?;
    if depth >= MAX_EXTENDS_DEPTH {
        return Err(parse_error(format!(
            "`extends` chains deeper than {MAX_EXTENDS_DEPTH} (a cycle?)"
        )));
    }
    let base_path = path.parent().unwrap_or(Path::new(".")).join(base);
    // A base that cannot be read is this scene's error: name the scene that refers to it.
    let mut merged = read_table(&base_path, depth + 1).map_err(|e| match e {
        Error::Io { path: p, source } => parse_error(format!(
            "`extends = \"{base}\"`: cannot read {}: {source}",
            p.display()
        )),
        e => e,
    })?;
    let overrides = match table.remove("overrides") {
        Some(toml::Value::Table(o)) => o,
        Some(_) => {
            return Err(parse_error(
                "`overrides` must be a table of dotted keys".into(),
            ))
        }
        None => toml::Table::new(),
    };
    merged.extend(table);
    let mut doc = toml::Value::Table(merged);
    for (key, value) in overrides {
        set_dotted(&mut doc, &key, value).map_err(|e| parse_error(format!("override: {e}")))?;
    }
    match doc {
        toml::Value::Table(t) => Ok(t),
        _ => unreachable!("a scene document is a table"),
    }
}

impl SteadyStateSpec {
    fn build(&self) -> Result<SteadyState> {
        let max_rotations = self.max_rotations;
        if !(2..=10000).contains(&max_rotations) {
            return Err(Error::invalid(
                "run.steady_state.max_rotations",
                max_rotations,
                "an integer in [2, 10000]",
            ));
        }
        Ok(SteadyState {
            tolerance: check_open(
                "run.steady_state.orbit_tolerance",
                self.orbit_tolerance,
                0.0,
                1.0,
            )?,
            max_rotations,
        })
    }
}

/// Path of a shipped scene, `data/scenes/<name>.toml`, relative to the crate root.
pub fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/scenes")
        .join(format!("{name}.toml"))
}

/// Sets the value at a dotted `key` of a scene document: table keys by name, array elements
/// by a 0-based number (`clearance.0.clearance_mm`, `driver.speed_rpm`). Every part but the
/// last must exist; the last may add a key to a table (an unknown key is then rejected when
/// the document is converted by [`SceneFile::from_document`]).
pub fn set_dotted(doc: &mut toml::Value, key: &str, value: toml::Value) -> Result<()> {
    let bad = |at: &str, expected: String| Error::invalid(key, format!("(at `{at}`)"), expected);
    let parts: Vec<&str> = key.split('.').collect();
    let mut node = doc;
    for (i, part) in parts.iter().enumerate() {
        let last = i + 1 == parts.len();
        node = match node {
            toml::Value::Table(table) if last => {
                table.insert(part.to_string(), value);
                return Ok(());
            }
            toml::Value::Table(table) => {
                if !table.contains_key(*part) {
                    let keys: Vec<&str> = table.keys().map(String::as_str).collect();
                    return Err(bad(part, format!("one of the keys {}", keys.join(", "))));
                }
                &mut table[*part]
            }
            toml::Value::Array(items) => {
                let len = items.len();
                let slot = part
                    .parse::<usize>()
                    .ok()
                    .and_then(|k| items.get_mut(k))
                    .ok_or_else(|| bad(part, format!("an array index in [0, {len})")))?;
                if last {
                    *slot = value;
                    return Ok(());
                }
                slot
            }
            _ => return Err(bad(part, "a table or an array before it".into())),
        };
    }
    Err(Error::invalid(key, "empty", "a dotted key"))
}

impl SceneFile {
    /// Reads a scene file as a TOML document (with `extends` resolved), to be varied with
    /// [`set_dotted`].
    pub fn read_document(path: impl AsRef<Path>) -> Result<toml::Value> {
        read_table(path.as_ref(), 0).map(toml::Value::Table)
    }

    /// Converts a (varied) scene document; `path` is only used in error messages.
    pub fn from_document(doc: toml::Value, path: &Path) -> Result<SceneFile> {
        doc.try_into().map_err(|e: toml::de::Error| Error::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }
}
